#!/usr/bin/env bash
# The discovery-server profile (deploy/dds/discovery_server.xml) end to end: a Fast DDS discovery
# server (`fastdds discovery`) and robot_server in one network namespace, a net_probe observer in
# another, joined by a veth pair; no multicast is used. Shared memory is left out of the
# participants' transports here so that data must cross the veth over UDP, as between two
# computers. Checks that frames, scans and health reach the observer, and that nothing arrives
# when the server is down (discovery really goes through it).
#
# Usage: discovery_server_test.sh ROBOT_SERVER NET_PROBE SOURCE_DIR
# Exit 77 (CTest: skipped) when network namespaces cannot be created or `fastdds` is missing.
set -euo pipefail
[ $# -eq 3 ] || { echo "usage: discovery_server_test.sh ROBOT_SERVER NET_PROBE SOURCE_DIR" >&2; exit 2; }
robot_server=$1; net_probe=$2; src=$3
# shellcheck source=lib.sh
source "$(cd "$(dirname "$0")" && pwd)/lib.sh"
command -v fastdds >/dev/null || { echo "discovery_server_test: fastdds (fastdds-tools) is missing"; exit 77; }
net_setup ds
server_ip=10.231.0.1
sed -e "s/192\.0\.2\.10/$server_ip/g" -e "/<userTransports>/,/<\/userTransports>/{/shm_frames/d}" \
  "$src/deploy/dds/discovery_server.xml" > "$work/ds.xml"
sed -e "s|scene_file: \"\.\./|scene_file: \"$src/deploy/|" "$src/deploy/config/server_sim.pbtxt" \
  > "$work/server.pbtxt"
domain=$((100 + $$ % 100))

probe() {  # label: run the observer for 8 s in the operator namespace, print its summary line
  timeout 60 ip netns exec "${prefix}_operator" "$net_probe" --domain "$domain" \
    --dds-profile "$work/ds.xml" --insecure --id "$1" --duration-s 8 --no-ping 2>"$work/$1.err" \
    | grep '^probe:' || echo "probe: none"
}
field() { echo "$1" | sed -n "s/.* $2=\([^ ]*\).*/\1/p"; }

ip netns exec "${prefix}_robot" "$robot_server" --domain "$domain" --dds-profile "$work/ds.xml" \
  --insecure --config "$work/server.pbtxt" --source test_pattern > "$work/server.log" 2>&1 &
pids+=($!)
# First without the discovery server: clients cannot find each other.
without=$(probe without_server)
ip netns exec "${prefix}_robot" fastdds discovery -i 0 -l "$server_ip" -p 11811 \
  > "$work/discovery.log" 2>&1 &
pids+=($!)
with=$(probe with_server)
echo "without server: $without"
echo "with server:    $with"

check "no frames without the discovery server" '[ "$(field "$without" left)" = 0 ]'
check "left frames through the discovery server" '[ "$(field "$with" left)" -ge 20 ]'
check "right frames through the discovery server" '[ "$(field "$with" right)" -ge 20 ]'
check "scans through the discovery server" '[ "$(field "$with" scan)" -ge 10 ]'
check "health through the discovery server" '[ "$(field "$with" health)" -ge 2 ]'
if [ "$failures" -ne 0 ]; then
  echo "--- server log"; tail -20 "$work/server.log"; echo "--- discovery server"; tail -20 "$work/discovery.log"
  exit 1
fi
echo "discovery_server_test: all checks passed"
