#!/usr/bin/env bash
# Boot order (the overlay comes up after the robot's service): robot_server starts in its
# namespace while its profile's overlay address (deploy/dds/overlay.xml, the line marked
# mostar:overlay-address) does not exist yet, says what it waits for, and once the address is
# added it is found: an operator-side net_probe reaching that address gets scans and health.
# Before robot_server waited, it logged "running", was never discovered and sent nothing.
# Then the address and its link go for 5 s and come back under the running server (the overlay
# restarted): scans flow again without a restart (the time to the first is printed).
#
# Usage: boot_order_test.sh ROBOT_SERVER NET_PROBE SOURCE_DIR
# Exit 77 (CTest: skipped) when network namespaces cannot be created.
set -euo pipefail
[ $# -eq 3 ] || { echo "usage: boot_order_test.sh ROBOT_SERVER NET_PROBE SOURCE_DIR" >&2; exit 2; }
robot_server=$1; net_probe=$2; src=$3
net="$src/tests/network"
"$net/netns.sh" check || exit 77

prefix="mboot$$"
work=$(mktemp -d /tmp/mostar_boot_XXXXXX)
robot_pid=""
cleanup() {
  [ -z "$robot_pid" ] || { kill "$robot_pid" 2>/dev/null || true; wait "$robot_pid" 2>/dev/null || true; }
  "$net/netns.sh" down "$prefix" || true
  if [ "${KEEP_WORK:-0}" = 1 ]; then echo "work dir kept: $work"; else rm -rf "$work"; fi
}
trap cleanup EXIT
trap "exit 1" INT TERM
"$net/netns.sh" up "$prefix"
robot_ns="${prefix}_robot"; operator_ns="${prefix}_operator"
domain=$((100 + $$ % 100))
# The robot's "overlay" address: on the veth, in the test subnet, added later.
late=10.231.0.11
sed -e "s|<address>10.77.0.2</address> <!-- mostar:overlay-address -->|<address>$late</address>|" \
  -e "s|<address>10.77.0.2</address></udpv4> <!-- mostar:robot-address -->|<address>$late</address></udpv4>|" \
  "$src/deploy/dds/overlay.xml" > "$work/robot.xml"
sed -e "s|<address>10.77.0.2</address> <!-- mostar:overlay-address -->|<address>10.231.0.2</address>|" \
  -e "s|<address>10.77.0.2</address></udpv4> <!-- mostar:robot-address -->|<address>$late</address></udpv4>|" \
  "$src/deploy/dds/overlay.xml" > "$work/operator.xml"
grep -q "$late" "$work/robot.xml" || { echo "FAIL: overlay.xml has no mostar:overlay-address line"; exit 1; }

ip netns exec "$robot_ns" "$robot_server" --domain "$domain" --dds-profile "$work/robot.xml" \
  --config "$src/deploy/config/server_sim.pbtxt" --source test_pattern --insecure \
  > "$work/robot.log" 2>&1 &
robot_pid=$!

failures=0
expect() {  # description, condition
  if eval "$2"; then echo "ok: $1"; else echo "FAIL: $1"; failures=$((failures + 1)); fi
}
# Up to 10 s until the robot's log has a line matching the regex $1.
logged() {
  for _ in $(seq 100); do grep -q "$1" "$work/robot.log" && return 0; sleep 0.1; done
  return 1
}
expect "robot_server says it waits for $late" 'logged "waiting up to .* for address $late"'
sleep 2
expect "robot_server is still waiting (alive)" 'kill -0 "$robot_pid" 2>/dev/null'
ip -n "$robot_ns" addr add "$late/24" dev veth0
expect "robot_server sees the address come up" 'logged "interface addresses are up"'
ip netns exec "$operator_ns" "$net_probe" --domain "$domain" --dds-profile "$work/operator.xml" \
  --insecure --duration-s 10 > "$work/probe.out" 2> "$work/probe.err" || true
cat "$work/probe.out"
field() { sed -n "s/.* $1=\([^ ]*\).*/\1/p" "$work/probe.out"; }
expect "the operator receives scans" '[ "$(field scan)" -ge 5 ]'
expect "the operator receives health" '[ "$(field health)" -ge 2 ]'

# The overlay restarted under the running server (wg-quick down/up: its address goes away and
# comes back): the same participant is found again, without a restart. A probe runs through a
# 5 s removal; the scans it receives after the address is back tell.
ip netns exec "$operator_ns" "$net_probe" --domain "$domain" --dds-profile "$work/operator.xml" \
  --insecure --duration-s 16 --samples "$work/samples.csv" > "$work/probe2.out" 2> "$work/probe2.err" &
probe_pid=$!
sleep 4
# As wg-quick down does: the address goes and the link with it (its routes too).
ip -n "$robot_ns" addr del "$late/24" dev veth0
ip -n "$robot_ns" link set veth0 down
sleep 5
back_ns=$(date +%s%N)
ip -n "$robot_ns" link set veth0 up
ip -n "$robot_ns" addr add "$late/24" dev veth0
wait "$probe_pid" || true
first_back_ns=$(awk -F, -v t="$back_ns" '$1 ~ /scan/ && $2 > t { print $2; exit }' "$work/samples.csv")
scans_back=$(awk -F, -v t="$back_ns" '$1 ~ /scan/ && $2 > t { n++ } END { print n + 0 }' "$work/samples.csv")
expect "scans flow again after the address came back ($scans_back)" '[ "$scans_back" -ge 5 ]'
[ -z "$first_back_ns" ] || echo "measured: first scan $(( (first_back_ns - back_ns) / 1000000 )) ms after the address came back"
expect "robot_server kept running" 'kill -0 "$robot_pid" 2>/dev/null'
expect "robot_server logged the address gone" 'logged "address $late of the profile.s interfaceWhiteList is gone"'
expect "robot_server logged it back" 'logged "the profile.s addresses are back"'
if [ "$failures" -ne 0 ]; then echo "--- robot log"; tail -20 "$work/robot.log"; exit 1; fi
echo "boot_order_test: all checks passed"
