#!/usr/bin/env bash
# Observers bench: how the robot's CPU and uplink grow with the number of observers, and how
# each observer is served; directly (every observer subscribes to robot_server) and through one
# mostar_relay (the robot serves the relay, the relay serves the observers on another domain).
# robot_server runs the test pattern with the demo configuration on the loopback profile; N
# net_probe observers (no clock pings) run 10 s each, for N in 1, 4 and 16 (and 0 for the
# robot's baseline). Prints a Markdown table.
#
# Usage: observers_bench.sh ROBOT_SERVER NET_PROBE RELAY SOURCE_DIR
#
# Method:
# - CPU %: utime + stime from /proc/PID/stat over a window that starts 1 s after the last
#   observer was started and lasts 8 s (all observers are running), divided by wall time;
#   one core = 100 %.
# - Per observer: stereo pairs/s = left frames / measured seconds, where net_probe leaves the
#   first second after its first sample out (--warmup-s 1, measured_s); a net_probe without
#   --warmup-s counts everything and the rate is left frames / (10 s - 1 s discovery), as
#   network_bench.sh did. Left-frame age p50 / p95 (receive time - capture stamp, one clock).
#   Min and median over the observers; ages are medians over the observers that got frames.
# - DDS domains: random in 100..198 (the relay's observer side on the next one), skipping
#   domains whose first discovery ports are already bound on this host (another robot).
# - Uplink: the loopback profile carries user data between processes of one host over Fast DDS
#   shared memory (UDP on 127.0.0.1 is for discovery and fallback), so no network interface
#   counter sees the video and there are no per-process network byte counters. The robot's
#   uplink is therefore counted in stereo pairs it sends: directly, the sum of pairs delivered to
#   all observers (one reliable copy per observer); through the relay, the pairs the relay
#   received from the robot (its robot-side reader count, from its 0.5 s statistics). Mbit/s is
#   that rate times the mean JPEG stereo pair size measured once from a 3 s robot_server
#   recording (mostar_record_info next to robot_server in the build tree; "n/a" without it):
#   the payload a network profile would carry, without RTPS/transport headers. Shared memory
#   can hand one buffer to several readers, so the robot's CPU for N direct observers here is a
#   lower bound of what N copies over a network cost.
set -euo pipefail
[ $# -eq 4 ] || { echo "usage: observers_bench.sh ROBOT_SERVER NET_PROBE RELAY SOURCE_DIR" >&2; exit 2; }
robot_server=$1; net_probe=$2; relay=$3; src=$4
for b in "$robot_server" "$net_probe" "$relay"; do
  [ -x "$b" ] || { echo "observers_bench: $b is not an executable" >&2; exit 77; }
done
[ -f "$src/deploy/config/server_sim.pbtxt" ] || { echo "observers_bench: no $src/deploy" >&2; exit 77; }
for t in awk timeout date getconf; do
  command -v "$t" > /dev/null || { echo "observers_bench: $t is missing" >&2; exit 77; }
done
record_info="$(dirname "$robot_server")/../common/record/mostar_record_info"
warmup_flag=()
if "$net_probe" --help 2>/dev/null | grep -q -- --warmup-s; then warmup_flag=(--warmup-s 1); fi

work=$(mktemp -d /tmp/mostar_observers_XXXXXX); pids=()
stop_all() { for p in "${pids[@]}"; do kill "$p" 2>/dev/null || true; done
             for p in "${pids[@]}"; do wait "$p" 2>/dev/null || true; done; pids=(); }
cleanup() { stop_all; rm -rf "$work"; }
trap cleanup EXIT
trap "exit 1" INT TERM
seconds=10; window=8; hz=$(getconf CLK_TCK)
sed -e "s|scene_file: \"\.\./|scene_file: \"$src/deploy/|" \
    "$src/deploy/config/server_sim.pbtxt" > "$work/server.pbtxt"

cpu_ticks() { sed 's/.*) //' "/proc/$1/stat" | awk '{ print $12 + $13 }'; }  # utime + stime
now_s() { date +%s.%N; }
# True when the metatraffic unicast ports of participant ids 0..3 of DDS domain $1
# (7400 + 250 * domain + 10 + 2 * id) are free on this host.
domain_free() {
  local id port
  for id in 0 1 2 3; do
    port=$(printf '%04X' $((7400 + 250 * $1 + 10 + 2 * id)))
    if awk -v p=":$port" 'substr($2, length($2) - 4) == p { found = 1 } END { exit !found }' \
         /proc/net/udp /proc/net/udp6 2>/dev/null; then return 1; fi
  done
}
pick_domain() {  # a random domain d in 100..198 with d and d + 1 free
  local d _
  for _ in $(seq 50); do
    d=$((100 + RANDOM % 99))
    if domain_free "$d" && domain_free $((d + 1)); then echo "$d"; return; fi
  done
  echo "$d"
}
median() { sort -n | awk '{ v[NR] = $1 } END { if (NR == 0) print "n/a";
  else if (NR % 2) print v[(NR + 1) / 2]; else printf "%.1f\n", (v[NR / 2] + v[NR / 2 + 1]) / 2 }'; }
# Left-camera count of the relay's robot-side reader and its log time (s), from the last
# statistics line logged so far: "I <ISO time> relay_main.cc:..] relay <topic>left..: in=N ...".
relay_in() {
  local line; line=$(grep 'camera/left.*: in=' "$work/relay.err" | tail -n 1 || true)
  [ -n "$line" ] || { echo "0 $(now_s)"; return; }
  echo "$(echo "$line" | sed -n 's/.* in=\([0-9]*\).*/\1/p') $(date -d "$(echo "$line" | awk '{ print $2 }')" +%s.%N)"
}

# Mean JPEG stereo pair size (bytes) from a short recording of the same configuration.
pair_bytes=""
if [ -x "$record_info" ]; then
  "$robot_server" --domain "$(pick_domain)" --config "$work/server.pbtxt" \
    --source test_pattern --duration 3 --record "$work/size.mrec" > "$work/size.log" 2>&1 &
  pids+=($!); wait "${pids[0]}" || true; pids=()
  pair_bytes=$("$record_info" "$work/size.mrec" 2>/dev/null | awk '
    function bytes(v, u) { return v * (u == "KiB" ? 1024 : u == "MiB" ? 1048576 : 1) }
    $1 == "camera/left" || $1 == "camera/right" { s += bytes($(NF - 3), $(NF - 2)); n++ }
    END { if (n == 2) printf "%.0f\n", s }' || true)
fi

row() {  # path (direct | relay), number of observers
  local path=$1 n=$2 domain obs_domain relay_pid=""
  domain=$(pick_domain)
  obs_domain=$domain
  "$robot_server" --domain "$domain" --config "$work/server.pbtxt" --source test_pattern \
    > "$work/robot.log" 2>&1 &
  local robot_pid=$!; pids+=("$robot_pid")
  sleep 1
  if [ "$path" = relay ]; then
    obs_domain=$((domain + 1))
    "$relay" --robot-domain "$domain" --observer-domain "$obs_domain" --stats-period-s 0.5 \
      > "$work/relay.out" 2> "$work/relay.err" &
    relay_pid=$!; pids+=("$relay_pid")
    sleep 2
  fi
  local i
  rm -f "$work"/probe*.out
  for ((i = 1; i <= n; i++)); do
    timeout $((seconds + 30)) "$net_probe" --domain "$obs_domain" --id "observer$i" \
      --duration-s "$seconds" --no-ping "${warmup_flag[@]}" > "$work/probe$i.out" 2>&1 &
    pids+=($!)
  done
  sleep 1
  if ! kill -0 "$robot_pid" 2>/dev/null ||
     { [ -n "$relay_pid" ] && ! kill -0 "$relay_pid" 2>/dev/null; }; then
    local who=relay log="$work/relay.err" dead=$relay_pid rc=0
    if ! kill -0 "$robot_pid" 2>/dev/null; then who=robot_server; log="$work/robot.log"; dead=$robot_pid; fi
    wait "$dead" || rc=$?
    { echo "observers_bench: $who exited early (status $rc):"; tail -n 5 "$log"; } >&2
    stop_all
    printf '| %s | %s | %s exited early (status %s), no result | | | | | |\n' "$path" "$n" "$who" "$rc"
    return
  fi
  local t0 r0 l0="" t1 r1 l1="" in0=0 it0=0 in1=0 it1=0
  t0=$(now_s); r0=$(cpu_ticks "$robot_pid")
  [ -z "$relay_pid" ] || { l0=$(cpu_ticks "$relay_pid"); read -r in0 it0 < <(relay_in); }
  sleep "$window"
  t1=$(now_s); r1=$(cpu_ticks "$robot_pid")
  [ -z "$relay_pid" ] || { l1=$(cpu_ticks "$relay_pid"); read -r in1 it1 < <(relay_in); }
  # Observers finish on their own; then the robot (and relay) are stopped.
  for p in "${pids[@]:$(( ${#pids[@]} - n ))}"; do wait "$p" 2>/dev/null || true; done
  stop_all
  local robot_cpu relay_cpu="-"
  cpu() { awk -v a="$1" -v b="$2" -v t0="$t0" -v t1="$t1" -v hz="$hz" \
            'BEGIN { printf "%.0f", 100 * (b - a) / hz / (t1 - t0) }'; }
  robot_cpu=$(cpu "$r0" "$r1")
  [ -z "$relay_pid" ] || relay_cpu=$(cpu "$l0" "$l1")
  local rates="" p50s="" p95s="" hung=0 line left measured
  for ((i = 1; i <= n; i++)); do
    line=$(grep '^probe:' "$work/probe$i.out" || true)
    if [ -z "$line" ]; then hung=$((hung + 1)); rates+="0"$'\n'; continue; fi
    f() { echo "$line" | sed -n "s/.* $1=\([^ ]*\).*/\1/p"; }
    left=$(echo "$line" | sed -n 's/^probe: left=\([0-9]*\).*/\1/p')
    measured=$(f measured_s); [ -n "$measured" ] || measured=$((seconds - 1))
    rates+=$(awk -v c="$left" -v s="$measured" \
               'BEGIN { printf "%.2f", (s > 0 ? c / s : 0) }')$'\n'
    if [ "$left" -gt 0 ]; then p50s+="$(f left_age_p50_ms)"$'\n'; p95s+="$(f left_age_p95_ms)"$'\n'; fi
  done
  local per_obs="-" ages="-" total="-" sends
  if [ "$n" -gt 0 ]; then
    per_obs=$(printf '%.1f / %.1f' "$(printf '%s' "$rates" | sort -n | head -n 1)" \
                                   "$(printf '%s' "$rates" | median)")
    ages="$(printf '%s' "$p50s" | median) / $(printf '%s' "$p95s" | median)"
    total=$(printf '%s' "$rates" | awk '{ s += $1 } END { printf "%.1f", s }')
    [ "$hung" -eq 0 ] || per_obs+=" ($hung without result)"
  fi
  if [ "$path" = relay ]; then
    sends=$(awk -v a="$in0" -v b="$in1" -v ta="$it0" -v tb="$it1" \
              'BEGIN { if (tb > ta) printf "%.1f", (b - a) / (tb - ta); else print "n/a" }')
  elif [ "$n" -gt 0 ]; then sends=$total; else sends=0; fi
  local mbit="n/a"
  if [ -n "$pair_bytes" ] && [ "$sends" != n/a ]; then
    mbit=$(awk -v r="$sends" -v b="$pair_bytes" 'BEGIN { printf "%.1f", r * b * 8 / 1e6 }')
  fi
  printf '| %s | %s | %s | %s | %s | %s | %s | %s (%s) |\n' "$path" "$n" "$robot_cpu" \
    "$relay_cpu" "$per_obs" "$ages" "$total" "$sends" "$mbit"
}

echo "| path | observers | robot CPU % | relay CPU % | pairs/s per observer (min / median) | left age p50 / p95 ms (median over observers) | total pairs/s delivered | pairs/s the robot sends (≈ Mbit/s) |"
echo "|---|---|---|---|---|---|---|---|"
row direct 0
for n in 1 4 16; do row direct "$n"; done
for n in 1 4 16; do row relay "$n"; done
if [ -n "$pair_bytes" ]; then
  echo; echo "Mean JPEG stereo pair: $(awk -v b="$pair_bytes" 'BEGIN { printf "%.1f", b / 1024 }') KiB (test pattern, from a robot_server recording)."
fi
