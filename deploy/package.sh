#!/usr/bin/env bash
# Builds mostar's Debian packages from this tree into BUILD_DIR/packages: mostar-common,
# mostar-robot, mostar-operator and mostar-hub (cmake/MostarPackaging.cmake, docs/packages.md).
# Usage: deploy/package.sh   (as root or with sudo: it installs the build dependencies first)
# Environment: BUILD_DIR (default build-pkg; a build directory configured with
#              CMAKE_INSTALL_PREFIX=/usr is reused as it is, e.g. deploy/test.sh's build-ci),
#              JOBS (default: cores).
# Then: apt install ./BUILD_DIR/packages/mostar-robot_*.deb ./BUILD_DIR/packages/mostar-common_*.deb
set -euo pipefail
cd "$(dirname "$0")/.."
./deploy/install-deps.sh
BUILD_DIR=${BUILD_DIR:-build-pkg}
JOBS=${JOBS:-$(nproc)}
if [ -f "$BUILD_DIR/CMakeCache.txt" ]; then
  prefix=$(sed -n 's/^CMAKE_INSTALL_PREFIX:PATH=//p' "$BUILD_DIR/CMakeCache.txt")
  if [ "$prefix" != /usr ]; then
    echo "package.sh: $BUILD_DIR installs into '$prefix'; the packages need /usr" \
      "(configure with -DCMAKE_INSTALL_PREFIX=/usr or use another BUILD_DIR)" >&2
    exit 1
  fi
else
  # Only the programs are built (no tests, no benchmarks): the install does not build `all`.
  cmake -S . -B "$BUILD_DIR" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    -DCMAKE_INSTALL_PREFIX=/usr -DCMAKE_SKIP_INSTALL_ALL_DEPENDENCY=ON \
    -DMOSTAR_BUILD_BENCHMARKS=OFF >/dev/null
fi
cmake --build "$BUILD_DIR" -j "$JOBS" \
  --target robot_server operator_client mostar_web mostar_relay mostar_wg_tcp man_pages
rm -rf "$BUILD_DIR/packages"
log=$BUILD_DIR/cpack.log
if ! (cd "$BUILD_DIR" && cpack -G DEB) >"$log" 2>&1; then
  cat "$log" >&2
  echo "package.sh: cpack failed (log above)" >&2
  exit 1
fi
ls -1 "$BUILD_DIR"/packages/*.deb
