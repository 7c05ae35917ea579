#!/usr/bin/env python3
"""Load bench for mostar_web: for each client count, robot_server on the simulator, mostar_web
and N WebSocket observers (TLS, reading every frame as a browser would, without decoding the
JPEG) for SECONDS; prints a Markdown table of the frames per second each observer got, the age
of the frames on arrival (this machine's clock minus the capture stamp: one clock, loopback),
and the CPU of mostar_web, robot_server and this load client. Not a test: nothing is asserted.

Usage: web_load.py ROBOT_SERVER MOSTAR_WEB SOURCE_DIR [--clients 1,4,16] [--seconds 15]
                   [--robot-source sim|test_pattern] [--edges on|off] [--header]
"""

import argparse
import os
import shutil
import sys
import threading
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import webtest  # noqa: E402


def percentile(values, p):
    """Nearest rank, as common/stats/percentile.h."""
    if not values:
        return float("nan")
    s = sorted(values)
    k = max(0, min(len(s) - 1, int(-(-p * len(s) // 1)) - 1))
    return s[k]


class Observer(threading.Thread):
    def __init__(self, programs, until):
        super().__init__(daemon=True)
        self.ws = webtest.WebSocket(programs.port, programs.cert, webtest.BENCH_TOKEN, timeout=10)
        self.until = until
        self.ages_ms = []
        self.error = None

    def run(self):
        try:
            while time.monotonic() < self.until:
                opcode, payload = self.ws.recv()
                if opcode == 0x2:
                    self.ages_ms.append((time.time() - webtest.frame_header(payload)["stamp"]) * 1e3)
        except Exception as e:  # noqa: BLE001
            self.error = repr(e)
        self.ws.close()


def run(robot_server, mostar_web, source, clients, seconds, robot_source, edges):
    server_args = ["--source", "test_pattern"] if robot_source == "test_pattern" else []
    programs = webtest.Programs(robot_server, mostar_web, source,
                                web_args=["--log-level", "warning", "--edges", edges],
                                server_args=server_args)
    try:
        time.sleep(3)  # discovery, first frames
        start = time.monotonic()
        warmup = 2
        observers = [Observer(programs, start + warmup + seconds) for _ in range(clients)]
        for o in observers:
            o.start()
        time.sleep(warmup)
        for o in observers:
            o.ages_ms.clear()
        cpu0 = [programs.cpu_seconds(programs.web), programs.cpu_seconds(programs.robot), time.process_time()]
        stats0 = programs.stats(webtest.BENCH_TOKEN)
        composed0 = stats0["frames_composed"]
        with_edges0 = stats0["frames_with_edges"]
        t0 = time.monotonic()
        for o in observers:
            o.join(seconds + 30)
        elapsed = time.monotonic() - t0
        cpu1 = [programs.cpu_seconds(programs.web), programs.cpu_seconds(programs.robot), time.process_time()]
        stats = programs.stats(webtest.BENCH_TOKEN)
        composed = stats["frames_composed"] - composed0
        with_edges = stats["frames_with_edges"] - with_edges0
    finally:
        programs.stop()
        shutil.rmtree(programs.work, ignore_errors=True)
    fps = [len(o.ages_ms) / elapsed for o in observers]
    ages = [a for o in observers for a in o.ages_ms]
    cpu = [100 * (b - a) / elapsed for a, b in zip(cpu0, cpu1)]
    errors = [o.error for o in observers if o.error]
    return {"clients": clients, "fps_min": min(fps), "fps_mean": sum(fps) / len(fps),
            "age_p50": percentile(ages, 0.5), "age_p95": percentile(ages, 0.95),
            "web_cpu": cpu[0], "robot_cpu": cpu[1], "load_cpu": cpu[2],
            "composed_fps": composed / elapsed, "dropped": stats["frames_dropped"],
            "with_edges": 100.0 * with_edges / max(1, composed),
            "edge_ms": stats.get("edge_processing_ms", float("nan")),
            "decode_ms": stats.get("edge_decode_ms", float("nan")),
            "errors": len(errors)}


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("robot_server")
    parser.add_argument("mostar_web")
    parser.add_argument("source")
    parser.add_argument("--clients", default="1,4,16")
    parser.add_argument("--seconds", type=float, default=15)
    parser.add_argument("--robot-source", choices=["sim", "test_pattern"], default="sim",
                        help="robot_server's source: the simulator (renders the scene) or the "
                             "lighter test pattern")
    parser.add_argument("--edges", choices=["on", "off"], default="on",
                        help="mostar_web's edge processing (NEP dots)")
    parser.add_argument("--header", action="store_true", help="print the table's header")
    args = parser.parse_args()
    if args.header:
        print("| source | edges | observers | frames composed/s | fps each (min / mean) | age p50 ms "
              "| age p95 ms | mostar_web CPU % | robot_server CPU % | load client CPU % "
              "| frames dropped for slow observers | frames with their edge result % "
              "| decode + edges ms (last pair) |")
        print("|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    for n in [int(c) for c in args.clients.split(",")]:
        r = run(args.robot_server, args.mostar_web, args.source, n, args.seconds, args.robot_source,
                args.edges)
        edges = ("%.0f | %.0f + %.0f" % (r["with_edges"], r["decode_ms"], r["edge_ms"])
                 if args.edges == "on" else "- | -")
        print("| %s | %s | %d | %.1f | %.1f / %.1f | %.0f | %.0f | %.0f | %.0f | %.0f | %d | %s |%s" % (
            args.robot_source, args.edges, n, r["composed_fps"], r["fps_min"], r["fps_mean"],
            r["age_p50"], r["age_p95"], r["web_cpu"], r["robot_cpu"], r["load_cpu"], r["dropped"],
            edges, " (%d observer errors)" % r["errors"] if r["errors"] else ""),
            flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
