#!/usr/bin/env bash
# mostar_web under 1, 4 and 16 observers on loopback (robot_server on the simulator): frames per
# second each observer gets, frame age on arrival p50/p95, CPU of mostar_web, robot_server and
# the load client; with the simulator (it renders the scene: the robot's rate depends on the
# machine) and with the test pattern (cheap frames, 30 per second); each with mostar_web's edge
# processing off and on (--edges: both eyes decoded and NEPs on this host). Prints a Markdown
# table (docs/web_observer.md keeps the measured one).
#
#   tests/bench/web_bench.sh [BUILD_DIR] [SECONDS] [CLIENTS]
set -euo pipefail
cd "$(dirname "$0")/../.."
BUILD_DIR=${1:-build}
SECONDS_RUN=${2:-15}
CLIENTS=${3:-1,4,16}
header=--header
for source in sim test_pattern; do
  for edges in off on; do
    python3 tests/web/web_load.py "$BUILD_DIR/robot_server/robot_server" \
      "$BUILD_DIR/operator_client/web/mostar_web" . --seconds "$SECONDS_RUN" --clients "$CLIENTS" \
      --robot-source "$source" --edges "$edges" $header
    header=
  done
done
