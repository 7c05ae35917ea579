#!/usr/bin/env bash
# The Debian packages as a new user meets them (docs/packages.md): lintian finds no error and
# every program in /usr/bin has its manual page; they install with apt into a fresh Debian 12
# root (debootstrap, minbase) that has nothing else;
# there every program starts (--help), the mostar user, groups and folders exist,
# /etc/mostar/server.pbtxt is a conffile whose --check-config names what a robot still lacks,
# a simulator example copied to /etc/mostar finds its scene and runs, and the PKI and overlay
# scripts work from their /usr/bin names, the role table checked against the PKI they made.
# Usage: package_test.sh PACKAGES_DIR   (as root: debootstrap, chroot, unshare)
# Environment: MOSTAR_DEBOOTSTRAP_CACHE (default /var/cache/mostar-test): the bare root is
#   kept there as a tarball and reused by later runs (a clean machine makes it, about 1 min).
set -euo pipefail
pkgs=$(cd "$1" && pwd)
cache=${MOSTAR_DEBOOTSTRAP_CACHE:-/var/cache/mostar-test}
mirror=${MOSTAR_DEBIAN_MIRROR:-http://deb.debian.org/debian}
fail() { echo "package_test: FAIL: $*" >&2; exit 1; }
step() { echo "package_test: $*"; }

shopt -s nullglob
debs=("$pkgs"/mostar-*.deb)
[ ${#debs[@]} -eq 4 ] || fail "expected 4 packages in $pkgs, found ${#debs[@]}"

step "lintian"
lintian_out=$(lintian --allow-root "${debs[@]}" 2>&1 || true)
if grep -q '^E:' <<<"$lintian_out"; then
  echo "$lintian_out" >&2
  fail "lintian reports errors"
fi

step "a manual page for every program"
if grep -E 'no-manual-page|binary-without-manpage' <<<"$lintian_out"; then
  fail "lintian finds programs without a manual page"
fi
for deb in "${debs[@]}"; do
  contents=$(dpkg-deb -c "$deb" | awk '{ print $6 }')
  for program in $(grep '^\./usr/bin/.' <<<"$contents" | sed 's|.*/||'); do
    grep -qx "./usr/share/man/man1/$program.1.gz" <<<"$contents" ||
      fail "$(basename "$deb") has /usr/bin/$program but no usr/share/man/man1/$program.1.gz"
  done
done

work=$(mktemp -d /tmp/mostar-package-test.XXXXXX)
root=$work/root
cleanup() {
  # unshare's private mounts are gone with its process; nothing stays mounted here.
  rm -rf "$work"
}
trap cleanup EXIT

step "a fresh Debian 12 root"
mkdir -p "$cache"
if [ -f "$cache/bookworm-minbase.tar" ]; then
  mkdir -p "$root"
  tar -C "$root" -xf "$cache/bookworm-minbase.tar"
else
  debootstrap --variant=minbase bookworm "$root" "$mirror" >"$work/debootstrap.log" 2>&1 ||
    { tail -20 "$work/debootstrap.log" >&2; fail "debootstrap"; }
  tar -C "$root" -cf "$cache/bookworm-minbase.tar.new" . && mv "$cache/bookworm-minbase.tar.new" "$cache/bookworm-minbase.tar"
fi
cp /etc/resolv.conf "$root/etc/resolv.conf"
mkdir -p "$root/tmp/debs"
cp "${debs[@]}" "$root/tmp/debs/"

# Runs a shell script in the root with /proc, /dev and /dev/pts of its own mount namespace;
# with ISOLATED=1 also in a network namespace of its own with only loopback up.
in_root() {
  local net=()
  [ "${ISOLATED:-0}" = 1 ] && net=(--net)
  unshare --mount "${net[@]}" --fork sh -c '
    root=$1; shift
    if [ "$isolated" = 1 ]; then ip link set lo up; fi
    mount --rbind /dev "$root/dev" && mount -t proc proc "$root/proc" &&
      exec chroot "$root" /bin/bash -euo pipefail -c "$@"' sh "$root" "$@"
}

step "apt install the packages (dependencies from Debian)"
in_root 'export DEBIAN_FRONTEND=noninteractive
  apt-get update -qq
  # Without recommends: wireguard-tools would bring a kernel into the root. It is installed
  # by name, for mostar-make-overlay.
  apt-get install -y -qq --no-install-recommends /tmp/debs/*.deb wireguard-tools >/tmp/apt.log 2>&1 || { tail -30 /tmp/apt.log; exit 1; }' ||
  fail "the packages do not install"

step "programs, user, folders, conffile"
in_root '
  for p in robot_server operator_client mostar_web mostar_relay mostar_wg_tcp; do
    "$p" --help >/dev/null || { echo "$p --help failed"; exit 1; }
  done
  id -nG mostar | grep -qw video || { echo "mostar is not in the group video"; exit 1; }
  [ "$(stat -c %a:%U:%G /etc/mostar/pki)" = 750:root:mostar ] || { echo "/etc/mostar/pki: $(stat -c %a:%U:%G /etc/mostar/pki)"; exit 1; }
  [ "$(stat -c %U /var/lib/mostar)" = mostar ] || { echo "/var/lib/mostar not owned by mostar"; exit 1; }
  dpkg-query -W -f="\${Conffiles}\n" mostar-robot | grep -q /etc/mostar/server.pbtxt ||
    { echo "/etc/mostar/server.pbtxt is not a conffile"; exit 1; }
  for u in mostar-robot-server mostar-relay mostar-wg-tcp mostar-wg-tcp-hub; do
    [ -f /lib/systemd/system/$u.service ] || { echo "unit $u missing"; exit 1; }
  done
  [ -f /lib/udev/rules.d/60-mostar-lms200.rules ] || { echo "udev rules missing"; exit 1; }' ||
  fail "installed layout"

step "--check-config of the packaged robot configuration names what is missing"
out=$(in_root 'robot_server --check-config --config /etc/mostar/server.pbtxt || echo "status=$?"' 2>&1 || true)
for want in "status=1" "/dev/lms200 does not exist" "60-mostar-lms200.rules" \
  "'CHANGE-ME-pilot' is a placeholder" "/etc/mostar/pki/robot.xml cannot be read"; do
  grep -qF -- "$want" <<<"$out" || { echo "$out" >&2; fail "robot check lacks: $want"; }
done

step "the simulator example copied to /etc/mostar finds its scene, checks clean and runs"
out=$(in_root 'cp /usr/share/mostar/config/server_sim.pbtxt /etc/mostar/sim.pbtxt
  robot_server --check-config --config /etc/mostar/sim.pbtxt' 2>&1) ||
  { echo "$out" >&2; fail "the copied simulator configuration does not check clean"; }
grep -qF "/usr/share/mostar/config/../scenes/corridor.pbtxt loads" <<<"$out" ||
  { echo "$out" >&2; fail "scene not found through the installed examples"; }
# 3 s of the simulated robot, DDS on the loopback of a network namespace of its own.
out=$(ISOLATED=1 isolated=1 in_root 'robot_server --config /etc/mostar/sim.pbtxt --duration 3' 2>&1) ||
  { echo "$out" | tail -20 >&2; fail "robot_server with the copied simulator configuration"; }
grep -q "running" <<<"$out" || { echo "$out" | tail -20 >&2; fail "robot_server never said it runs"; }

step "PKI and overlay scripts from /usr/bin, the role table against the PKI"
out=$(in_root 'mostar-make-pki /tmp/pki --robot robot --pilot alice --relay hub >/dev/null
  mostar-make-overlay /tmp/overlay --hub-endpoint hub.example.org:51820 --peer robot --peer alice >/dev/null
  [ -f /tmp/overlay/robot.conf ] && [ -f /tmp/pki/hosts/robot/roles ] || { echo "scripts made no files"; exit 1; }
  tool=$(sed -n "s/^PreDown = \([^ ]*\) save .*/\1/p" /tmp/overlay/mostar-hub.conf)
  [ "$tool" = /usr/share/mostar/wan/hub_endpoints.sh ] && [ -x "$tool" ] && mostar-hub-endpoints --help >/dev/null ||
    { echo "the hub config calls ${tool:-no} endpoint keeper"; exit 1; }
  robot_server --check-config --config /etc/mostar/sim.pbtxt --dds-profile /tmp/pki/hosts/robot/robot.xml || echo "status=$?"' 2>&1) ||
  { echo "$out" >&2; fail "scripts"; }
for want in "status=1" "'alice' holds a pilot certificate" "'operator' has no certificate"; do
  grep -qF -- "$want" <<<"$out" || { echo "$out" >&2; fail "role check lacks: $want"; }
done

step "relay and console checks"
in_root 'mostar_relay --check-config >/dev/null &&
  operator_client --check-config --headless --config /usr/share/mostar/config/client_sim.pbtxt >/dev/null' ||
  fail "mostar_relay or operator_client --check-config on the shipped examples"
echo "package_test: all checks passed"
