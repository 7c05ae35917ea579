#!/usr/bin/env bash
# LMS200 scan rate on DDS: robot_server with the simulated robot (its LMS200 emulator on a
# pseudo-terminal, read by the real driver at the configured baud) and a net_probe observer
# reading rt/mostar/scan on the loopback profile. Prints a Markdown table: scans/s received on
# DDS next to the ceiling (one scan per mirror turn the line can carry; with line faults, the
# share of telegrams the emulator sends intact), beams per scan, scans missing on DDS (from the
# scans' stamps; with line faults this includes the telegrams spoiled on the line), and the scan
# age on arrival.
# Steady state: each row measures SECONDS after a WARMUP that starts with the first sample.
#
# Usage: lms200_dds_bench.sh ROBOT_SERVER NET_PROBE SOURCE_DIR
# Environment: SECONDS_PER_ROW (default 20), WARMUP_S (default 4), CAMERA_HZ (default 30),
# ROWS (default all: a space-separated list of row numbers 1-4).
set -euo pipefail
[ $# -eq 3 ] || { echo "usage: lms200_dds_bench.sh ROBOT_SERVER NET_PROBE SOURCE_DIR" >&2; exit 2; }
robot_server=$1; net_probe=$2; src=$3
work=$(mktemp -d /tmp/mostar_lms_bench_XXXXXX); robot=""
stop_robot() { if [ -n "$robot" ]; then kill "$robot" 2>/dev/null || true; wait "$robot" 2>/dev/null || true; fi
               robot=""; }
trap 'stop_robot; rm -rf "$work"' EXIT
trap "exit 1" INT TERM
seconds=${SECONDS_PER_ROW:-20}; warmup=${WARMUP_S:-4}
camera_hz=${CAMERA_HZ:-30}  # the simulated stereo camera: it shares the CPU and the transport
mirror_s=0.01332

config() {  # name baud rs422 garbage crc truncate -> path
  local cfg="$work/$1.pbtxt"
  sed -e "s|baud: [0-9]*|baud: $2\n  rs422: $3|" -e "s|frame_rate_hz: [0-9.]*|frame_rate_hz: $camera_hz|" \
      -e "s|scene_file: \"\.\./|scene_file: \"$src/deploy/|" \
      "$src/deploy/config/server_sim.pbtxt" > "$cfg"
  printf 'sim { laser { line_garbage_rate: %s line_crc_error_rate: %s line_truncate_rate: %s } }\n' \
    "$4" "$5" "$6" >> "$cfg"
  echo "$cfg"
}

row() {  # label baud rs422 garbage crc truncate
  local label=$1 baud=$2 domain=$((100 + RANDOM % 100))
  local cfg; cfg=$(config "row$RANDOM" "$2" "$3" "$4" "$5" "$6")
  "$robot_server" --domain "$domain" --dds-profile loopback --insecure --config "$cfg" \
    --source sim > "$work/robot.log" 2>&1 &
  robot=$!
  local out
  out=$(timeout -k 5 $((seconds + warmup + 40)) "$net_probe" --domain "$domain" \
        --dds-profile loopback --insecure --no-ping --duration-s "$((seconds + warmup + 8))" \
        --warmup-s "$((warmup + 6))" --samples "$work/samples.csv" 2>/dev/null \
        | grep '^probe:' || echo "probe: hung")
  stop_robot
  f() { echo "$out" | sed -n "s/.* $1=\([^ ]*\).*/\1/p"; }
  local scans; scans=$(f scan)
  if [ -z "$scans" ]; then printf '| %s | no result (probe hung) | | | | | |\n' "$label"; return; fi
  # Ceiling: one scan per mirror turn the wire allows (372-byte telegram, 10 bits per byte),
  # times the share of telegrams sent intact (a CRC error or a truncation each spoil one).
  local ceiling
  ceiling=$(awk -v b="$baud" -v m="$mirror_s" -v c="$5" -v t="$6" 'BEGIN {
    w = 372 * 10 / b; turns = int(w / m); if (turns * m < w) turns++; if (turns < 1) turns = 1;
    printf "%.2f", (1 - c) * (1 - t) / (turns * m) }')
  # Scans missing on DDS in the measured window: the scan periods its stamps span (one period
  # per transmitted scan: a mirror turn at 500 kBd, 8 at 38400 Bd) minus the scans received.
  # Only the first and last stamp count, so stamp jitter does not make up gaps.
  local missing
  missing=$(awk -F, -v w="$((warmup + 6))" '
    $1 == "scan" { if (!first) first = $2; if ($2 - first >= w * 1e9) print $3 }' \
    "$work/samples.csv" | sort -n | awk -v b="$baud" -v m="$mirror_s" '
    BEGIN { w = 372 * 10 / b; turns = int(w / m); if (turns * m < w) turns++; p = turns * m * 1e9 }
    NR == 1 { first = $1 } { last = $1 }
    END { printf "%d of %d", int((last - first) / p + 0.5) + 1 - NR, int((last - first) / p + 0.5) + 1 }')
  local rate; rate=$(echo "$scans / $(f measured_s)" | bc -l)
  printf '| %s | %.2f | %s | %.1f %% | %s | %s | %s / %s |\n' "$label" "$rate" "$ceiling" \
    "$(echo "100 * $rate / $ceiling" | bc -l)" "$(f scan_beams)" "$missing" \
    "$(f scan_age_p50_ms)" "$(f scan_age_p95_ms)"
}

echo "| link, line faults (garbage / CRC / truncated per telegram) | scans/s on DDS | ceiling | ratio | beams | scans missing in the window | scan age p50 / p95 ms |"
echo "|---|---|---|---|---|---|---|"
rows=${ROWS:-1 2 3 4}
want() { [[ " $rows " == *" $1 "* ]]; }
cam="camera $camera_hz Hz"
want 1 && row "RS-232 38400 Bd, none, $cam" 38400 false 0 0 0
want 2 && row "RS-422 500 kBd, none, $cam" 500000 true 0 0 0
want 3 && row "RS-422 500 kBd, 0.05 / 0.02 / 0.01, $cam" 500000 true 0.05 0.02 0.01
want 4 && row "RS-422 500 kBd, 0.1 / 0.1 / 0.05, $cam" 500000 true 0.1 0.1 0.05
exit 0
