#!/usr/bin/env bash
# The Internet deployment under outages: robot behind NAT A, pilot and observer 1 behind NAT B
# (one public address), observer 2 behind NAT C, a hub on the public host
# (tests/network/nat_topology.sh), every public link through netem_relay (50 ms one-way, 5 ms
# jitter, 1 % loss each way, 8 Mbit/s; host to host through the hub: 100 ms one-way).
#
# Path "overlay": a WireGuard overlay (deploy/wan/make_overlay.sh, brought up with wg-quick and
# wireguard-go) and the per-peer UDP profiles the generator writes from deploy/dds/overlay.xml,
# with DDS Security on top (make_pki.sh) unless SECURE=0.
#
# TRANSPORT=tcp: the TCP fallback. Every NAT forwards no UDP at all (nat_topology.sh
# --block-udp), so WireGuard's datagrams travel through mostar_wg_tcp (WG_TCP: its path): a
# client on every host, named by the host's WireGuard as the hub's endpoint, dials the server on
# the hub's TCP port 443, which hands them to the hub's WireGuard. DDS is unchanged (UDP inside
# the overlay).
#
# Each run starts everything afresh: robot_server (simulator), a headless operator_client
# pilot driving forward at SPEED, net_probe observers obs1 and obs2. Once the robot drives and
# PRE_S seconds have passed, the robot's uplink is cut both ways (nftables in NAT A) for the
# run's outage, or NAT A gets a new public address ("readdress"), or robot_server is restarted
# as its service would be ("robot_restart": SIGTERM, then the same command line), or the hub
# restarts ("hub_restart": the relay ends, the hub's WireGuard goes down and up, the relay
# starts again); "link back" is then the moment the restarted part was started. Then POST_S
# seconds are measured and every program gets SIGTERM.
#
# One Markdown row per run:
#   stop        last accepted command's arrival -> drive output 0 on the robot (ms)
#   stale       any nonzero drive output from stop + 100 ms until the first command accepted
#               after the link came back (the robot moved on old commands)
#   drive       link back -> first nonzero drive output (s)
#   video back  link back -> first left image captured after it, at the pilot, obs1, obs2 (s)
#   fresh       link back -> first left image younger than FRESH_MS at each of them (s)
#   steady      before the cut, at obs2: stereo pairs/s, left age p50/p95 (ms), scan age p95;
#               the pilot's commands, send -> arrival at the robot, p50/p95 (ms); what the
#               robot sent into the overlay over PRE_S (Mbit/s)
#   exit        SIGTERM -> exit of every program (max, s); "hang" when one needed SIGKILL
# and after each row a STEADY line: pairs/s and left age p50/p95 at the pilot and each observer
# and the control one-way p50/p95, over the 5 s before the cut.
#
# Usage: nat_bench.sh ROBOT_SERVER OPERATOR_CLIENT NET_PROBE NETEM_RELAY MOSTAR_RELAY SOURCE_DIR
# Environment: RUNS ("5": outage seconds, "readdress", "robot_restart" or "hub_restart", one run
# each; e.g. "5 5 30 readdress hub_restart"),
# OBSERVERS ("obs1 obs2": which observers run), VIA ("relay": observers watch through
# mostar_relay on the hub, so the robot's uplink carries two copies of the video, the pilot's
# and the relay's, whatever the number of observers, or one with PILOT_VIDEO=relay; "direct":
# every observer subscribes to the
# robot), SECURE (1: DDS Security on top of the overlay, made by make_pki.sh; 0: off),
# PRE_S (4), POST_S (15), SPEED (0.2 m/s), FRESH_MS (200), VIDEO_HZ (15), VIDEO_QUALITY (60),
# LOSS (0.01: packet loss probability on each public link, each way),
# REPAIR_MS (250: the server's dds.video_repair_period_ms), REPAIR_DEADLINE (h264: milliseconds,
# the server's dds.video_repair_deadline_ms, or "auto": dds.video_repair_deadline_auto; unset:
# none), WINDOW (the server's default:
# dds.video_window_pairs),
# TRANSPORT ("udp", or "tcp" with WG_TCP), CODEC ("jpeg", or "h264": the camera as two H.264
# streams, deploy/config/server_sim_h264.pbtxt, VIDEO_HZ then 30 by default and observers
# read the stream), PILOT_VIDEO ("direct", or "relay": the pilot takes its video through the
# relay, operator_client --video-via-relay, so that the robot's uplink carries one copy; needs
# VIA=relay), SOURCE ("sim": the simulator renders the cameras during the run; "recorded": a
# moving session of the simulator recorded once on loopback before the runs, 20 s at
# VIDEO_HZ, replayed in a loop with --replay-sensors, so no scene is rendered during the runs),
# DDS_TEMPLATE (deploy/dds/overlay.xml: the profiles template make_overlay.sh fills in, e.g. a
# copy with another leaseDuration), KEEP_WORK=1 keeps logs and traces; CAPTURE=1 also records packet headers in the robot's,
# NAT A's, the Internet's, NAT B's, the pilot's and the hub's namespace (tcpdump -i any, one
# pcap each in the run's directory; tests/network/gap_report.py finds where a flow paused). Prints RESULT
# lines (key=value: run, what, then the row's values, or failed=overlay|never_drove) for the
# test wrapper and soak_bench.sh; with TRANSPORT=tcp also udp_blocked (a probe
# datagram dropped by NAT A: 1) and endpoints_not_tunnel (peers the hub's WireGuard saw at an
# address other than its tunnel server's: 0).
# Needs root, nftables, wireguard-go, wireguard-tools, openssl, xvfb-run and python3;
# exit 77 (skipped) without them.
set -euo pipefail
[ $# -eq 6 ] || {
  echo "usage: nat_bench.sh ROBOT_SERVER OPERATOR_CLIENT NET_PROBE NETEM_RELAY MOSTAR_RELAY SOURCE_DIR" >&2
  exit 2
}
robot_server=$1; operator_client=$2; net_probe=$3; netem_relay=$4; mostar_relay=$5; src=$6
for program in "$robot_server" "$operator_client" "$net_probe" "$netem_relay" "$mostar_relay"; do
  [ -x "$program" ] || { echo "nat_bench: $program is not an executable" >&2; exit 2; }
done
[ -f "$src/deploy/dds/overlay.xml" ] || { echo "nat_bench: $src is not the source tree" >&2; exit 2; }
here=$(cd "$(dirname "$0")" && pwd)
"$here/netns.sh" check || exit 77
for tool in nft wg wg-quick wireguard-go openssl xvfb-run python3; do
  command -v "$tool" >/dev/null || { echo "nat_bench: $tool is missing" >&2; exit 77; }
done
[ -c /dev/net/tun ] || { echo "nat_bench: /dev/net/tun is missing" >&2; exit 77; }
[ "${CAPTURE:-0}" != 1 ] || command -v tcpdump >/dev/null ||
  { echo "nat_bench: CAPTURE=1 needs tcpdump (apt install tcpdump)" >&2; exit 2; }

runs=${RUNS:-5}
for what in $runs; do
  [[ "$what" =~ ^[1-9][0-9]*$ || "$what" =~ ^(readdress|robot_restart|hub_restart)$ ]] ||
    { echo "nat_bench: RUNS: '$what' is neither outage seconds nor readdress, robot_restart" \
        "or hub_restart" >&2; exit 2; }
done
[ -n "${runs// /}" ] || { echo "nat_bench: RUNS is empty" >&2; exit 2; }
[[ "${WINDOW:-4}" =~ ^([1-9]|1[0-6])$ ]] || { echo "nat_bench: WINDOW must be 1..16" >&2; exit 2; }
[[ "${REPAIR_MS:-250}" =~ ^[1-9][0-9]*$ ]] ||
  { echo "nat_bench: REPAIR_MS must be a positive number of milliseconds" >&2; exit 2; }
pre_s=${PRE_S:-4}
post_s=${POST_S:-15}
speed=${SPEED:-0.2}
fresh_ms=${FRESH_MS:-200}
codec=${CODEC:-jpeg}
case "$codec" in
  jpeg) video_hz=${VIDEO_HZ:-15}; base_config=server_sim.pbtxt ;;
  h264) video_hz=${VIDEO_HZ:-30}; base_config=server_sim_h264.pbtxt ;;
  *) echo "nat_bench: CODEC must be jpeg or h264" >&2; exit 2 ;;
esac
video_quality=${VIDEO_QUALITY:-60}
observers=${OBSERVERS-obs1 obs2}
via=${VIA:-relay}
pilot_video=${PILOT_VIDEO:-direct}
case "$pilot_video" in
  direct) ;;
  relay) [ "$via" = relay ] || { echo "nat_bench: PILOT_VIDEO=relay needs VIA=relay" >&2; exit 2; } ;;
  *) echo "nat_bench: PILOT_VIDEO must be direct or relay" >&2; exit 2 ;;
esac
source_kind=${SOURCE:-sim}
[[ "$source_kind" =~ ^(sim|recorded)$ ]] || { echo "nat_bench: SOURCE must be sim or recorded" >&2; exit 2; }
secure=${SECURE:-1}
transport=${TRANSPORT:-udp}
case "$transport" in
  udp) ;;
  tcp) [ -x "${WG_TCP:-}" ] || { echo "nat_bench: TRANSPORT=tcp needs WG_TCP (mostar_wg_tcp)" >&2; exit 2; } ;;
  *) echo "nat_bench: TRANSPORT must be udp or tcp" >&2; exit 2 ;;
esac
insecure=()  # SECURE=0: the overlay's profiles without DDS Security, allowed by --insecure
[ "$secure" = 1 ] || insecure=(--insecure)

prefix="mn$$"
tag=$(echo -n "$prefix" | md5sum | cut -c1-4)
work=$(mktemp -d /tmp/mostar_nat_XXXXXX)
pids=()
export WG_QUICK_USERSPACE_IMPLEMENTATION=wireguard-go
hosts=(robot pilot obs1 obs2)
tunnel_pids=()  # TRANSPORT=tcp: mostar_wg_tcp on the hub and every host

teardown() {  # ends one run's topology: programs, WireGuard sockets, namespaces
  for p in "${pids[@]}"; do kill -KILL "$p" 2>/dev/null || true; done
  for p in "${pids[@]}"; do wait "$p" 2>/dev/null || true; done
  pids=()
  tunnel_pids=()
  "$here/nat_topology.sh" down "$prefix" >/dev/null 2>&1 || true
  rm -f /var/run/wireguard/w"$tag"*.sock
}
cleanup() {
  teardown
  pkill -9 -f "$work" 2>/dev/null || true
  if [ "${KEEP_WORK:-0}" = 1 ]; then echo "work dir kept: $work"; else rm -rf "$work"; fi
}
trap cleanup EXIT
trap "exit 1" INT TERM

# Configuration of the simulator: the shipped one with this bench's video settings.
sed -e "s|frame_rate_hz: [0-9.]*|frame_rate_hz: $video_hz|" \
    -e "s|jpeg_quality: [0-9]*|jpeg_quality: $video_quality|" \
    -e "s|scene_file: \"\.\./|scene_file: \"$src/deploy/|" \
    "$src/deploy/config/$base_config" > "$work/server.pbtxt"
# The Internet recipe's video settings (docs/networking.md): repairs about once per round trip.
deadline=""
case ${REPAIR_DEADLINE:-} in
  "") ;;
  auto) deadline=" video_repair_deadline_auto: true" ;;
  *) deadline=" video_repair_deadline_ms: $REPAIR_DEADLINE" ;;
esac
echo "dds { video_repair_period_ms: ${REPAIR_MS:-250}${WINDOW:+ video_window_pairs: $WINDOW}$deadline }" >> "$work/server.pbtxt"

# Waits up to $2 tenths of a second for the shell condition $1.
wait_for() {
  local i
  for i in $(seq "$2"); do eval "$1" && return 0; sleep 0.1; done
  return 1
}

# SOURCE=recorded: 20 s of the simulator with a pilot driving a curve (the whole picture
# moves), recorded on loopback before the runs; every run replays it in a loop.
replay=()
if [ "$source_kind" = recorded ]; then
  record_domain=$((10 + $$ % 80))
  sed -e "s|frame_rate_hz: [0-9.]*|frame_rate_hz: $video_hz|" \
      -e "s|jpeg_quality: [0-9]*|jpeg_quality: 90|" \
      -e "s|scene_file: \"\.\./|scene_file: \"$src/deploy/|" \
      "$src/deploy/config/server_sim.pbtxt" > "$work/record.pbtxt"
  "$robot_server" --domain "$record_domain" --config "$work/record.pbtxt" \
    --record "$work/source.mrec" --duration 24 > "$work/record_server.log" 2>&1 &
  record_pid=$!
  xvfb-run -a "$operator_client" --headless --domain "$record_domain" --id operator \
    --role pilot --duration 22 --drive 0.25,0.35 --no-hud \
    --calibration "$src/deploy/config/calibration_sim.pbtxt" > "$work/record_client.log" 2>&1 || true
  wait "$record_pid" || true
  [ -s "$work/source.mrec" ] || { echo "nat_bench: recording the source failed" >&2; cat "$work/record_server.log" >&2; exit 1; }
  replay=(--replay-sensors "$work/source.mrec" --loop)
fi

# Brings the topology and the overlay up for one run into directory $1.
overlay_up() {
  local run=$1 h
  # (called in an || list, where set -e does not apply: every step says its failure)
  local topology=() fallback=() conf=conf
  if [ "$transport" = tcp ]; then
    topology=(--block-udp)
    fallback=(--tcp-hub 198.18.0.10:443)
    conf=tcp.conf
  fi
  "$here/nat_topology.sh" up "$prefix" --netem "$netem_relay" --log-dir "$run" "${topology[@]}" \
    --loss "${LOSS:-0.01}" >/dev/null || return 1
  local observer_kind=--peer
  [ "$via" != relay ] || observer_kind=--observer
  "$src/deploy/wan/make_overlay.sh" "$run/overlay" --hub-endpoint 198.18.0.10:51820 \
    --peer robot --peer pilot "$observer_kind" obs1 "$observer_kind" obs2 "${fallback[@]}" \
    --dds-template "${DDS_TEMPLATE:-$src/deploy/dds/overlay.xml}" --hub-state-dir "$run" \
    >/dev/null || return 1
  if [ "$transport" = tcp ]; then
    # UDP really is blocked: a probe from the robot's LAN is dropped (and counted) by NAT A.
    ip netns exec "${prefix}_robot" bash -c 'echo probe > /dev/udp/198.18.0.10/9' || true
    echo "$("$here/nat_topology.sh" blocked "$prefix" a)" > "$run/udp_blocked"
    # The tunnel: its server on the hub, a client on every host (as the systemd units run them).
    local env
    env=$(grep -v '^#' "$run/overlay/hub.wg-tcp.env" | tr '\n' ' ')
    eval "local $env"
    ip netns exec "${prefix}_hub" "$WG_TCP" server --listen "$LISTEN" --wireguard "$WIREGUARD" \
      >"$run/tunnel_hub.log" 2>&1 &
    tunnel_pids+=("hub=$!"); pids+=($!)
    for h in "${hosts[@]}"; do
      env=$(grep -v '^#' "$run/overlay/$h.wg-tcp.env" | tr '\n' ' ')
      eval "local $env"
      ip netns exec "${prefix}_$h" "$WG_TCP" client --hub "$HUB" --listen "$LISTEN" \
        >"$run/tunnel_$h.log" 2>&1 &
      tunnel_pids+=("$h=$!"); pids+=($!)
    done
    # WireGuard's first handshake would otherwise be dropped and retried only after 5 s.
    for h in "${hosts[@]}"; do
      wait_for "grep -q 'connected to' '$run/tunnel_$h.log'" 100 ||
        { echo "nat_bench: the tunnel of $h did not connect" >&2; return 1; }
    done
  fi
  if [ "$secure" = 1 ]; then
    # DDS Security on top of the overlay, as the recipe does: NAME.xml from NAME.dds.xml. The
    # pilot's certificate carries its client id, "operator" (the simulator's role table).
    cp "$run/overlay/pilot.dds.xml" "$run/overlay/operator.dds.xml"
    "$src/deploy/security/make_pki.sh" "$run/pki" --profile-dir "$run/overlay" \
      --robot robot --pilot operator --observer obs1 --observer obs2 --relay hub \
      >"$run/pki.log" 2>&1 || return 1
    local h
    for h in robot obs1 obs2 hub; do cp "$run/pki/$h.xml" "$run/overlay/$h.dds.xml"; done
    cp "$run/pki/operator.xml" "$run/overlay/pilot.dds.xml"
  fi
  # wg-quick names the interface after the file: unique per bench, at most 15 characters.
  cp "$run/overlay/mostar-hub.conf" "$run/w${tag}hub.conf"
  ip netns exec "${prefix}_hub" wg-quick up "$run/w${tag}hub.conf" >"$run/wg_hub.log" 2>&1 ||
    return 1
  for h in "${hosts[@]}"; do
    cp "$run/overlay/$h.$conf" "$run/w$tag$h.conf"
    ip netns exec "${prefix}_$h" wg-quick up "$run/w$tag$h.conf" >"$run/wg_$h.log" 2>&1 || return 1
  done
  # Every peer's handshake with the hub (keepalives start it).
  for h in "${hosts[@]}"; do
    wait_for "[ \"\$(wg show w$tag$h latest-handshakes | awk '{print \$2}')\" -gt 0 ] 2>/dev/null" 100 ||
      { echo "nat_bench: no WireGuard handshake from $h" >&2; return 1; }
  done
}

# Stops pid $1 with SIGTERM; prints the seconds it took, or "hang" after 10 s (then SIGKILL).
stop_timed() {
  local p=$1 t0 i
  t0=$(date +%s%N)
  kill -TERM "$p" 2>/dev/null || { echo 0; return; }
  for i in $(seq 100); do
    if ! kill -0 "$p" 2>/dev/null; then
      wait "$p" 2>/dev/null || true
      python3 -c "print('%.2f' % (($(date +%s%N) - $t0) / 1e9))"
      return
    fi
    sleep 0.1
  done
  kill -KILL "$p" 2>/dev/null || true
  echo hang
}

# pid of program `comm` inside namespace `ns`
ns_pid_of() {
  local p
  for p in $(ip netns pids "$1" 2>/dev/null); do
    [ "$(cat "/proc/$p/comm" 2>/dev/null)" = "$2" ] && { echo "$p"; return 0; }
  done
  return 0
}

run_one() {  # index, outage seconds or "readdress"
  local i=$1 what=$2 run domain robot_pid xvfb_pid client_pid probe1 probe2 total exits
  run="$work/run_$i"; mkdir -p "$run"
  domain=$((100 + RANDOM % 100))
  overlay_up "$run" || {
    echo "| $i | $what | overlay did not come up | | | | | | |"
    echo "RESULT run=$i what=$what failed=overlay"
    teardown; return
  }
  local ov="$run/overlay"
  if [ "${CAPTURE:-0}" = 1 ]; then
    local ns
    for ns in robot nata inet natb pilot hub; do
      ip netns exec "${prefix}_$ns" tcpdump -i any -nn -U -s 96 -w "$run/cap_$ns.pcap" \
        >/dev/null 2>&1 &
      pids+=($!)
    done
  fi
  start_robot() {  # trace and log file names in $run
    ip netns exec "${prefix}_robot" "$robot_server" --domain "$domain" \
      --dds-profile "$ov/robot.dds.xml" "${insecure[@]}" --config "$run/../server.pbtxt" \
      "${replay[@]}" --trace "$run/$1" >"$run/$2" 2>&1 &
    robot_pid=$!; pids+=("$robot_pid")
  }
  start_robot server.csv server.log
  local n=${what//[!0-9]/}; n=${n:-0}
  total=$((90 + n + post_s))
  local obs_domain=$domain relay_pid=""
  [ "$via" != relay ] || obs_domain=$((domain + 1))
  start_relay() {  # log file name in $run
    ip netns exec "${prefix}_hub" "$mostar_relay" --dds-profile "$ov/hub.dds.xml" "${insecure[@]}" \
      --robot-domain "$domain" --observer-domain "$obs_domain" \
      --video-repair-period-ms "${REPAIR_MS:-250}" >"$run/$1" 2>&1 &
    relay_pid=$!; pids+=("$relay_pid")
  }
  [ "$via" != relay ] || start_relay relay.log
  for h in $observers; do
    ip netns exec "${prefix}_$h" "$net_probe" --domain "$obs_domain" --dds-profile "$ov/$h.dds.xml" \
      "${insecure[@]}" --id "$h" --duration-s "$total" --samples "$run/$h.csv" >"$run/$h.log" 2>&1 &
    pids+=($!)
  done
  probe1=""; probe2=""
  [[ "$observers" != *obs1* ]] || probe1=${pids[-1]}
  [[ "$observers" != *obs2* ]] || probe2=${pids[-1]}
  [[ "$observers" != *"obs1 obs2"* ]] || probe1=${pids[-2]}
  local video_via=()
  [ "$pilot_video" != relay ] || video_via=(--video-via-relay --video-domain "$obs_domain")
  ip netns exec "${prefix}_pilot" xvfb-run -a -s "-screen 0 1920x1080x24 -noreset" \
    "$operator_client" --headless --domain "$domain" --dds-profile "$ov/pilot.dds.xml" "${video_via[@]}" \
    "${insecure[@]}" --id operator --role pilot --duration "$total" --drive "$speed,0" \
    --calibration "$src/deploy/config/calibration_sim.pbtxt" --trace "$run/client.csv" \
    >"$run/client.log" 2>&1 &
  xvfb_pid=$!; pids+=("$xvfb_pid")

  if ! wait_for "grep -q '^drive_out_mmps,[0-9]*,[1-9]' '$run/server.csv' 2>/dev/null" 600; then
    echo "| $i | $what | the robot never drove | | | | | | |"
    echo "RESULT run=$i what=$what failed=never_drove"
    teardown; return
  fi
  local tx0 tx1
  tx0=$(ip -n "${prefix}_robot" -s link show "w${tag}robot" | awk '/TX:/ { getline; print $1 }')
  sleep "$pre_s"
  tx1=$(ip -n "${prefix}_robot" -s link show "w${tag}robot" | awk '/TX:/ { getline; print $1 }')
  echo "$(( (tx1 - tx0) * 8 / pre_s / 1000 ))" > "$run/uplink_kbit"
  date +%s%N > "$run/t_down"
  if [ "$what" = readdress ]; then
    "$here/nat_topology.sh" readdress "$prefix" a 3
  elif [ "$what" = robot_restart ]; then
    # As systemd restarts the service: SIGTERM, then the same command line again.
    echo "old=$(stop_timed "$robot_pid")" > "$run/restart_exit"
    start_robot server_2.csv server_2.log
  elif [ "$what" = hub_restart ]; then
    # The hub computer restarted: the relay ends, its WireGuard goes down and up (peers keep
    # their sessions; the hub's are new), the relay starts again.
    [ -z "$relay_pid" ] || echo "old=$(stop_timed "$relay_pid")" > "$run/restart_exit"
    ip netns exec "${prefix}_hub" wg-quick down "$run/w${tag}hub.conf" >>"$run/wg_hub.log" 2>&1
    ip netns exec "${prefix}_hub" wg-quick up "$run/w${tag}hub.conf" >>"$run/wg_hub.log" 2>&1 ||
      echo "nat_bench: the hub's overlay did not come back" >&2
    [ "$via" != relay ] || start_relay relay_2.log
  else
    "$here/nat_topology.sh" outage "$prefix" a on
    sleep "$n"
    "$here/nat_topology.sh" outage "$prefix" a off
  fi
  date +%s%N > "$run/t_up"
  sleep "$post_s"
  date +%s%N > "$run/t_end"
  client_pid=$(ns_pid_of "${prefix}_pilot" operator_client)
  exits="client=$( [ -n "$client_pid" ] && stop_timed "$client_pid" || echo gone)"
  [ -z "$probe1" ] || exits+=" obs1=$(stop_timed "$probe1")"
  [ -z "$probe2" ] || exits+=" obs2=$(stop_timed "$probe2")"
  exits+=" robot=$(stop_timed "$robot_pid")"
  [ "$via" != relay ] || exits+=" relay=$(stop_timed "$relay_pid")"
  if [ "$transport" = tcp ]; then
    # Before the tunnels stop: where the hub's WireGuard sees its peers (all at the tunnel).
    wg show "w${tag}hub" endpoints | awk '$2 !~ /^127\.0\.0\.1:/' | wc -l \
      > "$run/endpoints_not_tunnel"
    local t
    for t in "${tunnel_pids[@]}"; do exits+=" tunnel_${t%%=*}=$(stop_timed "${t#*=}")"; done
  fi
  echo "$exits" > "$run/exits"
  teardown
  # A restarted robot's trace goes on in server_2.csv (its clock is the same host's).
  [ ! -f "$run/server_2.csv" ] || cat "$run/server_2.csv" >>"$run/server.csv"
  python3 - "$run" "$i" "$what" "$fresh_ms" <<'EOF'
import os, sys
run, idx, what, fresh_ms = sys.argv[1], sys.argv[2], sys.argv[3], float(sys.argv[4])
rd = lambda f: int(open(os.path.join(run, f)).read())
t_down, t_up, t_end = rd("t_down"), rd("t_up"), rd("t_end")
def trace(name):
    out = []
    path = os.path.join(run, name)
    if os.path.exists(path):
        for line in open(path):
            p = line.strip().split(",")
            if len(p) == 3:
                try: out.append((p[0], int(p[1]), int(p[2])))
                except ValueError: pass
    return out
server = [x for x in trace("server.csv") if x[1] <= t_end]
drive = [(t, v) for k, t, v in server if k == "drive_out_mmps"]
accepted = sorted(t for k, t, v in server if k == "command_rx")
before = [t for t in accepted if t < t_up]
after = [t for t in accepted if t >= t_up]
stop_ms, stale = "never", "no"
if before:
    last = before[-1]
    stopped = next((t for t, v in drive if t > last and v == 0), None)
    if stopped is not None:
        stop_ms = "%.0f" % ((stopped - last) / 1e6)
        resume_cmd = after[0] if after else t_end
        stale = "yes" if any(v > 0 for t, v in drive if stopped + 1e8 < t < resume_cmd) else "no"
if what == "readdress" and stop_ms == "never":
    stop_ms = "kept driving"
if what == "robot_restart":
    stop_ms = "(restarted)"  # the old process ended: no drive output after its last command
drive_again = next((t for t, v in drive if t > t_up and v > 0), None)
drive_s = "never" if drive_again is None else "%.1f" % ((drive_again - t_up) / 1e9)
def after(samples, ok):  # link back -> first sample for which ok(receive, age)
    t = next((rx for rx, age in samples if rx > t_up and ok(rx, age)), None)
    return "never" if t is None else "%.1f" % ((t - t_up) / 1e9)
pilot = [(t, t - st) for k, t, st in trace("client.csv") if k == "left_rx"]
obs = {h: [(rx, rx - st) for k, rx, st in trace(h + ".csv") if k == "left"] for h in ("obs1", "obs2")}
operators = (pilot, obs["obs1"], obs["obs2"])
# Back: an image captured after the link came back; fresh: one younger than fresh_ms.
back = " / ".join(after(s, lambda rx, age: rx - age > t_up) for s in operators)
video = " / ".join(after(s, lambda rx, age: age < fresh_ms * 1e6) for s in operators)
# Steady state at obs2 over the last 5 s before the cut.
def pct(v, q):
    v = sorted(v)
    return v[min(len(v) - 1, int(q * len(v)))] if v else float("nan")
win = [(rx, age) for rx, age in (obs["obs2"] or pilot) if t_down - 5e9 <= rx < t_down]
scans = [rx - st for k, rx, st in trace("obs2.csv") if k == "scan" and t_down - 5e9 <= rx < t_down]
uplink = int(open(os.path.join(run, "uplink_kbit")).read()) / 1000.0
# Control one-way: the pilot's command (its stamp) -> its arrival at the robot, by sequence.
sent = {v: t for k, t, v in trace("client.csv") if k == "command"}
control = [t - sent[v] for k, t, v in server
           if k == "command_rx" and v in sent and t_down - 5e9 <= t < t_down]
steady = "%.1f pairs/s, %.0f / %.0f ms, scan p95 %.0f ms; control %.0f / %.0f ms; robot sends %.1f Mbit/s" % (
    len(win) / 5.0, pct([a for _, a in win], 0.5) / 1e6, pct([a for _, a in win], 0.95) / 1e6,
    pct(scans, 0.95) / 1e6, pct(control, 0.5) / 1e6, pct(control, 0.95) / 1e6, uplink)
def at(samples):  # pairs/s and left age p50 / p95 over the 5 s before the cut
    w = [age for rx, age in samples if t_down - 5e9 <= rx < t_down]
    return "%.1f pairs/s %.0f / %.0f ms" % (len(w) / 5.0, pct(w, 0.5) / 1e6, pct(w, 0.95) / 1e6)
steady_each = "STEADY pilot: %s; obs1: %s; obs2: %s; control one-way p50 / p95: %.0f / %.0f ms" % (
    at(pilot), at(obs["obs1"]), at(obs["obs2"]), pct(control, 0.5) / 1e6, pct(control, 0.95) / 1e6)
exits = dict(kv.split("=") for kv in open(os.path.join(run, "exits")).read().split())
hangs = [k for k, v in exits.items() if v == "hang"]
slowest = max((float(v) for v in exits.values() if v not in ("hang", "gone")), default=0.0)
exit_cell = ("hang: " + ",".join(hangs)) if hangs else "%.2f" % slowest
label = what + (" s" if what.isdigit() else "")
print("| %s | %s | %s | %s | %s | %s | %s | %s | %s |" % (idx, label, stop_ms, stale, drive_s, back, video, steady, exit_cell))
print(steady_each)
extra = ""
for name in ("udp_blocked", "endpoints_not_tunnel"):
    path = os.path.join(run, name)
    if os.path.exists(path):
        extra += " %s=%s" % (name, open(path).read().strip() or "none")
print("RESULT run=%s what=%s stop_ms=%s stale=%s drive_s=%s back=%s fresh=%s exit=%s%s" % (
    idx, what, stop_ms.replace(" ", "_"), stale, drive_s, back.replace(" ", ""), video.replace(" ", ""),
    exit_cell.replace(" ", ""), extra))
EOF
}

echo "| run | outage | stop after last command (ms) | moved on stale commands? | driving again after link back (s) | video back after link back, pilot / obs1 / obs2 (s) | fresh video (age < ${fresh_ms} ms) after, pilot / obs1 / obs2 (s) | steady state at obs2 before the cut | slowest exit on SIGTERM (s) |"
echo "|---|---|---|---|---|---|---|---|---|"
i=0
for what in $runs; do
  i=$((i + 1))
  run_one "$i" "$what"
done
