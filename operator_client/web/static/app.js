// mostar observer page: draws the frames and HUD mostar_web streams over the WebSocket.
// The overlay arrives as vertices in image pixels (projected by the console's C++ camera
// model on the server); this page only draws them. Frame layout: web_messages.h.
'use strict';

const $ = (id) => document.getElementById(id);
const imageCanvas = $('image');
const imageCtx = imageCanvas.getContext('2d');
const mapCanvas = $('map');
const mapCtx = mapCanvas.getContext('2d');

// Counters for people and for tests (read through window.mostar).
const stats = {
  connected: false, framesReceived: 0, framesShown: 0, framesSkipped: 0, badMessages: 0,
  hudReceived: 0, lastSequence: 0, lastHudSequence: 0, refused: 0, lastAgeMs: -1,
  framesWithEdges: 0,
};
let lastFrame = null;       // the frame shown last (decoded)
let lastHud = null;         // the HUD received last
let frozen = false;         // tests: keep the shown frame (window.mostar.freeze)
let pendingFrame = null;    // the newest frame waiting for the image decoder
let decoding = false;

function token() {
  const m = /(?:^|[#&])token=([^&]*)/.exec(location.hash);
  if (m) {
    sessionStorage.setItem('mostar_token', decodeURIComponent(m[1]));
    history.replaceState(null, '', location.pathname);  // keep the token out of the address bar
  }
  return sessionStorage.getItem('mostar_token') || '';
}

function pad4(n) { return (n + 3) & ~3; }

// One frame message -> plain object; throws on a malformed message.
function decodeFrame(buffer) {
  const dv = new DataView(buffer);
  if (buffer.byteLength < 96 || dv.getUint32(0, true) !== 0x3246574d) {  // "MWF2"
    throw new Error('not a frame');
  }
  const f = {
    headerBytes: dv.getUint32(4, true), sequence: dv.getUint32(8, true),
    width: dv.getUint16(12, true), height: dv.getUint16(14, true),
    stamp: dv.getFloat64(16, true), scanStamp: dv.getFloat64(24, true),
    pointSize: dv.getFloat32(60, true),
    sonarEchoes: dv.getUint16(80, true), sonarUnseen: dv.getUint16(82, true),
    possibleObstacles: dv.getUint32(84, true), flags: dv.getUint32(88, true),
  };
  f.edges = (f.flags & 1) !== 0;  // kFrameEdges
  f.sonar = (f.flags & 2) !== 0;  // kFrameSonar
  const counts = [32, 36, 40, 44, 64, 68, 72, 76].map((o) => dv.getUint32(o, true));
  const labelBytes = dv.getUint32(48, true);
  const leftBytes = dv.getUint32(52, true);
  const rightBytes = dv.getUint32(56, true);
  let offset = f.headerBytes;
  const take = (bytes) => {
    if (offset + bytes > buffer.byteLength) throw new Error('truncated frame');
    const start = offset;
    offset = pad4(offset + bytes);
    return start;
  };
  const vertices = (n) => ({
    n, xy: new Float32Array(buffer, take(8 * n), 2 * n), rgba: new Uint8Array(buffer, take(4 * n), 4 * n),
  });
  f.triangles = vertices(counts[0]);
  f.lines = vertices(counts[1]);
  f.points = vertices(counts[2]);
  f.map = vertices(counts[3]);
  f.sonarTriangles = vertices(counts[4]);
  f.sonarLines = vertices(counts[5]);
  f.sonarMapTriangles = vertices(counts[6]);
  f.sonarMapLines = vertices(counts[7]);
  f.labels = JSON.parse(new TextDecoder().decode(new Uint8Array(buffer, take(labelBytes), labelBytes)));
  f.left = new Blob([new Uint8Array(buffer, take(leftBytes), leftBytes)], { type: 'image/jpeg' });
  f.right = rightBytes > 0
    ? new Blob([new Uint8Array(buffer, take(rightBytes), rightBytes)], { type: 'image/jpeg' }) : null;
  return f;
}

function rgba(c, i, alphaScale = 1) {
  return `rgba(${c[4 * i]},${c[4 * i + 1]},${c[4 * i + 2]},${(c[4 * i + 3] / 255) * alphaScale})`;
}

// Red-cyan anaglyph: red from the left eye, green and blue from the right.
function anaglyph(left, right, w, h) {
  const scratch = new OffscreenCanvas(w, h);
  const ctx = scratch.getContext('2d');
  ctx.drawImage(left, 0, 0, w, h);
  const l = ctx.getImageData(0, 0, w, h);
  ctx.drawImage(right, 0, 0, w, h);
  const r = ctx.getImageData(0, 0, w, h);
  for (let i = 0; i < l.data.length; i += 4) {
    l.data[i + 1] = r.data[i + 1];
    l.data[i + 2] = r.data[i + 2];
  }
  return l;
}

// Image pixel (u, v) (OpenCV: (0, 0) is the centre of the top-left pixel) -> canvas coordinates.
const X = (u) => u + 0.5;
const Y = (v) => v + 0.5;

// Triangles, one colour each: the mean of its vertices' (walls fade towards the top).
function fillTriangles(ctx, t, toX, toY) {
  for (let i = 0; i + 2 < t.n; i += 3) {
    const c = [0, 0, 0, 0];
    for (let k = 0; k < 3; ++k) for (let j = 0; j < 4; ++j) c[j] += t.rgba[4 * (i + k) + j] / 3;
    ctx.fillStyle = `rgba(${c[0] | 0},${c[1] | 0},${c[2] | 0},${c[3] / 255})`;
    ctx.beginPath();
    ctx.moveTo(toX(t.xy[2 * i], t.xy[2 * i + 1]), toY(t.xy[2 * i], t.xy[2 * i + 1]));
    ctx.lineTo(toX(t.xy[2 * i + 2], t.xy[2 * i + 3]), toY(t.xy[2 * i + 2], t.xy[2 * i + 3]));
    ctx.lineTo(toX(t.xy[2 * i + 4], t.xy[2 * i + 5]), toY(t.xy[2 * i + 4], t.xy[2 * i + 5]));
    ctx.closePath();
    ctx.fill();
  }
}

function strokeLines(ctx, l, toX, toY, width) {
  ctx.lineWidth = width;
  for (let i = 0; i + 1 < l.n; i += 2) {
    ctx.strokeStyle = rgba(l.rgba, i);
    ctx.beginPath();
    ctx.moveTo(toX(l.xy[2 * i], l.xy[2 * i + 1]), toY(l.xy[2 * i], l.xy[2 * i + 1]));
    ctx.lineTo(toX(l.xy[2 * i + 2], l.xy[2 * i + 3]), toY(l.xy[2 * i + 2], l.xy[2 * i + 3]));
    ctx.stroke();
  }
}

const imageX = (u) => X(u);
const imageY = (u, v) => Y(v);

function drawOverlay(ctx, f) {
  // Sonar sectors on the floor first (under the walls, as in the console), their outlines
  // (sectors the laser does not see) over everything but the labels.
  fillTriangles(ctx, f.sonarTriangles, imageX, imageY);
  fillTriangles(ctx, f.triangles, imageX, imageY);
  strokeLines(ctx, f.lines, imageX, imageY, 1.5);
  strokeLines(ctx, f.sonarLines, imageX, imageY, 2.5);
  const p = f.points;
  const s = f.pointSize;
  for (let i = 0; i < p.n; ++i) {
    ctx.fillStyle = rgba(p.rgba, i);
    ctx.fillRect(X(p.xy[2 * i]) - s / 2, Y(p.xy[2 * i + 1]) - s / 2, s, s);
  }
  ctx.font = 'bold 15px sans-serif';
  ctx.textAlign = 'center';
  ctx.textBaseline = 'bottom';
  for (const label of f.labels) {
    const w = ctx.measureText(label.t).width;
    ctx.fillStyle = 'rgba(0,0,0,0.67)';
    ctx.fillRect(X(label.u) - w / 2 - 4, Y(label.v) - 22, w + 8, 22);
    ctx.fillStyle = label.c;
    ctx.fillText(label.t, X(label.u), Y(label.v) - 3);
  }
}

// Bumper segment colours as the console's map: pressed segments blink (2 Hz), latched ones
// stay red until the pilot re-arms.
function segmentColor(look, flashOn) {
  if (look === 'pressed') return flashOn ? 'rgb(255,40,40)' : 'rgb(120,20,20)';
  if (look === 'latched') return 'rgb(255,40,40)';
  return 'rgba(80,160,255,0.63)';
}
const flashOn = () => Math.floor(Date.now() / 250) % 2 === 0;

// Bird's-eye map as the console draws it: robot 40 px above the bottom centre, forward up, 4 m
// ahead; sonar fans under the laser points; the robot outline one arc per bumper segment.
function drawMap(f) {
  const size = mapCanvas.width;
  const rangeM = 4;
  const scale = size / (2 * rangeM);
  const rx = size / 2;
  const ry = size - 40;
  // Laser frame (x forward, y left, metres) -> map canvas.
  const mapX = (x, y) => rx - y * scale;
  const mapY = (x) => ry - x * scale;
  mapCtx.fillStyle = '#000';
  mapCtx.fillRect(0, 0, size, size);
  for (let r = 0.5; r <= 2 * rangeM; r += 0.5) {
    mapCtx.strokeStyle = `rgba(255,255,255,${Number.isInteger(r) ? 0.27 : 0.14})`;
    mapCtx.lineWidth = 1;
    mapCtx.beginPath();
    mapCtx.arc(rx, ry, r * scale, 0, 2 * Math.PI);
    mapCtx.stroke();
  }
  fillTriangles(mapCtx, f.sonarMapTriangles, mapX, mapY);
  strokeLines(mapCtx, f.sonarMapLines, mapX, mapY, 1.5);
  const m = f.map;
  for (let i = 0; i < m.n; ++i) {
    mapCtx.fillStyle = rgba(m.rgba, i);
    mapCtx.fillRect(mapX(m.xy[2 * i], m.xy[2 * i + 1]) - 1.5, mapY(m.xy[2 * i]) - 1.5, 3, 3);
  }
  const b = lastHud && lastHud.bumpers;
  const radius = Math.max(4, (b && b.radius_m > 0 ? b.radius_m : 0.3) * scale);
  const segments = b ? b.segments : [];
  const flash = flashOn();
  if (segments.length === 0) {
    mapCtx.strokeStyle = 'rgba(80,160,255,0.63)';
    mapCtx.lineWidth = 1.5;
    mapCtx.beginPath();
    mapCtx.arc(rx, ry, radius, 0, 2 * Math.PI);
    mapCtx.stroke();
  }
  segments.forEach((look, i) => {
    // Segment i centred at i x 360/N degrees counter-clockwise from ahead (screen up), with a
    // small gap between segments.
    const width = (2 * Math.PI) / segments.length;
    const centre = i * width;
    mapCtx.strokeStyle = segmentColor(look, flash);
    mapCtx.lineWidth = look === 'idle' ? 2 : 4;
    mapCtx.beginPath();
    for (let k = 0; k <= 6; ++k) {
      const a = centre - 0.45 * width + (0.9 * width * k) / 6;
      const x = rx - Math.sin(a) * radius;
      const y = ry - Math.cos(a) * radius;
      if (k === 0) mapCtx.moveTo(x, y); else mapCtx.lineTo(x, y);
    }
    mapCtx.stroke();
  });
  mapCtx.fillStyle = 'rgb(80,160,255)';
  mapCtx.beginPath();
  mapCtx.moveTo(rx, ry - 9);
  mapCtx.lineTo(rx - 6, ry + 4);
  mapCtx.lineTo(rx + 6, ry + 4);
  mapCtx.fill();
}

async function show(f) {
  const left = await createImageBitmap(f.left);
  if (frozen) {
    left.close();
    return;
  }
  if (imageCanvas.width !== f.width || imageCanvas.height !== f.height) {
    imageCanvas.width = f.width;
    imageCanvas.height = f.height;
  }
  if ($('view').value === 'anaglyph' && f.right) {
    const right = await createImageBitmap(f.right);
    imageCtx.putImageData(anaglyph(left, right, f.width, f.height), 0, 0);
    right.close();
  } else {
    imageCtx.drawImage(left, 0, 0, f.width, f.height);
  }
  left.close();
  if ($('overlay').checked) drawOverlay(imageCtx, f);
  drawMap(f);
  lastFrame = f;
  stats.framesShown += 1;
  stats.lastSequence = f.sequence;
  stats.lastAgeMs = Date.now() - f.stamp * 1000;
  stats.framesWithEdges += f.edges ? 1 : 0;
  $('hud-sonar').textContent = !f.sonar ? 'no sonar cycle'
    : `${f.sonarEchoes} echoes` + (f.sonarUnseen > 0 ? `, ${f.sonarUnseen} not seen by the laser` : '');
  $('hud-sonar').className = f.sonarUnseen > 0 ? 'magenta' : '';
  $('hud-edges').textContent = f.edges ? `${f.possibleObstacles} possible obstacles` : 'no result for this frame';
}

// The newest frame only: while one is being decoded and drawn, a newer one replaces the waiting
// one (this browser's own queue of one).
function offer(f) {
  if (frozen) return;
  if (pendingFrame) stats.framesSkipped += 1;
  pendingFrame = f;
  if (decoding) return;
  decoding = true;
  (async () => {
    while (pendingFrame) {
      const next = pendingFrame;
      pendingFrame = null;
      try {
        await show(next);
      } catch (e) {
        stats.badMessages += 1;
      }
    }
    decoding = false;
  })();
}

// The bumper line and banner; pressed segments blink, so this runs on a timer as well.
function showBumpers() {
  const b = lastHud && lastHud.bumpers;
  const cell = $('hud-bumpers');
  const banner = $('bumper-alert');
  if (!b || b.segments.length === 0) {
    cell.textContent = b ? 'none' : '?';
    cell.className = '';
    banner.hidden = true;
    return;
  }
  const hit = b.segments.filter((s) => s !== 'idle').length;
  cell.textContent = b.alert ? (hit > 0 ? `${hit} of ${b.segments.length} hit` : 'unreadable')
    : `${b.segments.length} clear` + (b.stale ? ' (stale)' : '');
  cell.className = b.alert ? 'bad' : 'ok';
  banner.hidden = !b.status;
  banner.textContent = b.status;
  banner.className = flashOn() ? 'banner' : 'banner dim';
}
setInterval(() => {
  showBumpers();
  if (lastFrame) drawMap(lastFrame);
}, 250);

const fmtMs = (v) => (v < 0 ? '-' : `${Math.round(v)} ms`);

function showHud(h) {
  stats.hudReceived += 1;
  stats.lastHudSequence = h.seq;
  const link = $('hud-link');
  link.textContent = h.link;
  link.className = h.link === 'ok' ? 'ok' : 'bad';
  $('robot').textContent = h.robot ? `- ${h.robot}` : '';
  $('hud-pilot').textContent = h.pilot || '(nobody)';
  $('hud-watchdog').textContent = h.watchdog || '?';
  $('hud-estop').textContent = h.estop ? 'ENGAGED' : 'released';
  $('hud-estop').className = h.estop ? 'bad' : 'ok';
  lastHud = h;
  showBumpers();
  $('estop').hidden = !h.estop;
  $('security').hidden = !h.dds_security_off;
  $('hud-frame-age').textContent = fmtMs(h.frame_age_ms);
  $('hud-scan-age').textContent = fmtMs(h.scan_age_ms);
  $('hud-video').textContent = `${h.video_fps.toFixed(1)} fps, scans ${h.scan_hz.toFixed(1)} Hz`;
  $('hud-browser').textContent =
      `${stats.framesShown} frames shown, ${stats.framesSkipped} skipped, age ${fmtMs(stats.lastAgeMs)}`;
  $('hud-browsers').textContent = String(h.browsers);
  $('hud-seq').textContent = String(h.seq);
  const list = $('warnings');
  list.replaceChildren(...h.warnings.map((w) => {
    const li = document.createElement('li');
    li.textContent = w;
    return li;
  }));
}

let socket = null;
let retryMs = 1000;

function connect() {
  const t = token();
  if (!t) {
    $('login').hidden = false;
    return;
  }
  const eyes = $('view').value === 'anaglyph' ? 2 : 1;
  const url = `wss://${location.host}/ws?eyes=${eyes}&token=${encodeURIComponent(t)}`;
  const ws = new WebSocket(url);
  socket = ws;
  ws.binaryType = 'arraybuffer';
  let opened = false;
  ws.onopen = () => {
    opened = true;
    retryMs = 1000;
    stats.connected = true;
    $('connection').textContent = 'live';
    $('connection').className = 'ok';
    $('login').hidden = true;
  };
  ws.onmessage = (event) => {
    try {
      if (typeof event.data === 'string') {
        showHud(JSON.parse(event.data));
      } else {
        stats.framesReceived += 1;
        offer(decodeFrame(event.data));
      }
    } catch (e) {
      stats.badMessages += 1;
    }
  };
  ws.onclose = () => {
    stats.connected = false;
    if (socket !== ws) return;  // replaced on purpose (view change)
    $('connection').textContent = opened ? 'disconnected' : 'refused or unreachable';
    $('connection').className = 'bad';
    if (!opened) {
      stats.refused += 1;
      $('login-error').textContent = 'not accepted: check the token';
      $('login').hidden = false;
    }
    setTimeout(connect, retryMs);
    retryMs = Math.min(retryMs * 2, 10000);
  };
}

$('login').addEventListener('submit', (event) => {
  event.preventDefault();
  sessionStorage.setItem('mostar_token', $('token').value.trim());
  if (socket) socket.close(1000, 'new token');
  socket = null;
  connect();
});
$('view').addEventListener('change', () => {
  const old = socket;
  socket = null;
  if (old) old.close(1000, 'view changed');
  connect();
});

// For tests and debugging: counters, and the overlay's wall triangles' centroids in CSS pixels
// of the page (where a screenshot shows them).
window.mostar = {
  stats,
  wallCentroids(max = 50) {
    const f = lastFrame;
    if (!f) return [];
    const box = imageCanvas.getBoundingClientRect();
    const sx = box.width / imageCanvas.width;
    const sy = box.height / imageCanvas.height;
    const out = [];
    const t = f.triangles;
    const step = Math.max(1, Math.floor(t.n / 3 / max));
    for (let i = 0; i + 2 < t.n; i += 3 * step) {
      const u = (t.xy[2 * i] + t.xy[2 * i + 2] + t.xy[2 * i + 4]) / 3;
      const v = (t.xy[2 * i + 1] + t.xy[2 * i + 3] + t.xy[2 * i + 5]) / 3;
      if (u < 0 || v < 0 || u > imageCanvas.width - 1 || v > imageCanvas.height - 1) continue;
      out.push({ x: box.left + X(u) * sx, y: box.top + Y(v) * sy, rgba: Array.from(t.rgba.slice(4 * i, 4 * i + 4)) });
    }
    return out;
  },
  // The sonar outlines' segment midpoints and the magenta dots (possible obstacles), in CSS
  // pixels of the page, for the tests.
  sonarOutlineMidpoints() { return this.pagePoints('sonarLines', 2); },
  obstacleDots() {
    const f = lastFrame;
    if (!f) return [];
    const out = this.pagePoints('points', 1);
    return out.filter((p) => p.rgba[0] === 255 && p.rgba[1] === 0 && p.rgba[2] === 255);
  },
  pagePoints(section, step) {
    const f = lastFrame;
    if (!f) return [];
    const box = imageCanvas.getBoundingClientRect();
    const sx = box.width / imageCanvas.width;
    const sy = box.height / imageCanvas.height;
    const s = f[section];
    const out = [];
    for (let i = 0; i + step - 1 < s.n; i += step) {
      let u = 0;
      let v = 0;
      for (let k = 0; k < step; ++k) {
        u += s.xy[2 * (i + k)] / step;
        v += s.xy[2 * (i + k) + 1] / step;
      }
      if (u < 0 || v < 0 || u > imageCanvas.width - 1 || v > imageCanvas.height - 1) continue;
      out.push({ x: box.left + X(u) * sx, y: box.top + Y(v) * sy, rgba: Array.from(s.rgba.slice(4 * i, 4 * i + 4)) });
    }
    return out;
  },
  // Tests: while frozen, the page keeps the frame it shows (a screenshot then matches the
  // frame the test read) and drops the frames that come.
  freeze(on) { frozen = on; },
  lastFrameInfo() {
    const f = lastFrame;
    return f ? { sequence: f.sequence, edges: f.edges, sonar: f.sonar, sonarEchoes: f.sonarEchoes,
      sonarUnseen: f.sonarUnseen, possibleObstacles: f.possibleObstacles } : null;
  },
  imageBox() {
    const b = imageCanvas.getBoundingClientRect();
    return { left: b.left, top: b.top, width: b.width, height: b.height, w: imageCanvas.width, h: imageCanvas.height };
  },
};

connect();
