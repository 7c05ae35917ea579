#!/usr/bin/env bash
# Operator-side latency on loopback: robot_server (simulated robot at 640x480 or 1280x960, or the
# test pattern) and a headless operator_client under Xvfb/llvmpipe. Prints two tables: the delivered pair rate,
# capture-to-display age and render time (p50/p95); then the capture-to-screen latency trace,
# stage by stage (p50 / p95 ms of each stage since the one before, the total capture to
# presented, and what no stamp explains), one column per run.
#
#   tests/bench/client_latency_bench.sh [BUILD_DIR] [SECONDS]
set -euo pipefail
cd "$(dirname "$0")/../.."
BUILD_DIR=${1:-build}
SECONDS_RUN=${2:-15}
DOMAIN=$((150 + $$ % 50))
STAGES=(encoded written received decoded picked vision drawn presented total unexplained)
declare -a reports=() labels=()
printf '| source | display | pairs/s | age p50 ms | age p95 ms | render p50 ms | render p95 ms |\n'
printf '|---|---|---|---|---|---|---|\n'
# Rows: source (test_pattern, sim at 640x480, sim_1280: the simulator at the cameras' native
# 1280x960, shown in the client's 640x480 window, so decoded at 1/2) x display mode.
for source in test_pattern sim sim_1280; do
  for display in mono-left anaglyph-color; do
    args=(--domain "$DOMAIN" --config deploy/config/server_sim.pbtxt)
    [ "$source" = test_pattern ] && args+=(--source test_pattern)
    [ "$source" = sim_1280 ] && args=(--domain "$DOMAIN" --config deploy/config/server_sim_1280.pbtxt)
    "$BUILD_DIR/robot_server/robot_server" "${args[@]}" --log-level warning &
    server=$!
    sleep 2
    report=$(xvfb-run -a -s "-screen 0 1280x1024x24 -noreset" \
      "$BUILD_DIR/operator_client/operator_client" --headless --domain "$DOMAIN" \
      --config deploy/config/client_sim.pbtxt --role observer --id observer \
      --display "$display" --duration "$SECONDS_RUN" --log-level warning | grep '^report:')
    kill -TERM "$server"; wait "$server" || true
    get() { echo "$report" | tr ' ' '\n' | grep "^$1=" | cut -d= -f2; }
    printf '| %s | %s | %.1f | %.1f | %.1f | %.1f | %.1f |\n' "$source" "$display" \
      "$(get pair_rate_hz_last_2s)" "$(get display_age_ms_p50)" "$(get display_age_ms_p95)" \
      "$(get frame_time_ms_p50)" "$(get frame_time_ms_p95)"
    reports+=("$report")
    labels+=("$source $display")
  done
done
echo
header='| stage (ms, p50 / p95) |'
rule='|---|'
for label in "${labels[@]}"; do header+=" $label |"; rule+='---|'; done
echo "$header"
echo "$rule"
for stage in "${STAGES[@]}"; do
  line="| $stage |"
  for report in "${reports[@]}"; do
    p50=$(echo "$report" | tr ' ' '\n' | grep "^latency_${stage}_ms_p50=" | cut -d= -f2)
    p95=$(echo "$report" | tr ' ' '\n' | grep "^latency_${stage}_ms_p95=" | cut -d= -f2)
    line+=$(printf ' %.1f / %.1f |' "${p50:-0}" "${p95:-0}")
  done
  echo "$line"
done
