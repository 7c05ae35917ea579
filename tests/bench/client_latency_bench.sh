#!/usr/bin/env bash
# Operator-side latency on loopback: robot_server (simulated robot or test pattern) and a
# headless operator_client under Xvfb/llvmpipe; prints a table of the delivered pair rate, the
# capture-to-display age and the client's render time (p50/p95).
#
#   tests/bench/client_latency_bench.sh [BUILD_DIR] [SECONDS]
set -euo pipefail
cd "$(dirname "$0")/../.."
BUILD_DIR=${1:-build}
SECONDS_RUN=${2:-15}
DOMAIN=$((150 + $$ % 50))
printf '| source | display | pairs/s | age p50 ms | age p95 ms | render p50 ms | render p95 ms |\n'
printf '|---|---|---|---|---|---|---|\n'
for source in test_pattern sim; do
  for display in mono-left anaglyph-color; do
    args=(--domain "$DOMAIN" --config deploy/config/server_sim.pbtxt)
    [ "$source" = test_pattern ] && args+=(--source test_pattern)
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
      "$(get pair_rate_hz)" "$(get display_age_ms_p50)" "$(get display_age_ms_p95)" \
      "$(get frame_time_ms_p50)" "$(get frame_time_ms_p95)"
  done
done
