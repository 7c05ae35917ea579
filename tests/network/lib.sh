# Shared pieces of the network tests (source it; needs `set -euo pipefail` in the caller):
#   net_setup NAME     work dir /tmp/mostar_NAME_XXXXXX in $work, namespaces "${prefix}_robot" and
#                      "${prefix}_operator" (netns.sh), cleanup on exit; exits 77 (CTest: skipped)
#                      when namespaces cannot be created here
#   pids+=(PID)        processes that cleanup stops
#   check TEXT EXPR    prints ok/FAIL for a shell condition and counts failures in $failures
#   at_most VALUE MAX  true when VALUE is a number no greater than MAX
#   run_bench CMD...   runs a bench whose result a test checks: prints its output and keeps it in
#                      $bench_out; exits 77 when the bench was skipped, 1 when it failed
# KEEP_WORK=1 keeps the work directory.
net_here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
pids=()
failures=0

net_cleanup() {
  for p in "${pids[@]}"; do kill "$p" 2>/dev/null || true; done
  sleep 1
  # Anything still running from this test (grandchildren under ip netns exec included) would keep
  # CTest waiting on its output: kill it by its work directory.
  pkill -9 -f "$work" 2>/dev/null || true
  for p in "${pids[@]}"; do kill -9 "$p" 2>/dev/null || true; wait "$p" 2>/dev/null || true; done
  "$net_here/netns.sh" down "$prefix" || true
  if [ "${KEEP_WORK:-0}" = 1 ]; then echo "work dir kept: $work"; else rm -rf "$work"; fi
}

net_setup() {
  "$net_here/netns.sh" check || exit 77
  prefix="m${1:0:4}$$"
  work=$(mktemp -d "/tmp/mostar_$1_XXXXXX")
  trap net_cleanup EXIT
  trap "exit 1" INT TERM
  "$net_here/netns.sh" up "$prefix"
}

check() {
  if eval "$2"; then echo "ok: $1"; else echo "FAIL: $1"; failures=$((failures + 1)); fi
}

at_most() {
  [[ "$1" =~ ^[0-9]+(\.[0-9]+)?$ ]] && python3 -c "import sys; sys.exit(0 if $1 <= $2 else 1)"
}

run_bench() {
  local status
  set +e
  bench_out=$("$@" 2>&1)
  status=$?
  set -e
  echo "$bench_out"
  [ "$status" -ne 77 ] || exit 77
  [ "$status" -eq 0 ] || { echo "FAIL: $(basename "$1") exited with status $status"; exit 1; }
}
