#!/usr/bin/env python3
"""mostar_web under DDS Security, as docs/web_observer.md ("With DDS Security") sets it up: a PKI
from deploy/security/make_pki.sh with an observer identity "web", robot_server on the simulator
with the robot's secure profile, and mostar_web with the observer's. A TLS WebSocket client
must receive frames and live HUD messages that do not report DDS security off, and the robot's
stream must stay closed to a mostar_web on the same domain without an identity.

Usage: web_secure_test.py ROBOT_SERVER MOSTAR_WEB SOURCE_DIR
"""

import json
import os
import re
import select
import shutil
import subprocess
import sys
import tempfile
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import webtest  # noqa: E402


def read_messages(programs, seconds, frames_wanted):
    """(frames, hud messages) read within `seconds`, stopping early once enough frames came and
    a HUD message says the link is ok (scans and video live)."""
    ws = webtest.WebSocket(programs.port, programs.cert, webtest.TOKEN)
    if ws.status != 101:
        return 0, []
    frames, huds = 0, []
    ws.sock.settimeout(2)
    deadline = time.monotonic() + seconds
    while time.monotonic() < deadline and (frames < frames_wanted or
                                           not any(h.get("link") == "ok" for h in huds)):
        try:
            opcode, payload = ws.recv()
        except OSError:
            continue
        if opcode == 0x2:
            webtest.frame_header(payload)
            frames += 1
        elif opcode == 0x1:
            huds.append(json.loads(payload.decode()))
    return frames, huds


def start_unidentified_web(programs, source):
    """A second mostar_web on the robot's domain with the plain loopback profile (no identity);
    returns (process, port)."""
    log = open(os.path.join(programs.work, "unidentified_web.log"), "w")
    proc = subprocess.Popen(
        [programs.web.args[0], "--domain", str(programs.domain), "--config",
         os.path.join(source, "deploy/config/client_sim.pbtxt"), "--cert", programs.cert,
         "--key", programs.key, "--tokens", programs.tokens, "--port", "0"],
        stdout=subprocess.PIPE, stderr=log, text=True)
    programs.procs.append(proc)
    deadline = time.monotonic() + 20
    while time.monotonic() < deadline and proc.poll() is None:
        ready, _, _ = select.select([proc.stdout], [], [], 0.5)
        if ready:
            m = re.search(r"serving https://[^:]+:(\d+)/", proc.stdout.readline())
            if m:
                return proc, int(m.group(1))
    return proc, None


def main():
    args = webtest.program_args(sys.argv, __doc__)
    if isinstance(args, int):
        return args
    robot_server, mostar_web, source, _ = args
    check = webtest.Checks()
    failures = check.failures

    pki = tempfile.mkdtemp(prefix="mostar_web_pki_")
    made = subprocess.run(
        [os.path.join(source, "deploy/security/make_pki.sh"), pki, "--profile",
         os.path.join(source, "tests/security/secure_loopback.xml"), "--observer", "web"],
        stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    if made.returncode != 0:
        print(made.stdout)
        print("FAIL: make_pki.sh")
        return 1
    programs = webtest.Programs(
        robot_server, mostar_web, source,
        web_args=["--dds-profile", os.path.join(pki, "web.xml"), "--profile-name", "operator"],
        server_args=["--dds-profile", os.path.join(pki, "robot.xml")])
    try:
        frames, huds = read_messages(programs, 40, 5)
        check(frames >= 5, "the observer with the 'web' identity streams frames (%d)" % frames)
        check(bool(huds), "HUD messages arrive (%d)" % len(huds))
        if huds:
            hud = next((h for h in huds if h.get("link") == "ok"), huds[-1])
            check(hud.get("dds_security_off") is False,
                  "the HUD does not report DDS security off (%s)" % hud.get("dds_security_off"))
            check(hud.get("link") == "ok", "the HUD's link gets ok: video and scans (%s)"
                  % hud.get("link"))
        stats = programs.stats()
        check(stats.get("pairs", 0) > 0, "mostar_web received pairs over DDS Security (%s)"
              % stats.get("pairs"))

        # Control: without an identity the secure robot's streams stay closed.
        proc, port = start_unidentified_web(programs, source)
        check(port is not None, "a mostar_web without identity starts")
        if port is not None:
            time.sleep(5)
            body = webtest.https_get(port, "/stats?token=" + webtest.TOKEN, programs.cert)[1]
            pairs = json.loads(body).get("pairs", -1)
            check(pairs == 0, "a mostar_web without identity receives no pair (%d)" % pairs)
    finally:
        status = programs.finish(failures)
        shutil.rmtree(pki, ignore_errors=True)
    return status


if __name__ == "__main__":
    sys.exit(main())
