#!/usr/bin/env bash
# Soak bench of the Internet deployment (not in CI): many nat_bench.sh runs per path, each
# starting the whole NAT topology afresh, then one summary row per kind of disturbance.
#
# Default set (SOAK): 20 runs with a 5 s cut of the robot's uplink, 10 with 30 s, 3 with 120 s
# and 3 changes of the robot's public address, about 35 minutes per path on two cores. Every
# nat_bench.sh environment variable (TRANSPORT, WG_TCP, SECURE, VIA, POST_S...) passes through.
#
# Summary per kind (times after the link came back, p50 / p95 / max over the runs):
#   recovered   runs in which the pilot drove again and all three operators got video captured
#               after the link came back, within POST_S
#   stop        last accepted command -> drive output 0 on the robot (ms, max); for a new
#               address, whether the robot drove on
#   stale       runs in which the robot moved on commands from before the link came back
#   drive       link back -> the pilot driving again (s)
#   video       link back -> video captured after it at the slowest of the three operators (s)
#   fresh       the same for video younger than FRESH_MS (s)
#   hangs       runs in which a program needed SIGKILL; unclean: runs with a program slower
#               than 2 s to end on SIGTERM
# The per-run rows (nat_bench.sh's table) come first; after the summary, the steady state
# before the cut (pairs/s, image age p50 / p95 at each operator, control one-way p50 / p95),
# the median over the runs.
#
# Usage: soak_bench.sh ROBOT_SERVER OPERATOR_CLIENT NET_PROBE NETEM_RELAY MOSTAR_RELAY SOURCE_DIR
# Environment: SOAK (the runs, nat_bench.sh's RUNS syntax), plus nat_bench.sh's.
set -euo pipefail
[ $# -eq 6 ] || {
  echo "usage: soak_bench.sh ROBOT_SERVER OPERATOR_CLIENT NET_PROBE NETEM_RELAY MOSTAR_RELAY SOURCE_DIR" >&2
  exit 2
}
here=$(cd "$(dirname "$0")" && pwd)
repeat() { local i; for i in $(seq "$2"); do printf '%s ' "$1"; done; }
default_soak="$(repeat 5 20)$(repeat 30 10)$(repeat 120 3)$(repeat readdress 3)"
out=$(mktemp /tmp/mostar_soak_XXXXXX)
trap 'rm -f "$out"' EXIT
status=0
RUNS="${SOAK:-$default_soak}" "$here/nat_bench.sh" "$@" | tee "$out" || status=$?
[ "$status" -eq 0 ] || exit "$status"
echo
python3 - "$out" <<'EOF'
import sys
rows = {}
for line in open(sys.argv[1]):
    if not line.startswith("RESULT "):
        continue
    kv = dict(f.split("=", 1) for f in line.split()[1:])
    rows.setdefault(kv.get("what", "?"), []).append(kv)

def num(v):
    try:
        return float(v)
    except ValueError:
        return None  # "never", "" (the run did not get that far)

def stats(values):
    values = sorted(v for v in values if v is not None)
    if not values:
        return "-"
    p = lambda q: values[min(len(values) - 1, int(q * len(values)))]
    return "%.1f / %.1f / %.1f" % (p(0.5), p(0.95), values[-1])

print("| disturbance | runs | recovered | stop, max (ms) | moved on stale commands | driving again (s) | video back, slowest operator (s) | fresh video, slowest operator (s) | hangs | unclean exits |")
print("|---|---|---|---|---|---|---|---|---|---|")
for what in sorted(rows, key=lambda w: (not w.isdigit(), int(w) if w.isdigit() else 0)):
    runs = rows[what]
    def slowest(key):
        out = []
        for r in runs:
            parts = [num(x) for x in r.get(key, "").split("/")]
            out.append(None if not parts or None in parts else max(parts))
        return out
    drive = [num(r.get("drive_s", "")) for r in runs]
    back, fresh = slowest("back"), slowest("fresh")
    recovered = sum(1 for d, b in zip(drive, back) if d is not None and b is not None)
    stops = [num(r.get("stop_ms", "")) for r in runs]
    stops = [s for s in stops if s is not None]
    if what == "readdress":  # the robot should drive on; a stop is a pause in its commands
        stop_cell = "kept driving" if not stops else "stopped in %d run(s), %.0f ms after the last command" % (len(stops), max(stops))
    else:
        stop_cell = "%.0f" % max(stops) if stops else "-"
    stale = sum(1 for r in runs if r.get("stale") == "yes")
    hangs = sum(1 for r in runs if r.get("exit", "").startswith("hang"))
    unclean = sum(1 for r in runs if (num(r.get("exit", "")) or 0) > 2.0)
    label = what + " s outage" if what.isdigit() else "new public address" if what == "readdress" else what
    print("| %s | %d | %d | %s | %d | %s | %s | %s | %d | %d |" % (
        label, len(runs), recovered, stop_cell, stale,
        stats(drive), stats(back), stats(fresh), hangs, unclean))

# Steady state before each cut (nat_bench.sh's STEADY lines): the median over the runs.
import re
steady = {}
for line in open(sys.argv[1]):
    if not line.startswith("STEADY "):
        continue
    for who, rate, p50, p95 in re.findall(r"(\w+): ([\d.]+) pairs/s (\S+) / (\S+) ms", line):
        steady.setdefault(who, []).append((float(rate), float(p50), float(p95)))
    m = re.search(r"control one-way p50 / p95: (\S+) / (\S+) ms", line)
    if m:
        steady.setdefault("control", []).append((float(m.group(1)), float(m.group(2))))
def median(values):
    values = sorted(v for v in values if v == v)  # without NaN
    return values[len(values) // 2] if values else float("nan")
if steady:
    print()
    print("| steady state before the cut, median of %d runs | pairs/s | image age p50 (ms) | image age p95 (ms) |" % len(steady.get("control", [])))
    print("|---|---|---|---|")
    for who in ("pilot", "obs1", "obs2"):
        if who in steady:
            rows = steady[who]
            print("| %s | %.1f | %.0f | %.0f |" % (who, median([r[0] for r in rows]),
                  median([r[1] for r in rows]), median([r[2] for r in rows])))
    if "control" in steady:
        rows = steady["control"]
        print("| control one-way (pilot -> robot) | | %.0f | %.0f |" % (
            median([r[0] for r in rows]), median([r[1] for r in rows])))
EOF
