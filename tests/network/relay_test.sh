#!/usr/bin/env bash
# mostar_relay delivers the robot's streams to several observers on another DDS domain, and
# nothing reaches the robot through it but an observer's e-stop engagement: observer 1 engages
# the e-stop 3 s in, and tries to release it 1 s later. Loopback profile: no namespaces needed.
#
# Usage: relay_test.sh ROBOT_SERVER MOSTAR_RELAY NET_PROBE SOURCE_DIR
set -euo pipefail
[ $# -eq 4 ] || { echo "usage: relay_test.sh ROBOT_SERVER MOSTAR_RELAY NET_PROBE SOURCE_DIR" >&2; exit 2; }
robot_server=$1; relay=$2; net_probe=$3; src=$4
work=$(mktemp -d /tmp/mostar_relay_XXXXXX)
pids=()
cleanup() {
  for p in "${pids[@]}"; do kill "$p" 2>/dev/null || true; done
  sleep 1
  # Anything still running from this test (grandchildren under xvfb-run or ip netns exec
  # included) would keep CTest waiting on its output: kill it by its work directory.
  pkill -9 -f "$work" 2>/dev/null || true
  for p in "${pids[@]}"; do kill -9 "$p" 2>/dev/null || true; wait "$p" 2>/dev/null || true; done
  if [ "${KEEP_WORK:-0}" = 1 ]; then echo "work dir kept: $work"; else rm -rf "$work"; fi
}
trap cleanup EXIT
trap "exit 1" INT TERM
robot_domain=$((10 + $$ % 45 * 2)); observer_domain=$((robot_domain + 1))  # [10, 99]: loopback

"$robot_server" --domain "$robot_domain" --config "$src/deploy/config/server_sim.pbtxt" \
  --source test_pattern --trace "$work/server.csv" > "$work/server.log" 2>&1 &
pids+=($!)
"$relay" --robot-domain "$robot_domain" --observer-domain "$observer_domain" --duration 14 \
  > "$work/relay.out" 2> "$work/relay.err" &
relay_pid=$!
sleep 1
probes=()
for i in 1 2 3; do
  estop=(); [ "$i" != 1 ] || estop=(--estop-at 3)
  "$net_probe" --domain "$observer_domain" --id "observer$i" --duration-s 8 "${estop[@]}" \
    > "$work/probe$i.out" 2>&1 &
  probes+=($!)
done
for p in "${probes[@]}"; do wait "$p"; done
wait "$relay_pid" || { cat "$work/relay.err"; echo "FAIL: mostar_relay exited with an error"; exit 1; }

failures=0
field() { sed -n "s/.* $2=\([^ ]*\).*/\1/p" "$work/$1.out"; }
for i in 1 2 3; do
  line=$(grep '^probe:' "$work/probe$i.out" || true)
  echo "observer$i: $line"
  left=$(field "probe$i" left); scan=$(field "probe$i" scan); health=$(field "probe$i" health)
  pongs=$(field "probe$i" pongs)
  if [ "${left:-0}" -ge 30 ] && [ "${scan:-0}" -ge 10 ] && [ "${health:-0}" -ge 3 ]; then
    echo "ok: observer$i receives video, scans and health through the relay"
  else
    echo "FAIL: observer$i"; failures=$((failures + 1))
  fi
  # Clock pings are not forwarded: the robot never answers an observer behind the relay.
  if [ "${pongs:-1}" = 0 ]; then echo "ok: observer$i reaches nothing on the robot side"; else
    echo "FAIL: observer$i got $pongs pongs through the relay"; failures=$((failures + 1)); fi
done
cat "$work/relay.out"
check() { if eval "$2"; then echo "ok: $1"; else echo "FAIL: $1"; failures=$((failures + 1)); fi; }
check "observer 1's e-stop reached the robot through the relay (its health says engaged after $(field probe1 estop_seen_after_s) s)" \
  '[ "$(field probe1 estop_seen_after_s)" != no ] && [ "$(field probe1 robot_estop)" = engaged ]'
check "the robot took it from the relay's id" 'grep -q "emergency stop engage from relay" "$work/server.log"'
check "observer 1's release was not forwarded: the e-stop stays engaged for every observer" \
  '[ "$(field probe1 releases_sent)" -ge 1 ] && grep -q "releases_refused=[1-9]" "$work/relay.out" &&
   [ "$(field probe2 robot_estop)" = engaged ] && [ "$(field probe3 robot_estop)" = engaged ] &&
   ! grep -q "emergency stop release" "$work/server.log"'
[ "$failures" -eq 0 ] || exit 1
echo "relay_test: all checks passed"
