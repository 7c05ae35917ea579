#!/usr/bin/env bash
# Operator-side latency on loopback: robot_server and a headless operator_client under
# Xvfb/llvmpipe. Prints two tables: per run configuration the delivered pair rate, the
# capture-to-display age, the pairs dropped, the edge results' timing and the load average; then
# the capture-to-screen latency trace, stage by stage (p95 ms of each stage since the one before,
# the total capture to presented) and `drawn` by part (overlay geometry, eyes, compositor,
# panels), one column per configuration. With RUNS > 1 every cell is
# the median of the runs' values with their range.
#
#   tests/bench/client_latency_bench.sh [BUILD_DIR] [SECONDS]
#
# Sources (SOURCES, space separated):
#   camera       a camera-like source: 20 s of the simulator at 640x480 with a pilot driving a
#                curve, recorded before the runs; each run replays it in a loop through the live
#                camera pipeline (--replay-sensors: recorded JPEGs decoded like a camera's
#                readout, then compressed as captured), so no scene is rendered during the run;
#                each pair enters the pipeline at its capture stamp (deliver_at_capture_time)
#   camera_1280  the same at the cameras' native 1280x960, shown in the 640x480 window
#   test_pattern the server's test pattern (a control row: the cheapest source)
#   sim, sim_1280  the simulator rendering the scene during the run (its CPU renderer shares
#                the 2 cores: `encoded` holds the rendering)
# DISPLAYS: display modes (mono-left, anaglyph-color, ...), and "probe": no console but a
# net_probe (tests/network), whose age is capture to received: what the robot side and the
# transport cost on this machine without the console's CPU. VISION: "on off" (edge processing;
# a probe row runs once, as "-").
# EXTRA: other readers of the same robot during every run: "observers" (two net_probe
# observers: the robot writes each video sample to them too) and/or "web" (mostar_web with one
# WebSocket reader, tests/web/web_reader.py; WEB_EDGES: its --edges, default the configuration's:
# on); their own delivery is printed in the first table.
# RUNS: runs per configuration (the client's trace leaves out its first 2 s of pairs: the
# warm-up). CLIENT: another operator_client binary to time instead of BUILD_DIR's (A/B against
# an older build).
set -euo pipefail
cd "$(dirname "$0")/../.."
src=$PWD
BUILD_DIR=${1:-build}
SECONDS_RUN=${2:-20}
SOURCES=${SOURCES:-camera camera_1280 test_pattern}
DISPLAYS=${DISPLAYS:-mono-left anaglyph-color}
VISION=${VISION:-on off}
RUNS=${RUNS:-1}
EXTRA=${EXTRA:-}
WEB_EDGES=${WEB_EDGES:-config}
CLIENT=${CLIENT:-$BUILD_DIR/operator_client/operator_client}
SERVER=$BUILD_DIR/robot_server/robot_server
DOMAIN=$((150 + $$ % 50))
STAGES=(encoded written received queued decoded picked vision started drawn presented total)
PARTS=(overlay eyes compose panels)  # `drawn` by part (the console's FrameParts)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# Client configurations with edge processing on and off (absolute calibration path).
sed -e 's|^calibration_profile: .*||' deploy/config/client_sim.pbtxt > "$work/client_on.pbtxt"
sed -e 's|^vision_enabled: true|vision_enabled: false|' "$work/client_on.pbtxt" \
  > "$work/client_off.pbtxt"
calibration=(--calibration "$src/deploy/config/calibration_sim.pbtxt")

# Records the camera-like source for server config $1 into $2.
record_source() {
  local config=$1 out=$2 domain=$((DOMAIN + 1))
  sed -e "s|scene_file: \"\.\./|scene_file: \"$src/deploy/|" "$config" > "$work/record.pbtxt"
  "$SERVER" --domain "$domain" --config "$work/record.pbtxt" --record "$out" --duration 24 \
    --log-level warning > "$work/record_server.log" 2>&1 &
  local server=$!
  xvfb-run -a "$CLIENT" --headless --domain "$domain" --id operator --role pilot --duration 22 \
    --drive 0.25,0.35 --no-hud "${calibration[@]}" --log-level warning \
    > "$work/record_client.log" 2>&1 || true
  wait "$server" || true
  [ -s "$out" ] || { echo "bench: recording $config failed" >&2; cat "$work/record_server.log" >&2; exit 1; }
}

server_args() {  # the robot_server arguments of source $1
  case $1 in
    camera) echo "--config $work/replay_640.pbtxt --replay-sensors $work/camera_640.mrec --loop" ;;
    camera_1280) echo "--config $work/replay_1280.pbtxt --replay-sensors $work/camera_1280.mrec --loop" ;;
    test_pattern) echo "--config deploy/config/server_sim.pbtxt --source test_pattern" ;;
    sim) echo "--config deploy/config/server_sim.pbtxt" ;;
    sim_1280) echo "--config deploy/config/server_sim_1280.pbtxt" ;;
    *) echo "bench: unknown source $1" >&2; exit 2 ;;
  esac
}

# The replays deliver each pair at its capture stamp (not when it was recorded), so `encoded`
# holds the live pipeline only (CAPTURE_TIME=0: as recorded, the recording's own
# capture-to-log time included).
for size in 640 1280; do
  config=deploy/config/server_sim.pbtxt
  [ "$size" = 640 ] || config=deploy/config/server_sim_1280.pbtxt
  sed -e "s|scene_file: \"\.\./|scene_file: \"$src/deploy/|" "$config" > "$work/replay_$size.pbtxt"
  if [ "${CAPTURE_TIME:-1}" = 1 ]; then
    printf 'camera { replay { deliver_at_capture_time: true } }\n' >> "$work/replay_$size.pbtxt"
  fi
done
for source in $SOURCES; do
  [ "$source" = camera ] && record_source deploy/config/server_sim.pbtxt "$work/camera_640.mrec"
  [ "$source" = camera_1280 ] && record_source deploy/config/server_sim_1280.pbtxt "$work/camera_1280.mrec"
done

# mostar_web's TLS certificate and an observer token (EXTRA=web).
if [[ " $EXTRA " == *" web "* ]]; then
  openssl req -x509 -newkey ec -pkeyopt ec_paramgen_curve:prime256v1 -nodes -keyout "$work/web.key" \
    -out "$work/web.cert" -days 1 -subj /CN=localhost \
    -addext "subjectAltName=DNS:localhost,IP:127.0.0.1" > /dev/null 2>&1
  web_token=bench-token-0123456789abcdef
  echo "bench $web_token" > "$work/web.tokens"
fi

# Starts the EXTRA readers for a run of the robot on $DOMAIN; their pids in extra_pids.
start_extra() {
  extra_pids=()
  if [[ " $EXTRA " == *" observers "* ]]; then
    for i in 1 2; do
      "$BUILD_DIR/tests/network/net_probe" --domain "$DOMAIN" --id "probe$i" \
        --duration-s "$((SECONDS_RUN + 2))" --warmup-s 2 > "$work/probe$i.out" 2>&1 &
      extra_pids+=($!)
    done
  fi
  if [[ " $EXTRA " == *" web "* ]]; then
    "$BUILD_DIR/operator_client/web/mostar_web" --domain "$DOMAIN" \
      --config deploy/config/client_sim.pbtxt --cert "$work/web.cert" --key "$work/web.key" \
      --tokens "$work/web.tokens" --port 0 --edges "$WEB_EDGES" --log-level warning > "$work/web.out" 2> "$work/web.log" &
    web_pid=$!
    local port=""
    for _ in $(seq 100); do
      port=$(grep -o 'serving https://[^ ]*' "$work/web.out" | sed -e 's|.*:\([0-9]*\)/.*|\1|' || true)
      [ -z "$port" ] || break
      sleep 0.1
    done
    python3 tests/web/web_reader.py "$port" "$work/web.cert" "$web_token" \
      --seconds "$SECONDS_RUN" > "$work/web_reader.out" 2>&1 &
    extra_pids+=($!)
  fi
}

# Waits for the EXTRA readers; prints their delivery as report keys.
stop_extra() {
  local pid i
  for pid in "${extra_pids[@]}"; do wait "$pid" || true; done
  if [[ " $EXTRA " == *" observers "* ]]; then
    for i in 1 2; do
      echo -n " observer${i}_pairs_per_s=$(grep '^probe:' "$work/probe$i.out" | tr ' ' '\n' \
        | grep '^left=' | cut -d= -f2 | awk -v s="$SECONDS_RUN" '{ printf "%.1f", $1 / s }')"
    done
  fi
  if [[ " $EXTRA " == *" web "* ]]; then
    kill -TERM "$web_pid" 2>/dev/null; wait "$web_pid" || true
    echo -n " web_$(grep '^web:' "$work/web_reader.out" | sed -e 's/^web: //' -e 's/ / web_/g')"
  fi
}

# One run: prints the client's report line with the load average before the run appended.
run_once() {
  local source=$1 display=$2 vision=$3 load server report extra
  read -r load _ < /proc/loadavg
  # shellcheck disable=SC2046
  "$SERVER" --domain "$DOMAIN" $(server_args "$source") --log-level warning > "$work/server.log" 2>&1 &
  server=$!
  sleep 2
  start_extra
  if [ "$display" = probe ]; then
    # The probe's ages as the console's keys (the console's stages stay empty).
    report=$("$BUILD_DIR/tests/network/net_probe" --domain "$DOMAIN" --duration-s "$SECONDS_RUN" \
      --warmup-s 2 | grep '^probe:' | sed -e 's/left_age_p50_ms=/display_age_ms_p50=/' \
      -e 's/left_age_p95_ms=/display_age_ms_p95=/' || true)
    report+=" pairs_per_s_run=$(echo "$report" | tr ' ' '\n' | grep '^left=' | cut -d= -f2 \
      | awk -v s="$SECONDS_RUN" '{ printf "%.1f", $1 / (s - 2) }')"  # after the warm-up
  else
    report=$(xvfb-run -a -s "-screen 0 1280x1024x24 -noreset" \
      "$CLIENT" --headless --domain "$DOMAIN" --config "$work/client_$vision.pbtxt" \
      "${calibration[@]}" --role observer --id observer --display "$display" \
      --duration "$SECONDS_RUN" --log-level warning | grep '^report:' || true)
  fi
  stop_extra > "$work/extra.keys"
  extra=$(cat "$work/extra.keys")
  kill -TERM "$server" 2>/dev/null; wait "$server" || true
  echo "$report$extra load_avg_1m=$load"
}

# Median [min-max] of the numbers on stdin, formatted with one decimal.
summary() {
  sort -g | awk '{ v[NR] = $1 } END {
    if (NR == 0) { printf "-"; exit }
    m = (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2
    if (NR == 1) printf "%.1f", m; else printf "%.1f [%.1f-%.1f]", m, v[1], v[NR] }'
}
get() { tr ' ' '\n' | { grep "^$1=" || true; } | cut -d= -f2; }  # key $1 of the reports on stdin

declare -a labels=() results=()
printf '| source | display | vision | pairs/s | age p50 ms | age p95 ms | dropped | results in time / late | load | extra readers: pairs/s (age p95 ms) |\n'
printf '|---|---|---|---|---|---|---|---|---|---|\n'
for source in $SOURCES; do
  for display in $DISPLAYS; do
    visions=$VISION
    [ "$display" != probe ] || visions=-
    for vision in $visions; do
      reports=""
      for _ in $(seq "$RUNS"); do
        reports+="$(run_once "$source" "$display" "$vision")"$'\n'
      done
      col() { echo "$reports" | get "$1" | summary; }
      late=$(echo "$reports" | get vision_without_result | awk '{ s += $1 } END { print s + 0 }')
      in_time=$(echo "$reports" | get vision_in_time | awk '{ s += $1 } END { print s + 0 }')
      extra="-"
      [ -z "$EXTRA" ] || extra="observers $(col observer1_pairs_per_s), $(col observer2_pairs_per_s); web $(col web_frames_per_s) ($(col web_age_p95_ms))"
      printf '| %s | %s | %s | %s | %s | %s | %s | %s / %s | %s | %s |\n' "$source" "$display" "$vision" \
        "$(col pairs_per_s_run)" "$(col display_age_ms_p50)" "$(col display_age_ms_p95)" \
        "$(col pairs_dropped)" "$in_time" "$late" "$(col load_avg_1m)" "$extra"
      labels+=("$source $display vision $vision")
      results+=("$reports")
    done
  done
done
echo
header='| stage (p95 ms) |'
rule='|---|'
for label in "${labels[@]}"; do header+=" $label |"; rule+='---|'; done
echo "$header"
echo "$rule"
# One row per name: label $1 + name, the key "$2<name>_ms_p95" of every configuration.
rows() {
  local label=$1 key=$2 name line reports
  shift 2
  for name in "$@"; do
    line="| $label$name |"
    for reports in "${results[@]}"; do
      line+=" $(echo "$reports" | get "$key${name}_ms_p95" | summary) |"
    done
    echo "$line"
  done
}
rows "" latency_ "${STAGES[@]}"
rows "drawn: " part_ "${PARTS[@]}"
