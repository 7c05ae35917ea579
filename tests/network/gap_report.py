#!/usr/bin/env python3
"""Where a flow paused: for each packet capture, each IPv4 flow (source address -> destination
address, ports ignored) and each pause between two of its packets longer than --min-gap-ms,
one line with the pause's start (seconds since --origin, or since the epoch) and length.
Follow one flow hop by hop (nat_bench.sh CAPTURE=1 records the robot, NAT A, the Internet,
NAT B, the pilot and the hub): the first capture point where a pause appears is where the
packets stopped.

Usage: gap_report.py [--min-gap-ms 500] [--origin EPOCH_S] [--flow SRC>DST ...] PCAP...
Needs tcpdump (reads the files with tcpdump -tt -nn -r)."""
import argparse
import re
import subprocess
import sys

LINE = re.compile(r"^(\d+\.\d+) .*?IP (\d+\.\d+\.\d+\.\d+)(?:\.\d+)? > (\d+\.\d+\.\d+\.\d+)(?:\.\d+)?:")


def flows_of(path):
    """{(src, dst): [times]} of one capture."""
    out = subprocess.run(["tcpdump", "-tt", "-nn", "-r", path], capture_output=True, text=True)
    if out.returncode != 0 and not out.stdout:
        sys.exit(f"gap_report: cannot read {path}: {out.stderr.strip()}")
    flows = {}
    for line in out.stdout.splitlines():
        m = LINE.match(line)
        if m:
            flows.setdefault((m.group(2), m.group(3)), []).append(float(m.group(1)))
    return flows


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--min-gap-ms", type=float, default=500)
    parser.add_argument("--origin", type=float, default=0.0)
    parser.add_argument("--flow", action="append", default=[],
                        help="only this flow, SRC>DST (repeatable)")
    parser.add_argument("pcaps", nargs="+")
    args = parser.parse_args()
    wanted = {tuple(f.split(">")) for f in args.flow}
    for path in args.pcaps:
        for (src, dst), times in sorted(flows_of(path).items()):
            if wanted and (src, dst) not in wanted:
                continue
            times.sort()
            for a, b in zip(times, times[1:]):
                if (b - a) * 1000 >= args.min_gap_ms:
                    print(f"{path} {src}>{dst} packets={len(times)} pause_from_s={a - args.origin:.3f} "
                          f"pause_ms={(b - a) * 1000:.0f}")


if __name__ == "__main__":
    main()
