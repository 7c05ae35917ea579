"""Helpers for the mostar_web tests and bench: the programs on loopback, a TLS WebSocket client,
a WebDriver client for chromedriver and a PNG reader. Standard library only."""

import base64
import json
import os
import re
import select
import shutil
import signal
import socket
import ssl
import struct
import subprocess
import tempfile
import time
import urllib.request
import zlib

SKIP = 77  # CTest SKIP_RETURN_CODE

TOKEN = "observer-test-token-0123456789"
BENCH_TOKEN = "bench-token-0123456789abcdef"
CHROMIUM = "/usr/bin/chromium"
CHROMEDRIVER = "/usr/bin/chromedriver"


class Checks:
    """check(ok, what) prints the check's result and keeps what failed in .failures (the list
    Programs.finish() takes)."""

    def __init__(self):
        self.failures = []

    def __call__(self, ok, what):
        print(("ok: " if ok else "FAIL: ") + what)
        if not ok:
            self.failures.append(what)


def wait_for(what, predicate, timeout_s):
    """predicate()'s first truthy value, polled every 0.25 s; AssertionError after timeout_s."""
    deadline = time.monotonic() + timeout_s
    while time.monotonic() < deadline:
        value = predicate()
        if value:
            return value
        time.sleep(0.25)
    raise AssertionError("timed out waiting for " + what)


def program_args(argv, doc, browser=False):
    """(robot_server, mostar_web, source, screenshot_copy or None) from a test's command line
    `ROBOT_SERVER MOSTAR_WEB SOURCE_DIR [--screenshot PATH]`, or an exit status: 2 after
    printing `doc` when the arguments are wrong, SKIP when `browser` and chromium or chromedriver
    is missing."""
    args = argv[1:]
    screenshot = None
    if len(args) == 5 and args[3] == "--screenshot":
        screenshot = args.pop(4)
        args.pop(3)
    if len(args) != 3:
        print(doc)
        return 2
    if browser:
        for tool in (CHROMIUM, CHROMEDRIVER):
            if not os.path.exists(tool):
                print("SKIP: %s is missing (deploy/install-deps.sh installs chromium and "
                      "chromium-driver)" % tool)
                return SKIP
    return args[0], args[1], args[2], screenshot


class Programs:
    """robot_server on the simulator and mostar_web, on a DDS domain of their own, in a fresh
    temporary directory; stopped (SIGTERM, then SIGKILL) by stop()."""

    def __init__(self, robot_server, mostar_web, source_dir, web_args=(), server_args=()):
        self.work = tempfile.mkdtemp(prefix="mostar_web_test_")
        self.source = source_dir
        self.procs = []
        self.report = None
        # Loopback test scripts use DDS domains [10, 99] (docs/architecture.md).
        self.domain = 10 + os.getpid() % 90
        self.cert = os.path.join(self.work, "web.cert.pem")
        self.key = os.path.join(self.work, "web.key.pem")
        subprocess.run(
            ["openssl", "req", "-x509", "-newkey", "ec", "-pkeyopt", "ec_paramgen_curve:prime256v1",
             "-nodes", "-keyout", self.key, "-out", self.cert, "-days", "1", "-subj", "/CN=localhost",
             "-addext", "subjectAltName=DNS:localhost,IP:127.0.0.1"],
            check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        self.tokens = os.path.join(self.work, "tokens")
        with open(self.tokens, "w") as f:
            f.write("# test observers\nbrowser %s\nbench %s\n" % (TOKEN, BENCH_TOKEN))
        self.robot = self._start(
            "robot_server",
            [robot_server, "--domain", str(self.domain), "--config",
             os.path.join(source_dir, "deploy/config/server_sim.pbtxt"),
             "--log-level", "warning", *server_args])
        self.web_log = os.path.join(self.work, "mostar_web.log")
        self.web = subprocess.Popen(
            [mostar_web, "--domain", str(self.domain), "--config",
             os.path.join(source_dir, "deploy/config/client_sim.pbtxt"), "--cert", self.cert,
             "--key", self.key, "--tokens", self.tokens, "--port", "0", *web_args],
            stdout=subprocess.PIPE, stderr=open(self.web_log, "w"), text=True)
        self.procs.append(self.web)
        self.port = None
        deadline = time.monotonic() + 20
        while time.monotonic() < deadline:
            ready, _, _ = select.select([self.web.stdout], [], [], 0.5)
            if ready:
                line = self.web.stdout.readline()
                m = re.search(r"serving https://[^:]+:(\d+)/", line)
                if m:
                    self.port = int(m.group(1))
                    break
            if self.web.poll() is not None:
                break
        if self.port is None:
            raise RuntimeError("mostar_web did not start: " + open(self.web_log).read())

    def _start(self, name, argv):
        log = open(os.path.join(self.work, name + ".log"), "w")
        p = subprocess.Popen(argv, stdout=log, stderr=subprocess.STDOUT)
        self.procs.append(p)
        return p

    def url(self, path="/"):
        return "https://127.0.0.1:%d%s" % (self.port, path)

    def stats(self, token=TOKEN):
        return json.loads(https_get(self.port, "/stats?token=" + token, self.cert)[1])

    def cpu_seconds(self, proc):
        """User + system CPU time of a child so far."""
        fields = open("/proc/%d/stat" % proc.pid).read().rsplit(")", 1)[1].split()
        return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")

    def finish(self, failures):
        """Stops everything, prints the report and, on failure, mostar_web's log (the work
        directory is then kept); returns the exit status."""
        print(self.stop())
        if failures:
            print("--- mostar_web log ---")
            print(open(self.web_log).read()[-3000:])
            print("work dir kept:", self.work)
            return 1
        shutil.rmtree(self.work, ignore_errors=True)
        return 0

    def stop(self):
        """Stops everything (once); returns mostar_web's final report line (or "")."""
        if self.report is not None:
            return self.report
        report = ""
        for p in reversed(self.procs):
            if p.poll() is None:
                p.send_signal(signal.SIGTERM)
        for p in reversed(self.procs):
            try:
                p.wait(timeout=10)
            except subprocess.TimeoutExpired:
                p.kill()
                p.wait()
        if self.web.stdout:
            for line in self.web.stdout.read().splitlines():
                if line.startswith("report:"):
                    report = line
        self.report = report
        return report


def tls_context(cert):
    ctx = ssl.create_default_context(cafile=cert)
    ctx.check_hostname = False  # the certificate names localhost; we dial 127.0.0.1
    return ctx


def https_get(port, path, cert, timeout=5, client_cert=None):
    """(status, body) of a GET over TLS; client_cert: (certificate, key) files to present."""
    ctx = tls_context(cert)
    if client_cert:
        ctx.load_cert_chain(*client_cert)
    with socket.create_connection(("127.0.0.1", port), timeout=timeout) as raw:
        with ctx.wrap_socket(raw, server_hostname="localhost") as s:
            s.sendall(("GET %s HTTP/1.1\r\nHost: localhost\r\nConnection: close\r\n\r\n" % path).encode())
            data = b""
            while True:
                chunk = s.recv(65536)
                if not chunk:
                    break
                data += chunk
    head, _, body = data.partition(b"\r\n\r\n")
    return int(head.split()[1]), body.decode(errors="replace")


class WebSocket:
    """A minimal RFC 6455 client over TLS (client frames masked, as the protocol requires)."""

    def __init__(self, port, cert, token, rcvbuf=None, timeout=5, eyes=1):
        raw = socket.socket(socket.AF_INET, socket.SOCK_STREAM)
        if rcvbuf:
            raw.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, rcvbuf)
        raw.settimeout(timeout)
        raw.connect(("127.0.0.1", port))
        self.sock = tls_context(cert).wrap_socket(raw, server_hostname="localhost")
        key = base64.b64encode(os.urandom(16)).decode()
        self.sock.sendall((
            "GET /ws?eyes=%d&token=%s HTTP/1.1\r\nHost: localhost\r\nUpgrade: websocket\r\n"
            "Connection: Upgrade\r\nSec-WebSocket-Key: %s\r\nSec-WebSocket-Version: 13\r\n\r\n"
            % (eyes, token, key)).encode())
        self.buffer = b""
        while b"\r\n\r\n" not in self.buffer:
            chunk = self.sock.recv(4096)
            if not chunk:
                break
            self.buffer += chunk
        head, _, self.buffer = self.buffer.partition(b"\r\n\r\n")
        self.status = int(head.split()[1]) if head else 0

    def _read(self, n):
        while len(self.buffer) < n:
            chunk = self.sock.recv(1 << 20)
            if not chunk:
                raise ConnectionError("closed")
            self.buffer += chunk
        out, self.buffer = self.buffer[:n], self.buffer[n:]
        return out

    def recv(self):
        """(opcode, payload) of the next data message; answers pings; raises on close."""
        while True:
            b0, b1 = self._read(2)
            opcode = b0 & 0x0F
            n = b1 & 0x7F
            if n == 126:
                n = struct.unpack(">H", self._read(2))[0]
            elif n == 127:
                n = struct.unpack(">Q", self._read(8))[0]
            payload = self._read(n)
            if opcode == 0x9:
                self.send(0xA, payload)
                continue
            if opcode == 0x8:
                raise ConnectionError("close frame")
            return opcode, payload

    def send(self, opcode, payload, mask=True, fin=True, rsv=0):
        header = bytes([(0x80 if fin else 0) | rsv | opcode])
        n = len(payload)
        m = 0x80 if mask else 0
        if n < 126:
            header += bytes([m | n])
        elif n < 65536:
            header += bytes([m | 126]) + struct.pack(">H", n)
        else:
            header += bytes([m | 127]) + struct.pack(">Q", n)
        if mask:
            key = os.urandom(4)
            payload = bytes(b ^ key[i % 4] for i, b in enumerate(payload))
            header += key
        self.sock.sendall(header + payload)

    def finish_close(self):
        """Answers the server's close frame as a browser does: a close frame back, then the
        TLS close_notify, then the socket."""
        try:
            self.send(0x8, b"\x03\xe8")
            self.sock.settimeout(2)
            self.sock.unwrap()
        except (OSError, ValueError):
            pass
        self.close()

    def close(self):
        try:
            self.sock.close()
        except OSError:
            pass


def frame_header(payload):
    """Fields of a frame message's header (operator_client/web/web_messages.h)."""
    magic, header_bytes, sequence, w, h, stamp, scan_stamp = struct.unpack_from("<4sIIHHdd", payload)
    if magic != b"MWF2":
        raise ValueError("not a frame")
    tri, lines, points, mapn, labels, left, right = struct.unpack_from("<7I", payload, 32)
    sonar_tri, sonar_lines, sonar_map_tri, sonar_map_lines, echoes, unseen, obstacles, flags = \
        struct.unpack_from("<4IHHII", payload, 64)
    return {"sequence": sequence, "width": w, "height": h, "stamp": stamp, "scan_stamp": scan_stamp,
            "triangle_vertices": tri, "line_vertices": lines, "point_vertices": points,
            "left_jpeg_bytes": left, "right_jpeg_bytes": right,
            "sonar_triangle_vertices": sonar_tri, "sonar_line_vertices": sonar_lines,
            "sonar_echoes": echoes, "sonar_unseen": unseen, "possible_obstacles": obstacles,
            "edges": bool(flags & 1), "sonar": bool(flags & 2)}


class WebDriver:
    """A chromedriver session (W3C WebDriver over HTTP on loopback) running headless Chromium."""

    def __init__(self, work, chromium=CHROMIUM, chromedriver=CHROMEDRIVER,
                 window=(1280, 800)):
        s = socket.socket()
        s.bind(("127.0.0.1", 0))
        self.port = s.getsockname()[1]
        s.close()
        self.log = os.path.join(work, "chromedriver.log")
        self.proc = subprocess.Popen([chromedriver, "--port=%d" % self.port, "--log-path=" + self.log],
                                     stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        self.base = "http://127.0.0.1:%d" % self.port
        deadline = time.monotonic() + 20
        while True:
            try:
                self._call("GET", "/status")
                break
            except OSError:
                if time.monotonic() > deadline:
                    raise
                time.sleep(0.2)
        profile = tempfile.mkdtemp(prefix="profile_", dir=work)
        args = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
                "--disable-background-networking", "--disable-component-update", "--disable-sync",
                "--disable-dev-shm-usage", "--user-data-dir=" + profile,
                "--window-size=%d,%d" % window, "--force-device-scale-factor=1"]
        caps = {"capabilities": {"alwaysMatch": {
            "browserName": "chrome", "acceptInsecureCerts": True,
            "goog:chromeOptions": {"binary": chromium, "args": args}}}}
        self.session = self._call("POST", "/session", caps)["sessionId"]

    def _call(self, method, path, body=None, timeout=60):
        data = json.dumps(body).encode() if body is not None else None
        req = urllib.request.Request(self.base + path, data=data, method=method,
                                     headers={"Content-Type": "application/json"})
        with urllib.request.urlopen(req, timeout=timeout) as r:
            return json.loads(r.read())["value"]

    def get(self, url):
        self._call("POST", "/session/%s/url" % self.session, {"url": url})

    def js(self, script, *args):
        return self._call("POST", "/session/%s/execute/sync" % self.session,
                          {"script": script, "args": list(args)})

    def screenshot_png(self):
        return base64.b64decode(self._call("GET", "/session/%s/screenshot" % self.session))

    def quit(self):
        try:
            self._call("DELETE", "/session/%s" % self.session, timeout=20)
        except OSError:
            pass
        self.proc.terminate()
        try:
            self.proc.wait(timeout=10)
        except subprocess.TimeoutExpired:
            self.proc.kill()
            self.proc.wait()


def read_png(data):
    """(width, height, rows) of an 8-bit RGB or RGBA non-interlaced PNG; rows[y][x] = (r, g, b)."""
    assert data[:8] == b"\x89PNG\r\n\x1a\n", "not a PNG"
    pos = 8
    idat = b""
    while pos < len(data):
        n, kind = struct.unpack(">I4s", data[pos:pos + 8])
        chunk = data[pos + 8:pos + 8 + n]
        pos += 12 + n
        if kind == b"IHDR":
            w, h, depth, color, _, _, interlace = struct.unpack(">IIBBBBB", chunk)
            assert depth == 8 and color in (2, 6) and interlace == 0, "unsupported PNG"
            bpp = 4 if color == 6 else 3
        elif kind == b"IDAT":
            idat += chunk
    raw = zlib.decompress(idat)
    stride = w * bpp
    rows = []
    prev = bytearray(stride)
    i = 0
    for _ in range(h):
        f = raw[i]
        line = bytearray(raw[i + 1:i + 1 + stride])
        i += 1 + stride
        for x in range(stride):
            a = line[x - bpp] if x >= bpp else 0
            b = prev[x]
            c = prev[x - bpp] if x >= bpp else 0
            if f == 1:
                line[x] = (line[x] + a) & 0xFF
            elif f == 2:
                line[x] = (line[x] + b) & 0xFF
            elif f == 3:
                line[x] = (line[x] + (a + b) // 2) & 0xFF
            elif f == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                line[x] = (line[x] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 0xFF
        rows.append([tuple(line[x * bpp:x * bpp + 3]) for x in range(w)])
        prev = line
    return w, h, rows
