#!/usr/bin/env bash
# Installs every Debian 12 package that mostar's build, tests and demo need.
# Idempotent: prints nothing and returns at once when everything is already there.
# Must run as root (or with sudo available).
set -euo pipefail

PACKAGES=(
  # toolchain
  build-essential cmake ninja-build pkg-config git clang-format
  # DDS: runtime, generator (brings a JRE), tools; OpenSSL for DDS Security certificates
  libfastrtps-dev libfastcdr-dev fastddsgen fastdds-tools libssl-dev
  # sensors, maths, vision, config
  libopencv-dev libjpeg62-turbo-dev
  # H.264 for the WAN video: libx264 through libavcodec, colour conversion with libswscale
  libavcodec-dev libavutil-dev libswscale-dev libeigen3-dev libserial-dev libdc1394-dev libceres-dev
  # bumper contacts on GPIO lines (the Linux GPIO character device)
  libgpiod-dev
  # service manager readiness and watchdog (sd_notify)
  libsystemd-dev
  libprotobuf-dev protobuf-compiler libcli11-dev
  # client UI
  libglfw3-dev libimgui-dev libgl-dev libgl1-mesa-dri
  # mostar_web: HTTPS and WebSocket (Boost.Beast/Asio, header-only); its tests drive headless
  # Chromium through chromedriver
  libboost-dev chromium chromium-driver
  # a second DDS vendor for the GUID-forging insider of the attack suite (tests/security/forger)
  cyclonedds-dev cyclonedds-tools
  # tests, benchmarks, headless display
  libgtest-dev libgmock-dev libbenchmark-dev xvfb xauth
  # fuzzing (libFuzzer)
  clang libclang-rt-14-dev
  # tools used by the tests (network namespaces, shaping, analysis)
  iproute2 procps openssl bc python3
  # the Internet deployment: NAT routers in the tests, the WireGuard overlay (user-space
  # wireguard-go where the kernel has no WireGuard module)
  nftables wireguard-tools wireguard-go
  # the Debian packages (deploy/package.sh: dpkg-shlibdeps) and their test in a fresh root
  dpkg-dev lintian debootstrap help2man
)

missing=()
for p in "${PACKAGES[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done
[ ${#missing[@]} -eq 0 ] && exit 0

SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
echo "install-deps: installing ${#missing[@]} package(s): ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
echo "install-deps: done"
