#!/usr/bin/env bash
# Outage bench: what the robot and the operator see when the WAN link drops for a while.
#
# For each outage length (default 5 s and 25 s) a fresh robot_server (test pattern video and
# simulated drive) runs in the robot namespace, and a headless operator_client pilot driving
# forward (0.2 m/s) plus a net_probe observer run in the operator namespace, all over the WAN TCP
# profile through netem_relay (100 ms RTT, 1 % loss each way, 8 Mbit/s). Once the robot drives,
# SIGUSR1 to the relay cuts the link both ways; after N s a second SIGUSR1 brings it back and
# the run goes on for POST_S s. All programs share this machine's clock, so the stamps of the
# robot trace, the pilot trace and the probe samples compare directly.
#
# Printed per outage (Markdown table, then notes):
#   stop time     last accepted command's arrival on the robot -> drive output 0 (robot trace);
#   burst         commands that reached the robot's governor in the flush after the link came
#                 back (verdict counters of the drive_safety health, recorded on the robot
#                 every HEALTH_PERIOD_S), with the stale and not-holder rejections among them;
#   stale motion  any nonzero drive output while the newest accepted command was older than the
#                 maximum command age on arrival, or stamped before the link came back;
#   resume        link back -> first nonzero drive output again;
#   video         age of the first left frame the probe received after the link came back, and
#                 link back -> first left frame younger than 200 ms.
#
# Usage: outage_bench.sh ROBOT_SERVER OPERATOR_CLIENT NET_PROBE NETEM_RELAY SOURCE_DIR
# Environment: PROFILE (wan.xml: TCP; wan_udp.xml: UDP unicast), OUTAGES ("5 25"), ATTEMPTS (3 per outage when the robot never drives),
# PROBE=0 (no probe: two TCP clients from one address can starve one of them on Fast DDS 2.9;
# the video cell then counts the pilot's frames captured after the link came back),
# PROBE_LEAD_S (3: probe start before the pilot's), SPEED (0.2 m/s), PRE_S (3: driving before the cut), POST_S
# (seconds measured after the link comes back; default 15, and 2N - 5 for outages N > 10 s so
# that TCP's retransmission backoff can run out), HEALTH_PERIOD_S (0.05: counter resolution), VIDEO_HZ (30), VIDEO_QUALITY (80),
# RTO_MAX_MS caps TCP's retransmission timeout in both namespaces (net.ipv4.tcp_rto_max_ms),
# KEEP_WORK=1 keeps the traces, logs, recordings and `ss` snapshots; STACKS=1 (diagnosis only:
# it pauses the robot for a moment) also saves the robot's thread stacks 1 s into the outage.
# Thread stacks of both programs are always saved after the measured window (with gdb).
# Needs root (network namespaces, TUN), xvfb-run and python3; exit 77 (skipped) without them.
set -euo pipefail
[ $# -eq 5 ] || {
  echo "usage: outage_bench.sh ROBOT_SERVER OPERATOR_CLIENT NET_PROBE NETEM_RELAY SOURCE_DIR" >&2
  exit 2
}
robot_server=$1; operator_client=$2; net_probe=$3; netem_relay=$4; src=$5
here=$(cd "$(dirname "$0")" && pwd)
"$here/netns.sh" check || exit 77
command -v xvfb-run >/dev/null || { echo "outage_bench: xvfb-run is missing" >&2; exit 77; }
command -v python3 >/dev/null || { echo "outage_bench: python3 is missing" >&2; exit 77; }

outages=${OUTAGES:-5 25}
speed=${SPEED:-0.2}
pre_s=${PRE_S:-3}
post_s=${POST_S:-}
health_period=${HEALTH_PERIOD_S:-0.05}
video_hz=${VIDEO_HZ:-30}
video_quality=${VIDEO_QUALITY:-80}
max_command_age_ms=300  # drive.safety.max_command_age_ms of server_sim.pbtxt

prefix="mout$$"
work=$(mktemp -d /tmp/mostar_outage_XXXXXX)
pids=()
relay_pid=""
stacks() {  # pid, file: all thread stacks of a running program (for hangs)
  command -v gdb >/dev/null || return 0
  timeout 60 gdb -p "$1" -batch -ex "thread apply all bt" > "$2" 2>&1 || true
}
stop_pid() {  # pid, seconds to wait after SIGTERM, [stack file]; returns 1 when it had to be killed
  local p=$1 wait_s=$2 stack_file=${3:-}
  kill -TERM "$p" 2>/dev/null || return 0
  for _ in $(seq $((wait_s * 10))); do kill -0 "$p" 2>/dev/null || return 0; sleep 0.1; done
  [ -z "$stack_file" ] || stacks "$p" "$stack_file"
  kill -KILL "$p" 2>/dev/null || true
  return 1
}
cleanup() {
  for p in "${pids[@]}"; do kill -KILL "$p" 2>/dev/null || true; done
  for p in "${pids[@]}"; do wait "$p" 2>/dev/null || true; done
  # Leftovers inside the namespaces (the client and Xvfb under xvfb-run) die with them.
  "$here/netns.sh" down "$prefix" || true
  if [ "${KEEP_WORK:-0}" = 1 ]; then echo "work dir kept: $work"; else rm -rf "$work"; fi
}
trap cleanup EXIT
trap "exit 1" INT TERM
"$here/netns.sh" up "$prefix"
if [ -n "${RTO_MAX_MS:-}" ]; then
  # Cap TCP's retransmission backoff (Linux >= 6.15) so that a link that comes back is used
  # within RTO_MAX_MS instead of after the next doubled timeout (up to 2 minutes).
  for ns in "${prefix}_robot" "${prefix}_operator"; do
    ip netns exec "$ns" sysctl -qw net.ipv4.tcp_rto_max_ms="$RTO_MAX_MS"
  done
fi
rns="${prefix}_robot"; ons="${prefix}_operator"

# PROFILE: wan.xml (TCP, default) or wan_udp.xml (UDP unicast, as over a VPN). UDP participants
# announce every interface address: leave only the emulated path up.
profile=${PROFILE:-wan.xml}
case "$profile" in wan.xml|wan_udp.xml) ;; *) echo "outage_bench: PROFILE must be wan.xml or wan_udp.xml" >&2; exit 2 ;; esac
sed "s/203\.0\.113\.10/10.232.0.1/g" "$src/deploy/dds/$profile" > "$work/wan.xml"
if [ "$profile" = wan_udp.xml ]; then
  ip -n "$rns" link set veth0 down
  ip -n "$ons" link set veth0 down
fi
# The shipped simulator configuration; only the video settings, the scene path and the health
# period (the resolution of the verdict counters) change.
sed -e "s|frame_rate_hz: [0-9.]*|frame_rate_hz: $video_hz|" \
    -e "s|jpeg_quality: [0-9]*|jpeg_quality: $video_quality|" \
    -e "s|scene_file: \"\.\./|scene_file: \"$src/deploy/|" \
    "$src/deploy/config/server_sim.pbtxt" > "$work/server.pbtxt"
echo "health_period_s: $health_period" >> "$work/server.pbtxt"
grep -q "max_command_age_ms: $max_command_age_ms" "$work/server.pbtxt" ||
  echo "outage_bench: warning: max_command_age_ms in server_sim.pbtxt is not $max_command_age_ms" >&2

# The pid of the program named `comm` running in namespace `ns` (empty when none).
ns_pid_of() {
  local ns=$1 comm=$2 p
  for p in $(ip netns pids "$ns" 2>/dev/null); do
    [ "$(cat "/proc/$p/comm" 2>/dev/null)" = "$comm" ] && { echo "$p"; return 0; }
  done
  return 0
}
sleep_until() {  # wall-clock time in ns since the epoch
  local left_ns=$(($1 - $(date +%s%N)))
  [ "$left_ns" -le 0 ] || sleep "$(printf '%d.%09d' $((left_ns / 1000000000)) $((left_ns % 1000000000)))"
}
snapshot() {  # label: TCP state of both ends of the DDS connections
  local out="$run/ss.txt"
  { echo "=== $1 $(date +%s%N)"
    echo "--- robot"; ip netns exec "$rns" ss -tnio state all "( sport = :15100 or dport = :15100 )" || true
    echo "--- operator"; ip netns exec "$ons" ss -tnio state all "( dport = :15100 )" || true
  } >> "$out" 2>&1
}

post_for() {  # outage seconds -> measured seconds after the link comes back
  if [ -n "$post_s" ]; then echo "$post_s"; elif [ "$1" -le 10 ]; then echo 15; else echo $((2 * $1 - 5)); fi
}

run_outage() {  # outage seconds
  local n=$1 post; post=$(post_for "$1")
  run="$work/outage_$n"; mkdir -p "$run"
  local domain=$((100 + RANDOM % 100))
  local total=$((60 + n + post))
  "$netem_relay" --netns-a "$rns" --netns-b "$ons" --delay-ms 50 --jitter-ms 5 --loss 0.01 \
    --rate-kbit 8000 --duration-s $((total + 60)) > "$run/netem.log" 2>&1 &
  relay_pid=$!; pids+=("$relay_pid")
  for _ in $(seq 50); do grep -q ready "$run/netem.log" && break; sleep 0.1; done
  grep -q ready "$run/netem.log" || { cat "$run/netem.log" >&2; echo "outage_bench: netem_relay failed" >&2; exit 1; }

  ip netns exec "$rns" "$robot_server" --domain "$domain" --dds-profile "$work/wan.xml" \
    --insecure --config "$work/server.pbtxt" --source test_pattern --trace "$run/server.csv" \
    --record "$run/robot.mrec" > "$run/server.log" 2>&1 &
  local robot_pid=$!; pids+=("$robot_pid")
  sleep 1
  local probe_pid=""
  if [ "${PROBE:-1}" = 1 ]; then
    ip netns exec "$ons" "$net_probe" --domain "$domain" --dds-profile "$work/wan.xml" --insecure --no-ping \
      --duration-s "$total" --samples "$run/probe.csv" > "$run/probe.log" 2>&1 &
    probe_pid=$!; pids+=("$probe_pid")
    # The probe first, the pilot a little later: their DDS discoveries do not overlap.
    sleep "${PROBE_LEAD_S:-3}"
  fi
  ip netns exec "$ons" xvfb-run -a -s "-screen 0 1920x1080x24 -noreset" "$operator_client" \
    --headless --domain "$domain" --dds-profile "$work/wan.xml" --insecure --id operator \
    --role pilot --duration "$total" --drive "$speed,0" \
    --calibration "$src/deploy/config/calibration_sim.pbtxt" \
    --trace "$run/client.csv" > "$run/client.log" 2>&1 &
  local xvfb_pid=$!; pids+=("$xvfb_pid")

  # The trace is block-buffered: a nonzero drive output shows up within a few seconds.
  local driving=0
  for _ in $(seq 400); do
    if grep -q '^drive_out_mmps,[0-9]*,[1-9]' "$run/server.csv" 2>/dev/null; then driving=1; break; fi
    sleep 0.1
  done
  if [ "$driving" = 0 ]; then
    echo "outage_bench: the robot never drove in the ${n} s run; see $run (KEEP_WORK=1)" >&2
    echo "no_drive" > "$run/status"
    stacks "$robot_pid" "$run/robot_stacks_no_drive.txt"
    local c; c=$(ns_pid_of "$ons" operator_client)
    [ -z "$c" ] || stacks "$c" "$run/client_stacks_no_drive.txt"
  else
    sleep "$pre_s"
    snapshot "before"
    date +%s%N > "$run/t_down"
    kill -USR1 "$relay_pid"
    sleep 1; snapshot "outage+1s"
    if [ "${STACKS:-0}" = 1 ] && command -v gdb >/dev/null; then
      # Where the robot's threads are while the link is down (pauses the robot briefly).
      stacks "$robot_pid" "$run/robot_stacks_outage.txt"
    fi
    sleep_until $(($(cat "$run/t_down") + n * 1000000000 - 100000000)); snapshot "outage_end-0.1s"
    sleep_until $(($(cat "$run/t_down") + n * 1000000000))
    date +%s%N > "$run/t_up"
    kill -USR1 "$relay_pid"
    sleep 2; snapshot "link_back+2s"
    sleep $((post - 2)); snapshot "end"
    date +%s%N > "$run/t_end"
    # After the measured window: where both programs' threads are (evidence for a stuck link).
    stacks "$robot_pid" "$run/robot_stacks_end.txt"
    local c; c=$(ns_pid_of "$ons" operator_client)
    [ -z "$c" ] || stacks "$c" "$run/client_stacks_end.txt"
  fi
  # Stop in order: pilot (flushes its trace), probe, robot (closes its recording), relay.
  local client_pid; client_pid=$(ns_pid_of "$ons" operator_client)
  if [ -n "$client_pid" ] && ! stop_pid "$client_pid" 10 "$run/client_stacks_hung.txt"; then echo "client_hung" >> "$run/status"; fi
  [ -z "$probe_pid" ] || stop_pid "$probe_pid" 10 "$run/probe_stacks_hung.txt" || echo "probe_hung" >> "$run/status"
  stop_pid "$robot_pid" 20 "$run/robot_stacks_hung.txt" || echo "robot_hung" >> "$run/status"
  stop_pid "$relay_pid" 5 || true
  stop_pid "$xvfb_pid" 5 || true
  for p in "$robot_pid" $probe_pid "$xvfb_pid" "$relay_pid"; do wait "$p" 2>/dev/null || true; done
  pids=()
}

analyse() {  # outage seconds -> one table row on stdout, notes in $run/notes
  local n=$1
  python3 - "$work/outage_$n" "$n" "$max_command_age_ms" "$health_period" <<'EOF'
import os, sys, zlib

run, outage_s, max_age_ms, health_period = sys.argv[1], sys.argv[2], int(sys.argv[3]), float(sys.argv[4])
notes = []
status = open(os.path.join(run, "status")).read().split() if os.path.exists(os.path.join(run, "status")) else []
def row(*cells):
    print("| " + " | ".join(str(c) for c in cells) + " |")
def finish():
    with open(os.path.join(run, "notes"), "w") as f:
        f.write("".join("- %s s outage: %s\n" % (outage_s, n) for n in notes))
    sys.exit(0)
if "no_drive" in status or not os.path.exists(os.path.join(run, "t_up")):
    row(outage_s + " s", "robot never drove", "", "", "", "", "", "")
    notes.append("no measurement: the robot never drove before the cut (" + " ".join(status) + ")")
    finish()
t_down = int(open(os.path.join(run, "t_down")).read())
t_up = int(open(os.path.join(run, "t_up")).read())
t_end = int(open(os.path.join(run, "t_end")).read())  # later events belong to the shutdown
ms = lambda ns: ns / 1e6

def read_trace(path):
    out = []
    if not os.path.exists(path):
        return out
    for line in open(path):
        parts = line.strip().split(",")
        if len(parts) != 3:
            continue
        try:
            out.append((parts[0], int(parts[1]), int(parts[2])))
        except ValueError:
            pass
    return out

server = [x for x in read_trace(os.path.join(run, "server.csv")) if x[1] <= t_end]
client = [x for x in read_trace(os.path.join(run, "client.csv")) if x[1] <= t_end]
drive = [(t, v) for topic, t, v in server if topic == "drive_out_mmps"]
# Accepted commands: "command" (sender stamp) and "command_rx" (arrival) lines come in pairs.
stamp_of = {seq: t for topic, t, seq in server if topic == "command"}
accepted = sorted((t, seq, stamp_of.get(seq, t)) for topic, t, seq in server if topic == "command_rx")
sent = [(t, seq) for topic, t, seq in client if topic == "command"]

# ---- stop time ----
before = [a for a in accepted if a[0] < t_up]
if not before:
    row(outage_s + " s", "no command accepted", "", "", "", "", "", "")
    finish()
last_rx = before[-1][0]
speed_at_cut = 0
for t, v in drive:
    if t <= last_rx:
        speed_at_cut = v
stopped = next((t for t, v in drive if t > last_rx and v == 0), None)
stop_ms = "never" if stopped is None else "%.0f" % ms(stopped - last_rx)
# The control loop traces every 20 ms cycle: a long gap means the loop itself was blocked.
cycles = [t for t, v in drive] + [t_end]  # a pause may last past the measured window
gaps = [(y - x, x, y) for x, y in zip(cycles, cycles[1:]) if y >= t_down - 1e9]
if gaps:
    g, a, b = max(gaps)
    notes.append("longest pause of the robot's control loop: %.2f s, from %.2f s to %.2f s after the cut%s"
                 " (link back at %.2f s); drive output before the pause %d mm/s"
                 % (g / 1e9, (a - t_down) / 1e9, (b - t_down) / 1e9,
                    " (end of the measured window)" if b == t_end else "", (t_up - t_down) / 1e9,
                    next((v for t, v in reversed(drive) if t <= a), 0)))
notes.append("last command before the cut arrived %.0f ms after the cut (in flight), speed then %d mm/s"
             % (ms(last_rx - t_down), speed_at_cut))

# ---- verdict counters from the robot's recording (health of device drive_safety) ----
def varint(b, i):
    v = s = 0
    while True:
        c = b[i]; i += 1
        v |= (c & 0x7F) << s; s += 7
        if not c & 0x80:
            return v, i
def fields(b):
    i, out = 0, []
    while i < len(b):
        key, i = varint(b, i)
        fn, wt = key >> 3, key & 7
        if wt == 0: v, i = varint(b, i)
        elif wt == 1: v, i = b[i:i + 8], i + 8
        elif wt == 2:
            l, i = varint(b, i); v, i = b[i:i + l], i + l
        elif wt == 5: v, i = b[i:i + 4], i + 4
        else: raise ValueError("wire type %d" % wt)
        out.append((fn, v))
    return out
health = []  # (stamp_ns, counters, watchdog_state, holder)
rec_path = os.path.join(run, "robot.mrec")
if os.path.exists(rec_path):
    data = open(rec_path, "rb").read()
    i, first = 13, True
    while i < len(data):
        try:
            n, j = varint(data, i)
        except IndexError:
            break
        if j + n + 4 > len(data):
            break
        body = data[j:j + n]
        if zlib.crc32(body) != int.from_bytes(data[j + n:j + n + 4], "little"):
            break
        i = j + n + 4
        if first:  # the header
            first = False
            continue
        for fn, v in fields(body):
            if fn != 17:
                continue
            stamp, counters, state, holder = 0, {}, 0, ""
            for hf, hv in fields(v):
                if hf == 1: stamp = hv
                elif hf == 4: holder = hv.decode()
                elif hf == 5: state = hv
                elif hf == 3:
                    dev = fields(hv)
                    if any(df == 1 and dv == b"drive_safety" for df, dv in dev):
                        for df, dv in dev:
                            if df == 5:
                                c = dict(fields(dv))
                                counters[c.get(1, b"").decode()] = c.get(2, 0)
            health.append((stamp, counters, state, holder))
health = sorted((h for h in health if h[0] <= t_end), key=lambda h: h[0])
kinds = ["accepted", "rejected_not_holder", "rejected_stale", "rejected_out_of_order", "rejected_invalid"]
arrivals = lambda c: sum(c.get(k, 0) for k in kinds)
burst_cells = ("no health recorded", "")
if health:
    # The burst: every command that reached the governor after the link came back and before
    # the first command it accepted again (health records are written by the control loop, so
    # a blocked loop widens the interval but not the count).
    base = max((k for k, h in enumerate(health) if h[0] <= t_up), default=0)
    first_ok = next((a[0] for a in accepted if a[0] >= t_up), t_end)
    last = max((k for k, h in enumerate(health) if h[0] < first_ok), default=base)
    total = {x: health[last][1].get(x, 0) - health[base][1].get(x, 0) for x in kinds}
    count = sum(total.values())
    burst_cells = ("%d" % count, "%d stale (+%d not holder, %d out of order, %d accepted)" % (
        total["rejected_stale"], total["rejected_not_holder"], total["rejected_out_of_order"], total["accepted"]))
    first_arrival = next((h[0] for h in health[base + 1:last + 1] if arrivals(h[1]) > arrivals(health[base][1])), None)
    if first_arrival is not None:
        notes.append("first commands of the burst counted by the robot %.2f s after the link came back"
                     % ((first_arrival - t_up) / 1e9))
    else:
        notes.append("no command reached the robot between link back and its next accepted command")
    h_up = health[base]
    last = health[-1]
    notes.append("at link back: watchdog %d, holder '%s'; at the end: watchdog %d, holder '%s'; counters at the end: %s"
                 % (h_up[2], h_up[3], last[2], last[3],
                    ", ".join("%s=%d" % (k, v) for k, v in sorted(last[1].items()) if v)))
sent_out = [s for s in sent if t_down <= s[0] < t_up]
notes.append("pilot sent %d commands while the link was down (%d in total)" % (len(sent_out), len(sent)))

# ---- motion on stale data, and resumption ----
stale_moves = []
ai = -1
for t, v in drive:
    while ai + 1 < len(accepted) and accepted[ai + 1][0] <= t:
        ai += 1
    if v == 0 or t <= (stopped or t_up) or ai < 0:
        continue
    rx, seq, stamp = accepted[ai]
    if ms(rx - stamp) > max_age_ms or stamp < t_up:
        stale_moves.append((t, v, seq, ms(rx - stamp)))
old_accepted = [a for a in accepted if a[0] >= t_up and a[2] < t_up]
if stale_moves:
    t, v, seq, age = stale_moves[0]
    moved = "YES: %d cycles, first %.2f s after link back at %d mm/s on command %d (%.0f ms old on arrival)" % (
        len(stale_moves), (t - t_up) / 1e9, v, seq, age)
else:
    moved = "no"
if old_accepted:
    notes.append("%d commands stamped before the link came back were ACCEPTED after it (first seq %d, %.0f ms old)"
                 % (len(old_accepted), old_accepted[0][1], ms(old_accepted[0][0] - old_accepted[0][2])))
resumed = next((t for t, v in drive if t > t_up and v > 0 and stopped is not None and t > stopped), None)
resume_cell = "never" if resumed is None else "%.2f" % ((resumed - t_up) / 1e9)
fresh_cmd = next((a for a in accepted if a[0] >= t_up), None)
if fresh_cmd:
    notes.append("first command accepted after link back: %.2f s after it (seq %d, %.0f ms old)"
                 % ((fresh_cmd[0] - t_up) / 1e9, fresh_cmd[1], ms(fresh_cmd[0] - fresh_cmd[2])))
else:
    notes.append("no command was accepted after the link came back")

# ---- operator side: the probe's video and scan ages ----
samples = [x for x in read_trace(os.path.join(run, "probe.csv")) if x[1] <= t_end]
def recovery(topic):
    after = [(rx, rx - st) for tp, rx, st in samples if tp == topic and rx > t_up]
    first = after[0] if after else None
    fresh = next((rx for rx, age in after if age < 200e6), None)
    pre = sorted(rx - st for tp, rx, st in samples if tp == topic and t_down - 3e9 <= rx < t_down)
    return first, fresh, pre, len(after)
left_first, left_fresh, left_pre, left_n = recovery("left")
scan_first, scan_fresh, scan_pre, _ = recovery("scan")
frame_age = "no frame" if left_first is None else "%.0f" % ms(left_first[1])
if not os.path.exists(os.path.join(run, "probe.csv")):
    # PROBE=0: no receive times; count the pilot's frames captured after the link came back.
    pilot_after = sum(1 for tp, st, _ in read_trace(os.path.join(run, "client.csv"))
                      if tp == "left" and t_up < st <= t_end)
    frame_age = "no probe; pilot got %d frames" % pilot_after
frame_fresh = "never" if left_fresh is None else "%.2f" % ((left_fresh - t_up) / 1e9)
if left_first:
    notes.append("first left frame after link back received %.2f s after it; %d left frames after link back"
                 % ((left_first[0] - t_up) / 1e9, left_n))
if left_pre:
    notes.append("before the cut: %d left frames in 3 s, age p50 %.0f ms" % (len(left_pre), ms(left_pre[len(left_pre) // 2])))
if scan_first:
    notes.append("first scan after link back: %.0f ms old, scans fresh (< 200 ms) again after %s"
                 % (ms(scan_first[1]), "never" if scan_fresh is None else "%.2f s" % ((scan_fresh - t_up) / 1e9)))
else:
    notes.append("no scan reached the probe after the link came back")
if status:
    notes.append("process status: " + " ".join(status))
row(outage_s + " s", stop_ms, burst_cells[0], burst_cells[1], moved, resume_cell, frame_age, frame_fresh)
finish()
EOF
}

# A run whose robot never drives (it can hang in DDS discovery at start) is repeated.
attempts=${ATTEMPTS:-3}
for n in $outages; do
  for k in $(seq "$attempts"); do
    run_outage "$n"
    grep -q no_drive "$work/outage_$n/status" 2>/dev/null || break
    [ "$k" = "$attempts" ] || mv "$work/outage_$n" "$work/outage_${n}_failed$k"
  done
done
echo
echo "Outage bench: WAN TCP profile over netem_relay (100 ms RTT, 1 % loss, 8 Mbit/s), pilot at $speed m/s," \
  "test-pattern video $video_hz Hz q$video_quality; measured until $(for n in $outages; do printf '%s s ' "$(post_for "$n")"; done)after the link came back."
echo
echo "| outage | stop time after last command (ms) | commands arriving in the burst after | stale ones rejected | moved on stale data? | driving again after link back (s) | first frame age after link back (ms) | frames fresh (age < 200 ms) again after (s) |"
echo "|---|---|---|---|---|---|---|---|"
for n in $outages; do analyse "$n"; done
echo
for n in $outages; do cat "$work/outage_$n/notes"; done
for n in $outages; do
  for f in "$work/outage_${n}"_failed*; do
    [ -e "$f" ] || continue
    echo "- ${n} s outage: an earlier attempt never drove ($(tr '\n' ' ' < "$f/status")); robot main thread:" \
      "$(sed -n '/^Thread 1 /,/^$/p' "$f/robot_stacks_no_drive.txt" 2>/dev/null | grep -o 'mostar::[A-Za-z:]*' | head -3 | tr '\n' ' ')" \
      "$(grep -q OpenOutputChannel "$f/robot_stacks_no_drive.txt" 2>/dev/null && echo '(a TCP listen thread waits in TCPTransportInterface::OpenOutputChannel -> std::thread::join)')"
  done
done
for n in $outages; do
  echo "--- ${n} s: relay counters"; grep -h "a_to_b\|b_to_a" "$work/outage_$n/netem.log" || true
  echo "--- ${n} s: client"; grep -h "report:\|WARN\|ERROR" "$work/outage_$n/client.log" | tail -5 || true
  echo "--- ${n} s: probe"; grep -h "probe:" "$work/outage_$n/probe.log" || true
  echo "--- ${n} s: TCP connections (robot side first: local peer recv-q send-q timer)"
  sed -n '/^=== link_back/,$p' "$work/outage_$n/ss.txt" 2>/dev/null |
    awk '/^===/{print "   " $2} /^ESTAB/{print "     " $4, $5, $2, $3, $6}' || true
  for f in "$work/outage_$n"/*_stacks_*.txt; do
    [ -e "$f" ] || continue
    # Threads waiting for a lock inside Fast DDS, and the main thread (the robot's control
    # loop, the client's render loop) in short.
    echo "--- ${n} s: $(basename "$f"): $(grep -c '^Thread' "$f") threads," \
      "$(awk '/^Thread/{if (w) n++; w=0} /lll_lock_wait|futex_clocklock|clockjoin/{w=1} END{if (w) n++; print n+0}' "$f")" \
      "waiting on a lock or a thread join; main thread:"
    sed -n '/^Thread 1 /,/^$/p' "$f" | grep -o ' in [^ (]*' | grep -v ' in ??' | head -8 | sed 's/^/   /' || true
  done
done
