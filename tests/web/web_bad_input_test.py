#!/usr/bin/env python3
"""mostar_web against bad input, with robot_server on the simulator. A well-behaved observer
(TLS WebSocket client) reads frames throughout while:
  1. a wrong token (on /ws and on /stats) and a missing one are refused with 401 and counted;
  2. a client sends an unmasked frame, a frame with a reserved opcode and a message larger than
     mostar_web accepts: each such connection is closed and counted as a bad frame (an orderly
     close frame without a status code is not);
  3. a client with a tiny receive buffer stops reading: mostar_web disconnects it once a write
     stays blocked for --write-timeout-s, and counts it as stalled;
  4. a client sends half an HTTP request and nothing more: dropped after --request-timeout-s;
  5. with --client-ca, a TLS handshake without a certificate from that CA fails (counted), one
     with it goes through.
The well-behaved observer must keep receiving frames through all of it and mostar_web must
exit cleanly. Needs no browser.

Usage: web_bad_input_test.py ROBOT_SERVER MOSTAR_WEB SOURCE_DIR
"""

import json
import os
import shutil
import socket
import ssl
import subprocess
import sys
import tempfile
import threading
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import webtest  # noqa: E402


class Reader(threading.Thread):
    """Reads frames until stopped; counts them."""

    def __init__(self, programs):
        super().__init__(daemon=True)
        self.ws = webtest.WebSocket(programs.port, programs.cert, webtest.TOKEN)
        self.frames = 0
        self.huds = 0
        self.error = None
        self.stop = False

    def run(self):
        try:
            while not self.stop:
                opcode, payload = self.ws.recv()
                if opcode == 0x2:
                    webtest.frame_header(payload)
                    self.frames += 1
                elif opcode == 0x1:
                    self.huds += 1
        except Exception as e:  # noqa: BLE001
            if not self.stop:
                self.error = repr(e)


def closed_by_server(ws, timeout_s=5):
    """True when the server closes the connection (a close frame or EOF) within the timeout;
    the client then ends the closing handshake as a browser would."""
    ws.sock.settimeout(timeout_s)
    try:
        while True:
            ws.recv()
    except socket.timeout:
        return False
    except (ConnectionError, OSError):
        ws.finish_close()
        return True


def client_certificates(robot_server, mostar_web, source, check):
    """--client-ca: a TLS handshake without a certificate from that CA fails and is counted; with
    one (and the token) the request goes through."""
    work = tempfile.mkdtemp(prefix="mostar_web_ca_")
    run = lambda *a: subprocess.run(["openssl", *a], cwd=work, check=True,  # noqa: E731
                                    stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    ec = ["-newkey", "ec", "-pkeyopt", "ec_paramgen_curve:prime256v1", "-nodes"]
    run("req", "-x509", *ec, "-keyout", "ca.key", "-out", "ca.pem", "-days", "1", "-subj", "/CN=observers")
    run("req", *ec, "-keyout", "alice.key", "-out", "alice.csr", "-subj", "/CN=alice")
    run("x509", "-req", "-in", "alice.csr", "-CA", "ca.pem", "-CAkey", "ca.key", "-CAcreateserial",
        "-out", "alice.pem", "-days", "1")
    programs = webtest.Programs(robot_server, mostar_web, source,
                                web_args=["--client-ca", os.path.join(work, "ca.pem")])
    failures = []
    try:
        alice = (os.path.join(work, "alice.pem"), os.path.join(work, "alice.key"))
        path = "/stats?token=" + webtest.TOKEN
        try:
            without = webtest.https_get(programs.port, path, programs.cert)[0]
        except (ssl.SSLError, OSError):
            without = 0
        with_cert, body = webtest.https_get(programs.port, path, programs.cert, client_cert=alice)
        ok = without == 0 and with_cert == 200
        check(ok, "--client-ca: no certificate, no TLS session (%d); alice's certificate and token: %d"
              % (without, with_cert))
        if not ok:
            failures.append("client certificates")
        tls_failures = json.loads(body)["tls_failures"]
        check(tls_failures == 1, "the refused handshake is counted (%d)" % tls_failures)
        if tls_failures != 1:
            failures.append("tls_failures")
    finally:
        programs.finish(failures)
        shutil.rmtree(work, ignore_errors=True)
    return failures


def main():
    args = webtest.program_args(sys.argv, __doc__)
    if isinstance(args, int):
        return args
    robot_server, mostar_web, source, _ = args
    check = webtest.Checks()
    failures = check.failures

    programs = webtest.Programs(robot_server, mostar_web, source,
                                web_args=["--write-timeout-s", "1.5", "--request-timeout-s", "2"])
    reader = None
    try:
        reader = Reader(programs)
        check(reader.ws.status == 101, "a valid token opens the stream")
        reader.start()
        deadline = time.monotonic() + 30
        while reader.frames < 5 and time.monotonic() < deadline and reader.error is None:
            time.sleep(0.1)
        check(reader.frames >= 5, "the observer receives frames (%d)" % reader.frames)

        # 1. Tokens.
        statuses = [webtest.WebSocket(programs.port, programs.cert, t).status
                    for t in ("wrong-token-0123456789", "", webtest.TOKEN[:-1])]
        stats_status = webtest.https_get(programs.port, "/stats?token=nope", programs.cert)[0]
        check(statuses == [401, 401, 401] and stats_status == 401,
              "wrong, empty and truncated tokens are refused with 401 (%s, stats %d)" % (statuses, stats_status))

        # 2. Malformed frames: each connection is closed.
        bad = webtest.WebSocket(programs.port, programs.cert, webtest.TOKEN)
        bad.send(0x1, b"hello", mask=False)
        check(closed_by_server(bad), "an unmasked client frame closes that connection")
        bad = webtest.WebSocket(programs.port, programs.cert, webtest.TOKEN)
        bad.send(0x3, b"x")
        check(closed_by_server(bad), "a reserved opcode closes that connection")
        bad = webtest.WebSocket(programs.port, programs.cert, webtest.TOKEN)
        bad.sock.sendall(bytes([0x82, 0x80 | 127]) + (70000).to_bytes(8, "big") + b"mask")  # header only
        check(closed_by_server(bad), "an oversized message closes that connection")

        # An orderly close without a status code (what a page's ws.close() sends) is no bad frame.
        polite = webtest.WebSocket(programs.port, programs.cert, webtest.TOKEN)
        polite.send(0x8, b"")
        check(closed_by_server(polite), "a close frame without a status code ends that connection")

        # 3. A client that never reads.
        frozen = webtest.WebSocket(programs.port, programs.cert, webtest.TOKEN, rcvbuf=4096)
        check(frozen.status == 101, "the frozen client connected")
        before = reader.frames
        deadline = time.monotonic() + 25
        while programs.stats()["stalled"] < 1 and time.monotonic() < deadline:
            time.sleep(0.25)
        during = reader.frames - before
        check(programs.stats()["stalled"] == 1, "the client that stopped reading was disconnected as stalled")
        check(during >= 3, "the observer kept receiving frames meanwhile (%d)" % during)

        # 4. Half a request.
        slow = socket.create_connection(("127.0.0.1", programs.port))
        tls = webtest.tls_context(programs.cert).wrap_socket(slow, server_hostname="localhost")
        tls.sendall(b"GET / HTTP/1.1\r\nHost: loc")
        tls.settimeout(8)
        try:
            dropped = tls.recv(100) == b""
        except (ConnectionError, OSError):
            dropped = True
        except socket.timeout:
            dropped = False
        check(dropped, "half a request is dropped after the request timeout")

        s = programs.stats()
        print("mostar_web stats:", s)
        check(s["token_refused"] == 4, "4 refusals counted (%d)" % s["token_refused"])
        check(s["bad_frames"] == 3, "3 bad frames counted (%d)" % s["bad_frames"])
        check(s["aborted"] == 0, "no session aborted (%d)" % s["aborted"])
        check(s["http_timeouts"] == 1, "1 request timeout counted (%d)" % s["http_timeouts"])
        before = reader.frames
        time.sleep(1.0)
        check(reader.frames > before and reader.error is None,
              "the observer still receives frames at the end (%s)" % (reader.error or "no error"))
        check(s["browsers_open"] == 1, "only the observer is still connected (%d)" % s["browsers_open"])
    except Exception as e:  # noqa: BLE001 - report and fail, never hang
        failures.append(repr(e))
        print("FAIL:", repr(e))
    finally:
        if reader:
            reader.stop = True
            reader.ws.close()
        programs.stop()
        check(programs.web.returncode == 0, "mostar_web exited cleanly (%s)" % programs.web.returncode)
    status = programs.finish(failures)
    if client_certificates(robot_server, mostar_web, source, check):
        status = 1
    return status


if __name__ == "__main__":
    sys.exit(main())
