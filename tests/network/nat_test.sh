#!/usr/bin/env bash
# The Internet deployment as a test: one run of nat_bench.sh (robot behind NAT A, pilot and
# observer 1 behind NAT B, observer 2 behind NAT C, 100 ms one-way through the hub, 1 % loss
# on every public link) with a 5 s cut of the robot's uplink, or with what RUNS names (e.g.
# "robot_restart": robot_server restarted mid-session as its service would be), whose result
# row is checked:
# - after a cut, the robot stops within deadman + ramp + slack (700 ms) of the last command
#   before it; the robot never moves on commands from before the link came back;
# - after the link comes back the pilot drives again and the pilot and both observers get
#   video captured after it, each within 10 s (the soak bench measures the p95 and the time
#   to fresh video, which depends on the machine's load);
# - SIGTERM ends every program within 2 s.
# With TRANSPORT=tcp and WG_TCP (mostar_wg_tcp), the same over the TCP fallback with UDP
# blocked at every NAT, and also: a UDP probe was dropped at NAT A, and the hub's WireGuard saw
# every peer at its tunnel server, none across a NAT (ctest: network_nat_tcp_fallback).
# Usage: nat_test.sh ROBOT_SERVER OPERATOR_CLIENT NET_PROBE NETEM_RELAY MOSTAR_RELAY SOURCE_DIR
# Exit 77 (CTest: skipped) where the bench cannot run.
set -euo pipefail
[ $# -eq 6 ] || { echo "usage: nat_test.sh ROBOT_SERVER OPERATOR_CLIENT NET_PROBE NETEM_RELAY MOSTAR_RELAY SOURCE_DIR" >&2; exit 2; }
here=$(cd "$(dirname "$0")" && pwd)
source "$here/lib.sh"
RUNS=${RUNS:-5}
[[ "$RUNS" =~ ^[^[:space:]]+$ ]] || { echo "nat_test: RUNS names one run ('$RUNS')" >&2; exit 2; }
RUNS=$RUNS run_bench "$here/nat_bench.sh" "$@"
line=$(echo "$bench_out" | grep '^RESULT ' || true)
[ -n "$line" ] || { echo "FAIL: no result"; exit 1; }
value() { echo "$line" | tr ' ' '\n' | sed -n "s/^$1=//p"; }
stop_ms=$(value stop_ms); stale=$(value stale); drive_s=$(value drive_s)
back=$(value back); fresh=$(value fresh); exit_s=$(value exit)
case "$RUNS" in
  robot_restart)
    check "the robot_server restart was measured ($stop_ms)" '[ "$stop_ms" = "(restarted)" ]' ;;
  readdress)  # the robot may keep driving through a new address
    check "the robot kept driving or stopped within 700 ms ($stop_ms)" \
      '[ "$stop_ms" = kept_driving ] || at_most "$stop_ms" 700' ;;
  *)
    check "the robot stopped within 700 ms of the last command ($stop_ms ms)" 'at_most "$stop_ms" 700' ;;
esac
check "the robot never moved on stale commands" '[ "$stale" = no ]'
check "the pilot drove again within 10 s of the link coming back or the restarted program starting ($drive_s s)" 'at_most "$drive_s" 10'
IFS=/ read -r v_pilot v_obs1 v_obs2 <<< "$back"
check "video back at the pilot within 10 s ($v_pilot s)" 'at_most "$v_pilot" 10'
check "video back at observer 1, behind the pilot's NAT, within 10 s ($v_obs1 s)" 'at_most "$v_obs1" 10'
check "video back at observer 2, behind its own NAT, within 10 s ($v_obs2 s)" 'at_most "$v_obs2" 10'
echo "nat_test: fresh video (age < 200 ms) after link back, pilot / obs1 / obs2: $fresh s"
check "every program ended within 2 s of SIGTERM ($exit_s)" 'at_most "$exit_s" 2'
if [ "${TRANSPORT:-udp}" = tcp ]; then
  blocked=$(value udp_blocked); outside=$(value endpoints_not_tunnel)
  check "UDP is blocked at NAT A (probe datagrams dropped: $blocked)" '[ "${blocked:-0}" -ge 1 ]'
  check "the hub's WireGuard saw every peer through the tunnel ($outside elsewhere)" \
    '[ "$outside" = 0 ]'
fi
[ "$failures" -eq 0 ] || exit 1
echo "nat_test: all checks passed"
