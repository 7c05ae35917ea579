#!/usr/bin/env bash
# Installs what is missing, then runs every check CI runs, in this order (the first failure
# stops it):
#   format   clang-format --dry-run -Werror over the tracked C++ sources
#   default  build (warnings are errors) and the whole test suite (CTest); OpenGL tests under a
#            virtual X server (xvfb-run) when no display is present
#   asan     AddressSanitizer + UndefinedBehaviorSanitizer build running the unit tests
#            (ctest -L unit)
#   tsan     ThreadSanitizer build running the concurrency tests (ctest -L concurrency)
#   packages the Debian packages built from the default stage's build (deploy/package.sh),
#            lintian, then installed into a fresh Debian 12 root and tried there
#            (tests/packaging/package_test.sh; needs the network to Debian's mirror)
# A sanitizer finding fails its stage. Each stage prints its wall time.
# Usage: deploy/test.sh [CTEST ARGS...]   (from the repository root, as root or with sudo;
#        CTEST ARGS go to the default stage's ctest, e.g. -R Lms200)
# Environment: STAGES (default "format default asan tsan packages"), BUILD_DIR (default build-ci; the
#              sanitizer builds go to BUILD_DIR-asan and BUILD_DIR-tsan), JOBS (default: cores).
set -euo pipefail
cd "$(dirname "$0")/.."
./deploy/install-deps.sh
STAGES=${STAGES:-format default asan tsan packages}
BUILD_DIR=${BUILD_DIR:-build-ci}
JOBS=${JOBS:-$(nproc)}
# Sanitizer builds: light optimisation and line tables only (they build and link faster).
SANITIZER_FLAGS=(-DCMAKE_BUILD_TYPE=RelWithDebInfo "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O1 -g1"
                 -DMOSTAR_BUILD_BENCHMARKS=OFF)

in_display() {
  if [ -z "${DISPLAY:-}" ]; then
    xvfb-run -a -s "-screen 0 1920x1080x24 -noreset" "$@"
  else
    "$@"
  fi
}

stage() {
  local name=$1 start
  shift
  start=$(date +%s)
  echo "=== test.sh: $name"
  "$@"
  echo "=== test.sh: $name passed in $(($(date +%s) - start)) s"
}

format_stage() {
  local files
  if git rev-parse --is-inside-work-tree >/dev/null 2>&1; then
    files=$(git ls-files '*.cc' '*.h')
  else
    files=$(find common robot_server operator_client tests -name '*.cc' -o -name '*.h')
  fi
  # shellcheck disable=SC2086
  clang-format --dry-run -Werror $files
}

default_stage() {
  # Line tables only (-g1): backtraces keep file and line, and the build is a sixth faster.
  # Installed under /usr like the packages, so that the packages stage reuses this build.
  cmake -S . -B "$BUILD_DIR" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_INSTALL_PREFIX=/usr \
    "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O2 -g1 -DNDEBUG" >/dev/null
  cmake --build "$BUILD_DIR" -j "$JOBS"
  # known_failure: registered tests of a known defect that is not fixed yet (docs/architecture.md)
  in_display ctest --test-dir "$BUILD_DIR" --output-on-failure -j "$JOBS" --timeout 300 \
    -LE known_failure "$@"
}

asan_stage() {
  local dir=$BUILD_DIR-asan
  cmake -S . -B "$dir" -G Ninja -DMOSTAR_SANITIZE=address "${SANITIZER_FLAGS[@]}" >/dev/null
  cmake --build "$dir" -j "$JOBS" --target unit_tests
  # new_delete_type_mismatch=0: Debian's Fast DDS 2.9 deletes an RTPSReader member with the
  # wrong size in its own teardown at exit (inside libfastrtps, not mostar's code).
  ASAN_OPTIONS=detect_leaks=1:abort_on_error=1:strict_string_checks=1:new_delete_type_mismatch=0 \
    UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
    ctest --test-dir "$dir" -L unit --output-on-failure -j "$JOBS" --timeout 300
}

tsan_stage() {
  local dir=$BUILD_DIR-tsan
  cmake -S . -B "$dir" -G Ninja -DMOSTAR_SANITIZE=thread "${SANITIZER_FLAGS[@]}" >/dev/null
  cmake --build "$dir" -j "$JOBS" --target concurrency_tests
  TSAN_OPTIONS="halt_on_error=1:second_deadlock_stack=1:suppressions=$PWD/deploy/tsan.supp" \
    ctest --test-dir "$dir" -L concurrency --output-on-failure -j "$JOBS" --timeout 600
}

packages_stage() {
  BUILD_DIR=$BUILD_DIR ./deploy/package.sh >/dev/null
  tests/packaging/package_test.sh "$BUILD_DIR/packages"
}

for s in $STAGES; do
  case "$s" in
    format) stage format format_stage ;;
    default) stage default default_stage "$@" ;;
    asan) stage asan asan_stage ;;
    tsan) stage tsan tsan_stage ;;
    packages) stage packages packages_stage ;;
    *) echo "test.sh: unknown stage '$s' (format, default, asan, tsan, packages)" >&2; exit 2 ;;
  esac
done
echo "=== test.sh: all stages passed ($STAGES)"
