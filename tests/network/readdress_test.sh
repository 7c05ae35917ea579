#!/usr/bin/env bash
# A new address under a running robot_server on a profile that announces the host's addresses
# (as lan.xml: no interfaceWhiteList): its address is renewed to another one (a DHCP lease, a
# network moved) while an operator-side net_probe sends clock pings. Fast DDS 2.9.1 keeps
# announcing the old address for its readers, so without help the pings never reach the robot
# again; robot_server sees its announced address gone and a new one present for 1 s, ends in
# order and restarts in place (same process id), and the pings are answered again. The time
# from the new address to the first answer is printed (no limit asserted: a bench measures).
#
# Usage: readdress_test.sh ROBOT_SERVER NET_PROBE SOURCE_DIR
# Exit 77 (CTest: skipped) when network namespaces cannot be created.
set -euo pipefail
[ $# -eq 3 ] || { echo "usage: readdress_test.sh ROBOT_SERVER NET_PROBE SOURCE_DIR" >&2; exit 2; }
robot_server=$1; net_probe=$2; src=$3
# shellcheck source=lib.sh
source "$src/tests/network/lib.sh"
net_setup readdress
robot_ns="${prefix}_robot"; operator_ns="${prefix}_operator"
domain=$((100 + $$ % 100))
old=10.231.0.1 new=10.231.0.12 operator=10.231.0.2

# lan.xml's UDP transport without shared memory (both namespaces share this host's /dev/shm,
# which two computers on a LAN do not), and unicast discovery through the veth (multicast stays
# inside each namespace here): each side names the other's first address as an initial peer.
profile() {  # name, initial peer
  cat <<XML
<?xml version="1.0" encoding="UTF-8"?>
<dds xmlns="http://www.eprosima.com/XMLSchemas/fastRTPS_Profiles"><profiles>
  <transport_descriptors><transport_descriptor>
    <transport_id>udp_lan</transport_id><type>UDPv4</type>
  </transport_descriptor></transport_descriptors>
  <participant profile_name="$1"><rtps>
    <useBuiltinTransports>false</useBuiltinTransports>
    <userTransports><transport_id>udp_lan</transport_id></userTransports>
    <builtin>
      <discovery_config>
        <leaseDuration><sec>10</sec></leaseDuration>
        <leaseAnnouncement><sec>1</sec></leaseAnnouncement>
      </discovery_config>
      <initialPeersList><locator><udpv4><address>$2</address></udpv4></locator></initialPeersList>
    </builtin>
  </rtps></participant>
</profiles></dds>
XML
}
profile robot "$operator" > "$work/robot.xml"
profile operator "$old" > "$work/operator.xml"

ip netns exec "$robot_ns" "$robot_server" --domain "$domain" --dds-profile "$work/robot.xml" \
  --config "$src/deploy/config/server_sim.pbtxt" --source test_pattern --insecure \
  > "$work/robot.log" 2>&1 &
robot_pid=$!; pids+=("$robot_pid")
ip netns exec "$operator_ns" "$net_probe" --domain "$domain" --dds-profile "$work/operator.xml" \
  --insecure --duration-s 18 --samples "$work/samples.csv" > "$work/probe.out" 2> "$work/probe.err" &
probe_pid=$!; pids+=("$probe_pid")

pongs_between() {  # from_ns, to_ns
  awk -F, -v a="$1" -v b="$2" '$1 == "pong" && $2 > a && $2 <= b { n++ } END { print n + 0 }' \
    "$work/samples.csv"
}
sleep 6
renewed_ns=$(date +%s%N)
check "pings are answered before the new address ($(pongs_between 0 "$renewed_ns"))" \
  '[ "$(pongs_between 0 "$renewed_ns")" -ge 5 ]'
# The lease renewed to another address: the old one goes, the new one comes, the link stays up.
ip -n "$robot_ns" addr del "$old/24" dev veth0
ip -n "$robot_ns" addr add "$new/24" dev veth0
wait "$probe_pid" || true
cat "$work/probe.out"
# Answers to pings sent before the change may still arrive just after it: the restarted
# server's first answer is the first after the pause (over 500 ms without one) that follows.
first_ns=$(awk -F, -v t="$renewed_ns" '$1 != "pong" { next }
  $2 > t && prev != "" && $2 - prev > 500000000 { print $2; exit } { prev = $2 }' "$work/samples.csv")
after=$(pongs_between "${first_ns:-99999999999999999999}" 99999999999999999999)
[ -z "$first_ns" ] || after=$((after + 1))
check "pings are answered again on the new address ($after)" '[ "$after" -ge 5 ]'
[ -z "$first_ns" ] || echo "measured: first answer $(( (first_ns - renewed_ns) / 1000000 )) ms after the new address"
check "robot_server said why it restarts" 'grep -q "this host.s addresses changed (announced .*$old" "$work/robot.log"'
check "robot_server restarted in place" 'grep -q "restarting in place" "$work/robot.log"'
check "the same process runs again" 'kill -0 "$robot_pid" 2>/dev/null && [ "$(grep -c "running on DDS domain" "$work/robot.log")" -eq 2 ]'
if [ "$failures" -ne 0 ]; then echo "--- robot log"; tail -30 "$work/robot.log"; exit 1; fi
echo "readdress_test: all checks passed"
