#!/usr/bin/env bash
# Outage recovery over the WAN TCP profile, as a test: one 5 s outage of outage_bench.sh (a
# pilot driving at 0.2 m/s through netem_relay: 100 ms RTT, 1 % loss, 8 Mbit/s; the link is cut
# both ways, then restored) with the bench's own analysis, whose table row is checked here:
# - the robot stops within deadman + ramp + slack (700 ms) of the last command before the cut;
# - it never moves on data buffered during the outage (stale commands are rejected);
# - the pilot drives it again after the link comes back (within 12 s), and video reaches it again.
# A run whose robot never drove before the cut (a known Fast DDS 2.9 start-up hang over TCP,
# docs/networking.md) is repeated once, and says so.
#
# PROFILE=wan_udp.xml runs it over UDP unicast (the path of a VPN) instead of TCP (wan.xml).
# Usage: outage_test.sh ROBOT_SERVER OPERATOR_CLIENT NET_PROBE NETEM_RELAY SOURCE_DIR
# Exit 77 (CTest: skipped) where the bench cannot run (no namespaces, xvfb-run or python3).
set -euo pipefail
[ $# -eq 5 ] || { echo "usage: outage_test.sh ROBOT_SERVER OPERATOR_CLIENT NET_PROBE NETEM_RELAY SOURCE_DIR" >&2; exit 2; }
here=$(cd "$(dirname "$0")" && pwd)
source "$here/lib.sh"
# The pilot alone (PROBE=0): a second TCP client from the same address can starve on Fast DDS
# 2.9 (docs/networking.md, known limits).
PROFILE=${PROFILE:-wan.xml} PROBE=0 OUTAGES=5 POST_S=15 ATTEMPTS=2 VIDEO_HZ=15 VIDEO_QUALITY=60 \
  run_bench "$here/outage_bench.sh" "$@"
row=$(echo "$bench_out" | grep '^| 5 s |' || true)
[ -n "$row" ] || { echo "FAIL: no result row"; exit 1; }
cell() { echo "$row" | awk -F'|' -v i=$(($1 + 2)) '{ gsub(/^ +| +$/, "", $i); print $i }'; }
stop_ms=$(cell 1); moved=$(cell 4); resume_s=$(cell 5); frame_age=$(cell 6)
echo "outage_test: stop ${stop_ms} ms, moved on stale data: ${moved}, driving again after ${resume_s} s, video after: ${frame_age}"
check "the robot stopped within 700 ms of the last command" 'at_most "$stop_ms" 700'
check "the robot never moved on stale data" '[ "$moved" = no ]'
check "the pilot drove again within 12 s of the link coming back" \
  'at_most "$resume_s" 12'
pilot_frames=$(echo "$frame_age" | sed -n 's/.*pilot got \([0-9]*\) frames.*/\1/p')
check "video reached the pilot again after the link came back (>= 10 frames)" \
  '[ "${pilot_frames:-0}" -ge 10 ]'
[ "$failures" -eq 0 ] || exit 1
echo "outage_test: all checks passed"
