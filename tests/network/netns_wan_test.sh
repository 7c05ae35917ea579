#!/usr/bin/env bash
# robot_server and a headless operator_client in two network namespaces, over the WAN (TCPv4)
# profile deploy/dds/wan.xml with the robot's address filled in. Checks that stereo frames,
# scans and health reach the operator, and that its commands reach the robot and are accepted.
#
# Usage: netns_wan_test.sh ROBOT_SERVER OPERATOR_CLIENT NETEM_RELAY SOURCE_DIR [--emulated] [--udp]
#   --emulated  the path goes through netem_relay: 100 ms RTT, 1 % loss each way, 8 Mbit/s
#   --udp       deploy/dds/wan_udp.xml (UDP unicast, for VPN links) instead of wan.xml; with
#               --emulated the direct veth is taken down so that nothing bypasses the relay
# Exit 77 (CTest: skipped) when network namespaces cannot be created. Needs xvfb-run.
set -euo pipefail
[ $# -ge 4 ] || { echo "usage: netns_wan_test.sh ROBOT_SERVER OPERATOR_CLIENT NETEM_RELAY SOURCE_DIR [--emulated] [--udp]" >&2; exit 2; }
robot_server=$1; operator_client=$2; netem_relay=$3; src=$4
emulated=0; profile=wan.xml
for option in "${@:5}"; do
  case "$option" in
    --emulated) emulated=1 ;;
    --udp) profile=wan_udp.xml ;;
    *) echo "netns_wan_test: unknown option $option" >&2; exit 2 ;;
  esac
done
# shellcheck source=lib.sh
source "$(cd "$(dirname "$0")" && pwd)/lib.sh"
command -v xvfb-run >/dev/null || { echo "netns_wan_test: xvfb-run is missing"; exit 77; }
net_setup wan
robot_ip=10.231.0.1
duration=10
if [ "$emulated" = 1 ]; then
  robot_ip=10.232.0.1
  duration=16
  # NETEM_ARGS overrides the path model (e.g. "--delay-ms 50" alone).
  # shellcheck disable=SC2086
  "$netem_relay" --netns-a "${prefix}_robot" --netns-b "${prefix}_operator" \
    ${NETEM_ARGS:---delay-ms 50 --jitter-ms 5 --loss 0.01 --rate-kbit 8000} --duration-s 120 > "$work/netem.log" 2>&1 &
  pids+=($!)
  for _ in $(seq 50); do grep -q ready "$work/netem.log" && break; sleep 0.1; done
  grep -q ready "$work/netem.log" || { cat "$work/netem.log"; echo "FAIL: netem_relay"; exit 1; }
fi
sed "s/203\.0\.113\.10/$robot_ip/g" "$src/deploy/dds/$profile" > "$work/wan.xml"
if [ "$profile" = wan_udp.xml ] && [ "$emulated" = 1 ]; then
  # UDP participants announce every interface address: leave only the emulated path.
  ip -n "${prefix}_robot" link set veth0 down; ip -n "${prefix}_operator" link set veth0 down
fi
# The shipped simulator configuration with the test-pattern video at VIDEO_HZ frames/s per eye
# and JPEG quality VIDEO_QUALITY (defaults 30 Hz, q80; the ack-clock fits it to the link).
video_hz=${VIDEO_HZ:-30}; video_quality=${VIDEO_QUALITY:-80}
sed -e "s|frame_rate_hz: [0-9.]*|frame_rate_hz: $video_hz|" -e "s|jpeg_quality: [0-9]*|jpeg_quality: $video_quality|" \
    -e "s|scene_file: \"\.\./|scene_file: \"$src/deploy/|" \
    "$src/deploy/config/server_sim.pbtxt" > "$work/server.pbtxt"
domain=$((100 + $$ % 100))

ip netns exec "${prefix}_robot" "$robot_server" --domain "$domain" --dds-profile "$work/wan.xml" \
  --insecure --config "$work/server.pbtxt" --source test_pattern \
  --trace "$work/server.csv" > "$work/server.log" 2>&1 &
server_pid=$!
pids+=("$server_pid")
sleep 1
set +e
# A bounded run: a client stuck in a blocked DDS write must fail the test, not hang it.
timeout -k 5 $((duration + 40)) ip netns exec "${prefix}_operator" xvfb-run -a "$operator_client" --headless --domain "$domain" \
  --dds-profile "$work/wan.xml" --insecure --id operator --duration "$duration" --drive 0.2,0 \
  --calibration "$src/deploy/config/calibration_sim.pbtxt" \
  --trace "$work/client.csv" > "$work/client.log" 2>&1 &
client_pid=$!
# Stop the robot while the operator is still connected: it must end cleanly and promptly (a
# Fast DDS TCP receive thread outliving its participant used to crash it here).
sleep $((duration - 2))
kill -TERM "$server_pid"
for _ in $(seq 150); do kill -0 "$server_pid" 2>/dev/null || break; sleep 0.1; done
if kill -0 "$server_pid" 2>/dev/null; then server_exit=hung; else wait "$server_pid"; server_exit=$?; fi
wait "$client_pid"
client_exit=$?
set -e

count() { grep -c "^$1," "$2" || true; }
left=$(count left "$work/client.csv"); right=$(count right "$work/client.csv")
scan=$(count scan "$work/client.csv"); health=$(count health "$work/client.csv")
sent=$(count command "$work/client.csv"); accepted=$(count command "$work/server.csv")
# Every command the robot accepted must be one the client sent (same sequence numbers).
unknown=$(comm -13 <(grep '^command,' "$work/client.csv" | cut -d, -f3 | sort -u) \
                   <(grep '^command,' "$work/server.csv" | cut -d, -f3 | sort -u) | wc -l)
echo "netns_wan_test (emulated=$emulated, $profile): left=$left right=$right scan=$scan health=$health" \
  "commands sent=$sent accepted=$accepted unknown=$unknown client_exit=$client_exit server_exit=$server_exit"
check "operator_client exited cleanly" '[ "$client_exit" = 0 ]'
check "robot_server stopped cleanly with the operator connected (exit $server_exit)" '[ "$server_exit" = 0 ]'
check "left frames arrived" '[ "$left" -ge 20 ]'
check "right frames arrived" '[ "$right" -ge 20 ]'
check "scans arrived" '[ "$scan" -ge 10 ]'
check "health arrived" '[ "$health" -ge 3 ]'
check "commands accepted by the robot" '[ "$accepted" -ge 10 ]'
check "accepted commands were sent by this client" '[ "$unknown" = 0 ]'
if [ "$failures" -ne 0 ]; then
  echo "--- client log"; tail -20 "$work/client.log"; echo "--- server log"; tail -20 "$work/server.log"
  [ "$emulated" = 0 ] || { echo "--- netem"; cat "$work/netem.log"; }
  exit 1
fi
echo "netns_wan_test: all checks passed"
