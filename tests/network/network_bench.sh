#!/usr/bin/env bash
# Network bench: robot_server (test pattern) and one net_probe observer, printing a Markdown
# table: stereo pairs/s delivered, left-frame age p50/p95, scan rate and age, and the operator ->
# robot one-way latency of the reliable control path (clock pings, the path commands take).
# Steady state: each row measures SECONDS after a WARMUP (discovery and start-up) that starts
# with the first sample. Both programs run on this machine, so ages use one clock.
#
# Usage: network_bench.sh ROBOT_SERVER NET_PROBE NETEM_RELAY SOURCE_DIR
# Rows: loopback profile; WAN TCP profile over a plain veth; WAN TCP profile over netem_relay
# (100 ms RTT, 1 % loss each way, 8 Mbit/s) with BBR and with CUBIC congestion control, and
# with the initial peer written without its WAN address (the form that makes Fast DDS 2.9 send
# every message many times); and the UDP unicast profile wan_udp.xml over the same path. Needs
# root.
set -euo pipefail
[ $# -eq 4 ] || { echo "usage: network_bench.sh ROBOT_SERVER NET_PROBE NETEM_RELAY SOURCE_DIR" >&2; exit 2; }
robot_server=$1; net_probe=$2; netem_relay=$3; src=$4
here=$(cd "$(dirname "$0")" && pwd)
"$here/netns.sh" check || exit 77
prefix="mbench$$"; work=$(mktemp -d /tmp/mostar_bench_XXXXXX); pids=()
stop_all() { for p in "${pids[@]}"; do kill "$p" 2>/dev/null || true; done
             for p in "${pids[@]}"; do wait "$p" 2>/dev/null || true; done; pids=(); }
cleanup() { stop_all; "$here/netns.sh" down "$prefix" || true; rm -rf "$work"; }
trap cleanup EXIT
trap "exit 1" INT TERM
"$here/netns.sh" up "$prefix"
seconds=${SECONDS_PER_ROW:-12}; warmup=${WARMUP_S:-3}

config() {  # hz quality -> path
  sed -e "s|frame_rate_hz: [0-9.]*|frame_rate_hz: $1|" -e "s|jpeg_quality: [0-9]*|jpeg_quality: $2|" \
      -e "s|scene_file: \"\.\./|scene_file: \"$src/deploy/|" \
      "$src/deploy/config/server_sim.pbtxt" > "$work/server_$1_$2.pbtxt"
  echo "$work/server_$1_$2.pbtxt"
}
congestion() {  # algorithm: TCP congestion control inside both namespaces
  for ns in "${prefix}_robot" "${prefix}_operator"; do
    ip netns exec "$ns" sysctl -qw net.ipv4.tcp_congestion_control="$1" 2>/dev/null || return 1
  done
}
row() {  # label, robot netns, probe netns, profile, hz, quality
  local label=$1 rns=$2 pns=$3 profile=$4 hz=$5 q=$6 domain=$((100 + RANDOM % 100))
  local cfg; cfg=$(config "$hz" "$q")
  ${rns:+ip netns exec "$rns"} "$robot_server" --domain "$domain" --dds-profile "$profile" \
    --insecure --config "$cfg" --source test_pattern > "$work/robot.log" 2>&1 &
  pids+=($!)
  sleep 1
  local out
  out=$(timeout -k 5 $((seconds + warmup + 30)) ${pns:+ip netns exec "$pns"} "$net_probe" --domain "$domain" \
        --dds-profile "$profile" --insecure --duration-s "$((seconds + warmup + 2))" --warmup-s "$warmup" \
        2>/dev/null | grep '^probe:' || echo "probe: hung")
  stop_all
  f() { echo "$out" | sed -n "s/.* $1=\([^ ]*\).*/\1/p"; }
  local left; left=$(f left)
  if [ -z "$left" ]; then printf '| %s | %s Hz q%s | no result (probe hung) | | | | |\n' "$label" "$hz" "$q"; return; fi
  printf '| %s | %s Hz q%s | %.1f | %s / %s | %.1f | %s / %s | %s |\n' "$label" "$hz" "$q" \
    "$(echo "$left / $(f measured_s)" | bc -l)" "$(f left_age_p50_ms)" "$(f left_age_p95_ms)" \
    "$(echo "$(f scan) / $(f measured_s)" | bc -l)" "$(f scan_age_p50_ms)" "$(f scan_age_p95_ms)" \
    "$(f ping_oneway_p50_ms)"
}

echo "| path | video | stereo pairs/s | left age p50 / p95 ms | scans/s | scan age p50 / p95 ms | control one-way p50 ms |"
echo "|---|---|---|---|---|---|---|"
row "loopback profile, one host" "" "" loopback 30 80
sed "s/203\.0\.113\.10/10.231.0.1/g" "$src/deploy/dds/wan.xml" > "$work/wan_veth.xml"
row "WAN TCP profile, veth (no shaping)" "${prefix}_robot" "${prefix}_operator" "$work/wan_veth.xml" 30 80
sed "s/203\.0\.113\.10/10.232.0.1/g" "$src/deploy/dds/wan.xml" > "$work/wan_emu.xml"
# The initial peers without <wan_address> (how wan.xml was first written).
sed -e "/<wan_address>/d" "$work/wan_emu.xml" > "$work/wan_emu_nowan.xml"
emulated() {  # label, profile, congestion control (TCP) or "udp"
  if [ "$3" = udp ]; then
    # UDP participants announce every address: only the emulated path may stay up.
    ip -n "${prefix}_robot" link set veth0 down; ip -n "${prefix}_operator" link set veth0 down
  elif ! congestion "$3"; then
    printf '| %s | 30 Hz q80 | not run (this machine cannot select %s) | | | | |\n' "$1" "$3"; return
  fi
  "$netem_relay" --netns-a "${prefix}_robot" --netns-b "${prefix}_operator" --delay-ms 50 \
    --jitter-ms 5 --loss 0.01 --rate-kbit 8000 --duration-s $((seconds + warmup + 40)) > "$work/netem.log" 2>&1 &
  netem=$!
  sleep 0.5
  row "$1" "${prefix}_robot" "${prefix}_operator" "$2" 30 80
  kill "$netem" 2>/dev/null || true; wait "$netem" 2>/dev/null || true
  if [ "$3" = udp ]; then
    ip -n "${prefix}_robot" link set veth0 up; ip -n "${prefix}_operator" link set veth0 up
  fi
}
emulated "WAN TCP, 100 ms RTT, 1 % loss, 8 Mbit/s, BBR" "$work/wan_emu.xml" bbr
emulated "same, CUBIC" "$work/wan_emu.xml" cubic
emulated "same, BBR, initial peer without WAN address" "$work/wan_emu_nowan.xml" bbr
sed "s/203\.0\.113\.10/10.232.0.1/g" "$src/deploy/dds/wan_udp.xml" > "$work/wan_udp_emu.xml"
emulated "WAN UDP (wan_udp.xml), 100 ms RTT, 1 % loss, 8 Mbit/s" "$work/wan_udp_emu.xml" udp
