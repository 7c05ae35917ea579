#!/usr/bin/env bash
# Bitrate step bench: the video follows a link whose capacity changes (a cellular hand-over).
#
# robot_server (simulator video, 30 Hz) in the robot namespace and a headless operator_client
# pilot in the operator namespace talk over the WAN UDP profile through netem_relay (50 ms
# one-way, 5 ms jitter, no loss) whose bottleneck steps through RATES (kbit/s), PHASE_S seconds
# each. The robot's bitrate controller has no configured target (class `lan`): it learns the
# link from the ack-clock alone. With CODEC=h264 the robot sends the H.264 streams instead
# (deploy/config/server_sim_h264.pbtxt, class `lan`: no target, up to 16 Mbit/s) and follows the
# link from the pilot's receive reports (LinkRateController). All programs share this
# machine's clock, so the pilot's trace (arrival and capture stamp of every left frame) gives
# each frame's age directly.
#
# Printed: per phase, the stereo pairs/s and the age p50/p95 from 2 s after the step to the end
# of the phase, the largest age in the phase, and the settle time (step -> the first 1 s bin
# after which every bin has age p95 <= one-way + 100 ms), the stale time (seconds of the phase
# during which the newest picture the pilot holds is older than one-way + 150 ms: the issue's
# goal is at most 1 s after a step) and the uplink used (IP bytes the relay
# delivered robot -> operator, everything the robot sends, from 2 s after the step, against the
# link's capacity); then the bins, one per second.
#
# Usage: bitrate_step_bench.sh ROBOT_SERVER OPERATOR_CLIENT NETEM_RELAY SOURCE_DIR
# Environment: RATES ("8000 2000 8000"), PHASE_S (20), CODEC (jpeg or h264), LOSS (packet loss
# probability each way, 0), REPAIR_DEADLINE_MS (h264: the robot's dds.video_repair_deadline_ms,
# or "auto": dds.video_repair_deadline_auto; unset: the configuration's), RATE_TRACE=1 (the robot logs its rate control every 100 ms at
# debug level), CAPTURE=1 (netem_relay records the uplink; then the uplink per phase by RTPS
# stream: video, repairs, other data, discovery, control), KEEP_WORK=1 keeps the traces and
# logs.
# Needs root (network namespaces, TUN), xvfb-run and python3; exit 77 (skipped) without them.
set -euo pipefail
[ $# -eq 4 ] || {
  echo "usage: bitrate_step_bench.sh ROBOT_SERVER OPERATOR_CLIENT NETEM_RELAY SOURCE_DIR" >&2
  exit 2
}
robot_server=$1; operator_client=$2; netem_relay=$3; src=$(cd "$4" && pwd)
here=$(cd "$(dirname "$0")" && pwd)
source "$here/lib.sh"
command -v xvfb-run >/dev/null || { echo "bitrate_step_bench: xvfb-run is missing" >&2; exit 77; }
command -v python3 >/dev/null || { echo "bitrate_step_bench: python3 is missing" >&2; exit 77; }
read -r -a rates <<< "${RATES:-8000 2000 8000}"
phase_s=${PHASE_S:-20}
lead_s=8  # the robot and the pilot start and discover each other before the first phase
net_setup bitrate
rns="${prefix}_robot"; ons="${prefix}_operator"

# Only the emulated path: UDP participants announce every interface address.
sed "s/203\.0\.113\.10/10.232.0.1/g" "$src/deploy/dds/wan_udp.xml" > "$work/wan.xml"
ip -n "$rns" link set veth0 down
ip -n "$ons" link set veth0 down
codec=${CODEC:-jpeg}
case $codec in
  jpeg) server_config=server_sim.pbtxt ;;
  h264) server_config=server_sim_h264.pbtxt ;;
  *) echo "bitrate_step_bench: CODEC must be jpeg or h264" >&2; exit 2 ;;
esac
sed -e "s|scene_file: \"\.\./|scene_file: \"$src/deploy/|" \
  -e 's/initial_class: "wan"/initial_class: "lan"/' \
  "$src/deploy/config/$server_config" > "$work/server.pbtxt"
if [ "${REPAIR_DEADLINE_MS:-}" = auto ]; then
  echo "dds { video_repair_deadline_auto: true }" >> "$work/server.pbtxt"
elif [ -n "${REPAIR_DEADLINE_MS:-}" ]; then
  echo "dds { video_repair_deadline_ms: $REPAIR_DEADLINE_MS }" >> "$work/server.pbtxt"
fi

steps=""; at=$lead_s
for ((i = 1; i < ${#rates[@]}; i++)); do
  at=$((at + phase_s)); steps+="${steps:+,}$at:${rates[$i]}"
done
total=$((lead_s + phase_s * ${#rates[@]}))
domain=$((100 + RANDOM % 100))
"$netem_relay" --netns-a "$rns" --netns-b "$ons" --delay-ms 50 --jitter-ms 5 --loss "${LOSS:-0}" \
  --rate-kbit "${rates[0]}" ${steps:+--rate-steps "$steps"} --duration-s $((total + 30)) \
  --usage-csv "$work/usage.csv" ${CAPTURE:+--capture-a-to-b "$work/uplink.pcap"} \
  > "$work/netem.log" 2>&1 &
netem_pid=$!; pids+=("$netem_pid")
for _ in $(seq 50); do grep -q ready "$work/netem.log" && break; sleep 0.1; done
grep -q ready "$work/netem.log" || { cat "$work/netem.log" >&2; exit 1; }
start_ns=$(date +%s%N)  # the relay's clock for --rate-steps starts with "ready"

ip netns exec "$rns" "$robot_server" --domain "$domain" --dds-profile "$work/wan.xml" --insecure \
  --config "$work/server.pbtxt" --source sim ${RATE_TRACE:+--log-level debug} \
  > "$work/server.log" 2>&1 &
pids+=($!)
ip netns exec "$ons" xvfb-run -a -s "-screen 0 1920x1080x24 -noreset" "$operator_client" \
  --headless --domain "$domain" --dds-profile "$work/wan.xml" --insecure --id operator --role pilot \
  --duration $((total - 1)) --calibration "$src/deploy/config/calibration_sim.pbtxt" \
  --trace "$work/client.csv" > "$work/client.log" 2>&1 &
client_pid=$!; pids+=("$client_pid")
wait "$client_pid" || true
kill -TERM "$netem_pid" 2>/dev/null || true  # it prints its counters as it stops
wait "$netem_pid" 2>/dev/null || true

echo "bitrate_step_bench: $codec, link ${rates[*]} kbit/s, ${phase_s} s each, 50 ms one-way, loss ${LOSS:-0}${REPAIR_DEADLINE_MS:+, repair deadline $REPAIR_DEADLINE_MS}; $(nproc) cores, load $(cut -d' ' -f1 /proc/loadavg)"
python3 - "$work/client.csv" "$work/usage.csv" "$start_ns" "$lead_s" "$phase_s" "${rates[@]}" <<'EOF'
import sys
path, usage_path = sys.argv[1], sys.argv[2]
start_ns, lead_s, phase_s = int(sys.argv[3]), float(sys.argv[4]), float(sys.argv[5])
rates = [float(r) for r in sys.argv[6:]]
uplink = {}  # second since the relay started -> robot-to-operator kbit (IP bytes delivered)
for line in list(open(usage_path))[1:]:
    second, a_to_b, _ = line.strip().split(',')
    uplink[int(second)] = float(a_to_b)
one_way_s, settled_age_s = 0.05, 0.05 + 0.1
frames = []  # (seconds since the relay started, age in s)
for line in open(path):
    parts = line.strip().split(',')
    if len(parts) >= 3 and parts[0] == 'left_rx':
        arrival, capture = int(parts[1]), int(parts[2])
        frames.append(((arrival - start_ns) / 1e9, (arrival - capture) / 1e9))
def pct(values, p):
    values = sorted(values)
    return values[min(len(values) - 1, int(len(values) * p / 100))] if values else float('nan')
frames.sort()
newest = []  # (arrival, newest capture held so far) in arrival order: the picture shown
for t, age in frames:
    newest.append((t, max(t - age, newest[-1][1] if newest else t - age)))
def stale_seconds(t0, t1, limit_s):
    # Seconds in [t0, t1) during which the newest frame held is older than limit_s (1 ms steps).
    seconds, i, held = 0.0, 0, None
    for k in range(int((t1 - t0) * 1000)):
        t = t0 + k / 1000
        while i < len(newest) and newest[i][0] <= t:
            held = newest[i][1]
            i += 1
        if held is None or t - held > limit_s:
            seconds += 0.001
    return seconds
print("| phase | link Mbit/s | pairs/s | age p50 ms | age p95 ms | age max ms | settle s | "
      "stale s | uplink used |")
print("|---|---|---|---|---|---|---|---|---|")
bins = []
for i, rate in enumerate(rates):
    t0 = lead_s + i * phase_s
    phase = [(t, a) for t, a in frames if t0 <= t < t0 + phase_s]
    settled = [a for t, a in phase if t >= t0 + 2]
    settle = None
    phase_bins = []
    for b in range(int(phase_s)):
        ages = [a for t, a in phase if t0 + b <= t < t0 + b + 1]
        phase_bins.append((t0 + b, rate, len(ages), pct(ages, 50), pct(ages, 95),
                           uplink.get(int(t0 + b), 0.0)))
    for b in range(len(phase_bins)):
        if all(n > 0 and p95 <= settled_age_s for _, _, n, _, p95, _ in phase_bins[b:]):
            settle = b
            break
    bins += phase_bins
    print(f"| {i + 1} | {rate / 1000:.0f} | {len(settled) / (phase_s - 2):.1f} | "
          f"{pct(settled, 50) * 1e3:.0f} | {pct(settled, 95) * 1e3:.0f} | "
          f"{max((a for _, a in phase), default=float('nan')) * 1e3:.0f} | "
          f"{'never' if settle is None else settle} | "
          f"{stale_seconds(t0, min(t0 + phase_s, frames[-1][0]), one_way_s + 0.15):.2f} | "
          f"{sum(u for _, _, _, _, _, u in phase_bins[2:]) / (len(phase_bins) - 2) / rate:.0%} |")
print()
print("second,link_kbit,pairs,age_p50_ms,age_p95_ms,uplink_kbit")
for t, rate, n, p50, p95, used in bins:
    print(f"{t:.0f},{rate:.0f},{n},{p50 * 1e3:.0f},{p95 * 1e3:.0f},{used:.0f}")
EOF
# What the loss cost: the pilot's gaps, keyframe requests and stale time, the relay's drops.
echo
echo "pilot: $(grep -o -E '(video_frames|video_gaps|video_errors|keyframe_requests)=[0-9]+' "$work/client.log" | tail -4 | tr '\n' ' ')"
echo "netem_relay: $(grep -o -E '(lost|queue_drops)=[0-9]+' "$work/netem.log" | tail -4 | tr '\n' ' ')"
if [ -n "${CAPTURE:-}" ]; then
  # What the uplink carried in each phase (from 2 s after its step), by RTPS stream.
  echo
  echo "uplink by stream, kbit/s (tests/network/rtps_usage.py):"
  for ((i = 0; i < ${#rates[@]}; i++)); do
    from=$((lead_s + i * phase_s + 2)); to=$((lead_s + (i + 1) * phase_s))
    python3 "$src/tests/network/rtps_usage.py" --origin "$((start_ns / 1000000000)).$(printf '%09d' $((start_ns % 1000000000)))" \
      --from-s "$from" --to-s "$to" --bin-s "$((to - from))" "$work/uplink.pcap" |
      awk -v phase=$((i + 1)) -v rate="${rates[$i]}" -F, \
        'NR == 1 { header = $0 } /^total/ { print "phase " phase " (" rate " kbit/s): " header; print "  " $0 } /^share/ { print "  " $0 }'
  done
fi
