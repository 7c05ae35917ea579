#!/usr/bin/env bash
# Installs what is missing, builds everything and runs the whole test suite (CTest).
# OpenGL tests run under a virtual X server (xvfb-run) when no display is present.
# Usage: deploy/test.sh            (from the repository root, as root or with sudo)
# Environment: BUILD_DIR (default build-ci), JOBS (default: number of cores),
#              MOSTAR_SANITIZE (''|address|thread) for a sanitizer build.
set -euo pipefail
cd "$(dirname "$0")/.."
./deploy/install-deps.sh
BUILD_DIR=${BUILD_DIR:-build-ci}
JOBS=${JOBS:-$(nproc)}
cmake -S . -B "$BUILD_DIR" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DMOSTAR_SANITIZE="${MOSTAR_SANITIZE:-}" >/dev/null
cmake --build "$BUILD_DIR" -j "$JOBS"
CTEST=(ctest --test-dir "$BUILD_DIR" --output-on-failure -j "$JOBS" --timeout 300 "$@")
if [ -z "${DISPLAY:-}" ]; then
  xvfb-run -a -s "-screen 0 1920x1080x24 -noreset" "${CTEST[@]}"
else
  "${CTEST[@]}"
fi
