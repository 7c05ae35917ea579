#!/usr/bin/env bash
# One observer that stops reading must not stop the others (WAN TCP profile). robot_server in
# the robot namespace; observers A and B (net_probe) in the operator namespace dial it over
# deploy/dds/wan.xml. B is frozen (SIGSTOP: its connection stays open, its window closes) for
# FREEZE_S seconds, then resumed. Fast DDS 2.9 sends over TCP with a blocking write, so before
# the robot bounded that with TCP_USER_TIMEOUT and reclaimed video lanes B never acknowledged,
# A received nothing at all for the whole freeze.
#
# Checks: A's scans never pause for longer than the robot's TCP user timeout plus slack; A
# receives video again while B is still frozen; B receives again after it is resumed; the
# robot stops cleanly.
#
# --stall-exit: the last resort instead. The robot runs without the TCP user timeout and with
# dds.write_stall_exit_s 3, so B's freeze blocks its DDS writes for good: it must exit with
# status 3 (after stopping the motors, for the service manager to restart it) during the freeze
# and say why.
#
# Usage: stuck_observer_test.sh ROBOT_SERVER NET_PROBE SOURCE_DIR [--stall-exit]
# Exit 77 (CTest: skipped) when network namespaces cannot be created.
set -euo pipefail
[ $# -eq 3 ] || [ $# -eq 4 ] || { echo "usage: stuck_observer_test.sh ROBOT_SERVER NET_PROBE SOURCE_DIR [--stall-exit]" >&2; exit 2; }
robot_server=$1; net_probe=$2; src=$3; stall_exit=0
case "${4:-}" in
  "") ;;
  --stall-exit) stall_exit=1 ;;
  *) echo "stuck_observer_test: unknown option $4" >&2; exit 2 ;;
esac
# shellcheck source=lib.sh
source "$(cd "$(dirname "$0")" && pwd)/lib.sh"
net_setup stuck
# --stall-exit waits up to 30 s: the write blocks only once the frozen peer's receive buffer and
# the robot's send buffer are full (several MB); the robot exits as soon as it happens.
default_freeze_s=12
[ "$stall_exit" = 0 ] || default_freeze_s=30
freeze_after_s=5; freeze_s=${FREEZE_S:-$default_freeze_s}; run_s=$((freeze_after_s + freeze_s + 9))
robot_ip=10.231.0.1
sed "s/203\.0\.113\.10/$robot_ip/g" "$src/deploy/dds/wan.xml" > "$work/wan.xml"
sed -e "s|scene_file: \"\.\./|scene_file: \"$src/deploy/|" "$src/deploy/config/server_sim.pbtxt" \
  > "$work/server.pbtxt"
# With --stall-exit the video lanes left to B are written again after 100 ms instead of 2 s,
# so video keeps flowing into B's connection at about the full rate and fills the buffers in
# seconds (at the default, 4 pairs per 2 s took from 10 s to more than 30 s to fill them).
[ "$stall_exit" = 0 ] ||
  echo "dds { tcp_user_timeout_ms: 0 write_stall_exit_s: 3 video_lane_timeout_ms: 100 }" >> "$work/server.pbtxt"
user_timeout_ms=$(sed -n 's/.*tcp_user_timeout_ms: *\([0-9]*\).*/\1/p' "$work/server.pbtxt")
user_timeout_ms=${user_timeout_ms:-4000}  # the default of server_config.proto
domain=$((100 + $$ % 100))

ip netns exec "${prefix}_robot" "$robot_server" --domain "$domain" --dds-profile "$work/wan.xml" \
  --insecure --config "$work/server.pbtxt" --source test_pattern > "$work/server.log" 2>&1 &
server_pid=$!; pids+=("$server_pid")
sleep 1
# The probes' duration leaves room for the wait for video below; they are stopped (SIGTERM: they
# print their counters) 9 s after B is resumed.
declare -A probe
start_probe() {
  timeout $((run_s + 90)) ip netns exec "${prefix}_operator" "$net_probe" --domain "$domain" \
    --dds-profile "$work/wan.xml" --insecure --id "observer_${1}_$$" --duration-s $((run_s + 60)) \
    --no-ping --samples "$work/$1.csv" > "$work/$1.out" 2>&1 &
  probe[$1]=$!; pids+=($!)
}
start_probe a
start_probe b
sleep "$freeze_after_s"
# Freeze B only once both observers receive video (net_probe writes its samples file in blocks,
# so a line shows up within about a second). A B frozen before its video readers matched is never
# sent the video that would fill its connection. In about one run in four, one observer's
# connection never delivers anything: Fast DDS 2.9's TCP start-up defect (docs/networking.md,
# known limits; network_wan_tcp* are its registered known failures). That observer is restarted,
# as an operator would reconnect, at most twice; the defect is not what this test checks.
for who in a b; do
  for attempt in 1 2 3; do
    for _ in $(seq 150); do grep -q '^left,' "$work/$who.csv" 2>/dev/null && break; sleep 0.1; done
    grep -q '^left,' "$work/$who.csv" 2>/dev/null && break
    echo "stuck_observer_test: observer $who received no video within 15 s (attempt $attempt," \
      "Fast DDS 2.9 TCP start-up defect)"
    [ "$attempt" -lt 3 ] || { echo "FAIL: observer $who received no video in 3 attempts"; exit 1; }
    kill -TERM "${probe[$who]}" 2>/dev/null || true
    wait "${probe[$who]}" 2>/dev/null || true
    start_probe "$who"
  done
done
probe_a=${probe[a]}; probe_b=${probe[b]}
echo "stuck_observer_test: both observers receive video; freezing B"
pkill -STOP -f -- "--id observer_b_$$" || true
frozen_ns=$(date +%s%N)
if [ "$stall_exit" = 1 ]; then
  for _ in $(seq $((freeze_s * 10))); do kill -0 "$server_pid" 2>/dev/null || break; sleep 0.1; done
  set +e
  if kill -0 "$server_pid" 2>/dev/null; then server_exit=running; else wait "$server_pid"; server_exit=$?; fi
  set -e
  stall_s=$(python3 -c "print(round(($(date +%s%N) - $frozen_ns) / 1e9, 1))")
  echo "stuck_observer_test --stall-exit: robot exit status $server_exit, ${stall_s} s after the freeze"
  check "the robot exited with status 3 during the freeze" '[ "$server_exit" = 3 ]'
  check "it said why" 'grep -q "DDS write has been blocked" "$work/server.log"'
  pkill -CONT -f -- "--id observer_b_$$" || true
  if [ "$failures" -ne 0 ]; then
    echo "left frames received: A $(grep -c '^left,' "$work/a.csv"), B $(grep -c '^left,' "$work/b.csv") (B's file as of its freeze, up to one block short)"
    echo "--- server log"; tail -20 "$work/server.log"; exit 1
  fi
  echo "stuck_observer_test --stall-exit: all checks passed"
  exit 0
fi
sleep "$freeze_s"
resumed_ns=$(date +%s%N)
pkill -CONT -f -- "--id observer_b_$$" || true
sleep 9
set +e
kill -TERM "$probe_a" "$probe_b" 2>/dev/null
wait "$probe_a"; wait "$probe_b"
kill -TERM "$server_pid"
for _ in $(seq 150); do kill -0 "$server_pid" 2>/dev/null || break; sleep 0.1; done
if kill -0 "$server_pid" 2>/dev/null; then server_exit=hung; else wait "$server_pid"; server_exit=$?; fi
set -e

# Samples: topic,receive_ns,stamp_ns. Prints: longest gap between A's scans from the freeze on
# (s), A's left frames in the second half of the freeze, B's left frames from 4 s after resuming.
read -r scan_gap_s a_late b_after < <(python3 - "$work" "$frozen_ns" "$resumed_ns" <<'PY'
import sys
work, frozen, resumed = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
def samples(who, topic):
    out = []
    for line in open(f"{work}/{who}.csv"):
        parts = line.strip().split(",")
        if len(parts) == 3 and parts[0] == topic:
            out.append(int(parts[1]))
    return sorted(out)
scans = [t for t in samples("a", "scan") if t >= frozen - 1_000_000_000]
edges = [frozen] + scans + [resumed]
gap = max(b - a for a, b in zip(edges, edges[1:]) if a >= frozen or b >= frozen) / 1e9
middle = frozen + (resumed - frozen) // 2
a_late = sum(1 for t in samples("a", "left") if middle <= t < resumed)
b_after = sum(1 for t in samples("b", "left") if t >= resumed + 4_000_000_000)
print(f"{gap:.2f} {a_late} {b_after}")
PY
)
echo "stuck_observer_test: freeze ${freeze_s} s, tcp_user_timeout ${user_timeout_ms} ms:" \
  "A's longest scan gap ${scan_gap_s} s, A's left frames in the freeze's second half ${a_late}," \
  "B's left frames from 4 s after resuming ${b_after}, robot exit ${server_exit}"
grep '^probe:' "$work/a.out" | sed 's/^/A /' || true
grep '^probe:' "$work/b.out" | sed 's/^/B /' || true
limit_s=$(python3 -c "print($user_timeout_ms / 1000 + 3)")
check "A's scans pause at most the TCP user timeout + 3 s ($limit_s s)" \
  "python3 -c 'import sys; sys.exit(0 if $scan_gap_s <= $limit_s else 1)'"
check "A receives video while B is still frozen (>= 10 left frames)" '[ "$a_late" -ge 10 ]'
check "B receives video again after it is resumed (>= 10 left frames)" '[ "$b_after" -ge 10 ]'
check "robot_server stopped cleanly (exit $server_exit)" '[ "$server_exit" = 0 ]'
if [ "$failures" -ne 0 ]; then
  echo "--- server log"; tail -20 "$work/server.log"; exit 1
fi
echo "stuck_observer_test: all checks passed"
