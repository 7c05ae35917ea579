#!/usr/bin/env bash
# What the robot's command path adds to a pilot's velocity commands, on one host: a pilot
# (identity_actor as alice: a command every 50 ms, stamped when written) and the robot's side
# (command_path_probe) in two processes on the loopback network, without and with DDS Security
# (a make_pki.sh PKI on tests/security/secure_loopback.xml: PKI-DH, signed permissions,
# AES-GCM). Two readers of the same commands in alice's partition take turns:
#   plain  a DDS reader: what DDS delivery costs
#   node   RobotNode: per-client readers, the sender check, the command-writer tracker, up to the
#          command callback the drive loop gets
# Prints a Markdown table of one-way latency (arrival minus stamp, ms) per row and round, then
# node minus plain per profile (p50 and p95, the mean over rounds).
#
# Usage: command_path_bench.sh COMMAND_PATH_PROBE IDENTITY_ACTOR SOURCE_DIR
# Environment: SAMPLES (per row, default 400: 20 s), ROUNDS (default 2; rows alternate plain,
# node within each round), PROFILES (default "loopback secure").
set -euo pipefail
[ $# -eq 3 ] || { echo "usage: command_path_bench.sh COMMAND_PATH_PROBE IDENTITY_ACTOR SOURCE_DIR" >&2; exit 2; }
probe=$1; actor=$2; src=$(cd "$3" && pwd)
samples=${SAMPLES:-400}; rounds=${ROUNDS:-2}; profiles=${PROFILES:-loopback secure}
work=$(mktemp -d /tmp/mostar_cmd_bench_XXXXXX)
pids=()
cleanup() {
  for p in "${pids[@]}"; do kill "$p" 2>/dev/null || true; wait "$p" 2>/dev/null || true; done
  rm -rf "$work"
}
trap cleanup EXIT
trap "exit 1" INT TERM

if [[ " $profiles " == *" secure "* ]]; then
  "$src/deploy/security/make_pki.sh" "$work/pki" --profile "$src/tests/security/secure_loopback.xml" \
    --pilot alice > "$work/make_pki.log" 2>&1 || { cat "$work/make_pki.log"; exit 1; }
fi

# row PROFILE MODE -> the probe's result line
row() {
  local profile=$1 mode=$2 domain=$((10 + RANDOM % 200)) robot_profile actor_profile
  if [ "$profile" = secure ]; then
    robot_profile="$work/pki/robot.xml"; actor_profile="$work/pki/alice.xml"
  else
    robot_profile=loopback; actor_profile=loopback
  fi
  "$probe" --dds-profile "$robot_profile" --domain "$domain" --mode "$mode" --pilot alice \
    --samples "$samples" --timeout-s $((samples / 10 + 60)) > "$work/probe.out" 2> "$work/probe.err" &
  local probe_pid=$!
  pids+=("$probe_pid")
  for _ in $(seq 100); do grep -q "probe ready" "$work/probe.out" && break; sleep 0.1; done
  "$actor" --dds-profile "$actor_profile" --domain "$domain" --sender-id alice --commands idle \
    --duration-s $((samples / 10 + 60)) > "$work/actor.log" 2>&1 &
  local actor_pid=$!
  pids+=("$actor_pid")
  local status=0
  wait "$probe_pid" || status=$?
  kill "$actor_pid" 2>/dev/null || true
  wait "$actor_pid" 2>/dev/null || true
  if [ "$status" -ne 0 ]; then
    echo "command_path_bench: the probe failed ($profile $mode):" >&2
    cat "$work/probe.out" "$work/probe.err" >&2
    exit 1
  fi
  grep '^probe ' "$work/probe.out"
}

field() { sed -n "s/.* $1=\([^ ]*\).*/\1/p"; }
echo "| profile | reader | round | samples | p50 ms | p95 ms | p99 ms | max ms |"
echo "|---|---|---|---|---|---|---|---|"
declare -A sums
for profile in $profiles; do
  for round in $(seq "$rounds"); do
    for mode in plain node; do
      line=$(row "$profile" "$mode")
      echo "| $profile | $mode | $round | $(field samples <<< "$line") | $(field p50_ms <<< "$line") | $(field p95_ms <<< "$line") | $(field p99_ms <<< "$line") | $(field max_ms <<< "$line") |"
      for q in p50_ms p95_ms; do
        sums[$profile.$mode.$q]=$(awk -v a="${sums[$profile.$mode.$q]:-0}" -v b="$(field $q <<< "$line")" 'BEGIN { print a + b }')
      done
    done
  done
done
echo
echo "| profile | node - plain, p50 ms (mean of rounds) | node - plain, p95 ms (mean of rounds) |"
echo "|---|---|---|"
for profile in $profiles; do
  d50=$(awk -v n="${sums[$profile.node.p50_ms]}" -v p="${sums[$profile.plain.p50_ms]}" -v r="$rounds" 'BEGIN { printf "%.3f", (n - p) / r }')
  d95=$(awk -v n="${sums[$profile.node.p95_ms]}" -v p="${sums[$profile.plain.p95_ms]}" -v r="$rounds" 'BEGIN { printf "%.3f", (n - p) / r }')
  echo "| $profile | $d50 | $d95 |"
done
