#!/usr/bin/env python3
"""One WebSocket observer of a running mostar_web, reading every frame as a browser would
(without decoding the JPEG) for SECONDS after a warm-up; prints one line
`web: frames_per_s=F age_p50_ms=A age_p95_ms=B errors=N` (age: this machine's clock minus the
frame's capture stamp: one clock on loopback). Used by tests/bench/client_latency_bench.sh for
the web observer beside a console. Not a test: nothing is asserted.

Usage: web_reader.py PORT CERT TOKEN [--seconds 20] [--warmup 2]
"""

import argparse
import os
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import webtest  # noqa: E402
from web_load import percentile  # noqa: E402


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("port", type=int)
    parser.add_argument("cert")
    parser.add_argument("token")
    parser.add_argument("--seconds", type=float, default=20)
    parser.add_argument("--warmup", type=float, default=2)
    args = parser.parse_args()
    ages_ms = []
    errors = 0
    start = time.monotonic()
    end = start + args.warmup + args.seconds
    try:
        ws = webtest.WebSocket(args.port, args.cert, args.token, timeout=10)
        while time.monotonic() < end:
            opcode, payload = ws.recv()
            if opcode == 0x2 and time.monotonic() > start + args.warmup:
                ages_ms.append((time.time() - webtest.frame_header(payload)["stamp"]) * 1e3)
        ws.close()
    except Exception as e:  # noqa: BLE001
        errors += 1
        print("web_reader: " + repr(e), file=sys.stderr)
    print("web: frames_per_s=%.1f age_p50_ms=%.1f age_p95_ms=%.1f errors=%d" % (
        len(ages_ms) / args.seconds, percentile(ages_ms, 0.5), percentile(ages_ms, 0.95), errors),
        flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
