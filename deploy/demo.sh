#!/usr/bin/env bash
# The main job: installs what is missing, builds, then runs the simulated robot (robot_server)
# and the operator client on this machine, all DDS traffic on loopback.
#
# With a display: an interactive window (arrows/WASD drive, Esc quits).
# Without one (servers, CI): the client runs headless under xvfb-run for DEMO_SECONDS, drives
# the robot forward, and writes the last rendered view to out/demo.png.
#
# Environment: BUILD_DIR (default build), DEMO_SECONDS (default 15), DISPLAY_MODE
# (default mono-left; see operator_client --help), SCENE (default deploy/scenes/corridor.pbtxt;
# also open_room.pbtxt, checkerboard_room.pbtxt and tiled_room.pbtxt).
set -euo pipefail
cd "$(dirname "$0")/.."
./deploy/install-deps.sh
BUILD_DIR=${BUILD_DIR:-build}
cmake -S . -B "$BUILD_DIR" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo >/dev/null
cmake --build "$BUILD_DIR" -j "$(nproc)" --target robot_server operator_client
DEMO_SECONDS=${DEMO_SECONDS:-15}
DISPLAY_MODE=${DISPLAY_MODE:-mono-left}
SCENE=${SCENE:-deploy/scenes/corridor.pbtxt}
DOMAIN=${MOSTAR_DDS_DOMAIN:-$((40 + $$ % 60))}
mkdir -p out
# The server keeps its e-stop latch here (docs/safety.md); a fresh one per demo starts unlatched.
STATE_DIR=$(mktemp -d)

"$BUILD_DIR/robot_server/robot_server" --domain "$DOMAIN" \
  --config deploy/config/server_sim.pbtxt --sim "$SCENE" --state-dir "$STATE_DIR" &
SERVER=$!
trap 'kill -TERM $SERVER 2>/dev/null; wait $SERVER 2>/dev/null || true; rm -rf "$STATE_DIR"' EXIT

if [ -n "${DISPLAY:-}" ]; then
  "$BUILD_DIR/operator_client/operator_client" --domain "$DOMAIN" --display "$DISPLAY_MODE" \
    --config deploy/config/client_sim.pbtxt
else
  echo "demo: no display, running the client headless for ${DEMO_SECONDS}s (out/demo.png)"
  xvfb-run -a -s "-screen 0 1920x1080x24 -noreset" \
    "$BUILD_DIR/operator_client/operator_client" --domain "$DOMAIN" --headless \
    --display "$DISPLAY_MODE" --duration "$DEMO_SECONDS" --drive 0.15,0.05 \
    --config deploy/config/client_sim.pbtxt --screenshot out/demo.png
  echo "demo: wrote out/demo.png"
fi
