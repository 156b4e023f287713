// The workbench page: a virtualised grid over the server's JSON API. Everything the page shows
// is computed by the server (values as formatted, errors explained, geometry, NC programs and
// backplots); the page only lays out and draws.
'use strict';

const TOKEN = new URLSearchParams(location.search).get('t') || '';
const ROW_H = 20, HEAD_W = 50, HEAD_H = 20, DEFAULT_W = 64;
// How far past the screen a fetched window reaches, so that scrolling a little needs no fetch.
const MARGIN_ROWS = 60, MARGIN_COLS = 6, MAX_ROWS = 999, MAX_COLS = 199;

const $ = (id) => document.getElementById(id);
const scroller = $('scroller');

let book = null;          // the server's summary: file, sheets, notes, history
let sheet = 0;            // the sheet shown
let nrows = 100, ncols = 26;
let colX = [0];           // left edge of each column, and the right edge of the last
let cells = new Map();    // key(r, c) -> cell of the fetched window
let fetched = null;       // the window `cells` holds: {sheet, r0, r1, c0, c1}
let fetching = false;
let sel = { r: 0, c: 0 };
let marks = { prec: [], dep: [] }; // rectangles on the shown sheet
let runMoves = [];
let dialects = [];        // {name, machines} from the server
let program = null;       // the last run's program text and file name

const key = (r, c) => r * 16384 + c;

function colName(c) {
  let s = '';
  for (c += 1; c > 0; c = Math.floor((c - 1) / 26)) s = String.fromCharCode(65 + ((c - 1) % 26)) + s;
  return s;
}

function esc(text) {
  return String(text).replace(/[&<>"']/g, (ch) => ({ '&': '&amp;', '<': '&lt;', '>': '&gt;', '"': '&quot;', "'": '&#39;' }[ch]));
}

function status(text, bad) {
  $('status').textContent = text;
  $('status').className = bad ? 'bad' : '';
}

async function api(path, body) {
  const init = { headers: { 'x-ncsheet-token': TOKEN } };
  if (body !== undefined) {
    init.method = 'POST';
    init.headers['content-type'] = 'application/json';
    init.body = JSON.stringify(body);
  }
  const response = await fetch(path, init);
  const text = await response.text();
  let data = null;
  try { data = JSON.parse(text); } catch (e) { data = null; }
  if (!response.ok) throw new Error((data && data.error) || text || response.statusText);
  return data;
}

function query(params) {
  return Object.entries(params).map(([k, v]) => k + '=' + encodeURIComponent(v)).join('&');
}

// ---- layout -------------------------------------------------------------------------------

function layoutSheet() {
  const s = book.sheets[sheet];
  nrows = Math.min(1048576, Math.max(s.rows + 50, 100));
  ncols = Math.min(16384, Math.max(s.cols + 5, 26));
  const widths = new Map(s.widths.map(([c, w]) => [c, Math.round(w * 7 + 5)]));
  colX = [0];
  for (let c = 0; c < ncols; c++) colX.push(colX[c] + (widths.get(c) || DEFAULT_W));
  $('spacer').style.width = (HEAD_W + colX[ncols]) + 'px';
  $('spacer').style.height = (HEAD_H + nrows * ROW_H) + 'px';
  $('corner').style.width = HEAD_W + 'px';
  $('corner').style.height = HEAD_H + 'px';
}

function colAt(x) {
  let lo = 0, hi = ncols - 1;
  while (lo < hi) {
    const mid = (lo + hi + 1) >> 1;
    if (colX[mid] <= x) lo = mid; else hi = mid - 1;
  }
  return lo;
}

function visible() {
  const top = scroller.scrollTop, left = scroller.scrollLeft;
  const r0 = Math.min(nrows - 1, Math.floor(top / ROW_H));
  const r1 = Math.min(nrows - 1, Math.floor((top + scroller.clientHeight - HEAD_H) / ROW_H) + 1);
  const c0 = colAt(left);
  const c1 = colAt(left + scroller.clientWidth - HEAD_W);
  return { r0, r1, c0, c1 };
}

function inside(rect, r, c) {
  return r >= rect.r0 && r <= rect.r1 && c >= rect.c0 && c <= rect.c1;
}

// ---- drawing ------------------------------------------------------------------------------

function render() {
  if (!book) return;
  const v = visible();
  const top = scroller.scrollTop, left = scroller.scrollLeft;
  const out = [];
  for (let r = v.r0; r <= v.r1; r++) {
    for (let c = v.c0; c <= v.c1; c++) {
      const cell = cells.get(key(r, c));
      let cls = 'c';
      if (cell && cell.num !== undefined) cls += ' num';
      if (cell && cell.explain) cls += ' err';
      if (cell && cell.spill) cls += ' spill';
      if (r === sel.r && c === sel.c) cls += ' sel';
      if (marks.prec.some((m) => inside(m, r, c))) cls += ' prec';
      if (marks.dep.some((m) => inside(m, r, c))) cls += ' dep';
      const title = cell && cell.explain ? ' title="' + esc(cell.explain) + '"' : '';
      out.push('<div class="' + cls + '" data-cell="' + colName(c) + (r + 1) + '" data-r="' + r + '" data-c="' + c + '"' + title +
        ' style="left:' + (HEAD_W + colX[c]) + 'px;top:' + (HEAD_H + r * ROW_H) + 'px;width:' + (colX[c + 1] - colX[c]) + 'px">' +
        (cell ? esc(cell.shown) : '') + '</div>');
    }
  }
  $('cells').innerHTML = out.join('');
  const heads = [];
  for (let c = v.c0; c <= v.c1; c++) {
    heads.push('<div class="h" style="left:' + (HEAD_W + colX[c]) + 'px;top:0;width:' + (colX[c + 1] - colX[c]) + 'px">' + colName(c) + '</div>');
  }
  $('colhead').innerHTML = heads.join('');
  $('colhead').style.transform = 'translateY(' + top + 'px)';
  const rows = [];
  for (let r = v.r0; r <= v.r1; r++) {
    rows.push('<div class="h" style="left:0;top:' + (HEAD_H + r * ROW_H) + 'px;width:' + HEAD_W + 'px">' + (r + 1) + '</div>');
  }
  $('rowhead').innerHTML = rows.join('');
  $('rowhead').style.transform = 'translateX(' + left + 'px)';
  $('corner').style.transform = 'translate(' + left + 'px,' + top + 'px)';
  if (!fetched || fetched.sheet !== sheet || !inside(fetched, v.r0, v.c0) || !inside(fetched, v.r1, v.c1)) fetchWindow(v);
}

async function fetchWindow(v) {
  if (fetching) return;
  fetching = true;
  const w = {
    sheet,
    r0: Math.max(0, v.r0 - MARGIN_ROWS), c0: Math.max(0, v.c0 - MARGIN_COLS),
  };
  w.r1 = Math.min(nrows - 1, w.r0 + Math.min(MAX_ROWS, v.r1 - w.r0 + MARGIN_ROWS));
  w.c1 = Math.min(ncols - 1, w.c0 + Math.min(MAX_COLS, v.c1 - w.c0 + MARGIN_COLS));
  try {
    const data = await api('/api/cells?' + query(w));
    if (w.sheet === sheet) {
      cells = new Map(data.cells.map((cell) => [key(cell.r, cell.c), cell]));
      fetched = w;
    }
  } catch (e) {
    status(e.message, true);
  } finally {
    fetching = false;
  }
  render();
  showSelection();
}

function scrollIntoView(r, c) {
  const x = colX[c], y = r * ROW_H;
  const w = scroller.clientWidth - HEAD_W, h = scroller.clientHeight - HEAD_H;
  if (y < scroller.scrollTop) scroller.scrollTop = y;
  else if (y + ROW_H > scroller.scrollTop + h) scroller.scrollTop = y + ROW_H - h;
  if (x < scroller.scrollLeft) scroller.scrollLeft = x;
  else if (colX[c + 1] > scroller.scrollLeft + w) scroller.scrollLeft = colX[c + 1] - w;
}

// ---- selection, inspection ----------------------------------------------------------------

function showSelection() {
  const cell = cells.get(key(sel.r, sel.c));
  $('namebox').value = colName(sel.c) + (sel.r + 1);
  if (document.activeElement !== $('formula')) $('formula').value = cell ? cell.input : '';
}

let inspectTimer = null;
function select(r, c) {
  sel = { r: Math.max(0, Math.min(nrows - 1, r)), c: Math.max(0, Math.min(ncols - 1, c)) };
  scrollIntoView(sel.r, sel.c);
  showSelection();
  render();
  clearTimeout(inspectTimer);
  inspectTimer = setTimeout(inspect, 120);
}

async function inspect() {
  const at = { sheet, r: sel.r, c: sel.c };
  try {
    const data = await api('/api/inspect?' + query(at));
    const here = (list) => list.filter((m) => m.sheet === sheet);
    marks = { prec: here(data.precedents), dep: here(data.dependents) };
    const link = (m) => '<a data-sheet="' + m.sheet + '" data-r="' + m.r0 + '" data-c="' + m.c0 + '">' + esc(m.name) + '</a>';
    $('links').innerHTML = '<div><b>' + esc(data.cell) + '</b></div>' +
      '<div>reads: ' + (data.precedents.map(link).join('') || '—') + '</div>' +
      '<div>read by: ' + (data.dependents.map(link).join('') || '—') + '</div>';
    render();
  } catch (e) {
    status(e.message, true);
  }
  const cell = cells.get(key(sel.r, sel.c));
  if (cell && /CHAMFER/i.test(cell.input)) drawChamfer(at);
  if (cell && /ARCH_FIT/i.test(cell.input)) drawArchFit(at);
  if (cell && /BALLPATH/i.test(cell.input)) drawBallPath(at);
}

async function goTo(targetSheet, r, c) {
  if (targetSheet !== sheet) await showSheet(targetSheet);
  select(r, c);
}

// ---- edits --------------------------------------------------------------------------------

function applyChanges(data) {
  if (fetched && data.sheet === fetched.sheet) {
    for (const cell of data.changed) {
      if (cell.shown === '' && cell.input === '') cells.delete(key(cell.r, cell.c));
      else cells.set(key(cell.r, cell.c), cell);
    }
  }
  showHistory(data.history);
  status(data.problems && data.problems.length ? data.problems.join('  ') : data.cell + ': ' + data.changed.length + ' cell(s) changed on screen', data.problems && data.problems.length);
  render();
  showSelection();
}

function showHistory(h) {
  if (!h) return;
  book.history = h;
  $('undo').disabled = !h.undo;
  $('redo').disabled = !h.redo;
}

function editWindow() {
  return fetched || { sheet, r0: 0, r1: 0, c0: 0, c1: 0 };
}

async function commit(input, move) {
  try {
    const data = await api('/api/set', { sheet, r: sel.r, c: sel.c, input, window: editWindow() });
    applyChanges(data);
    if (move) select(sel.r + 1, sel.c);
    inspect();
  } catch (e) {
    status(e.message, true);
  }
}

async function history(which) {
  try {
    applyChanges(await api('/api/' + which, { window: editWindow() }));
    inspect();
  } catch (e) {
    status(e.message, true);
  }
}

// ---- sheets -------------------------------------------------------------------------------

async function showSheet(index) {
  sheet = index;
  cells = new Map();
  fetched = null;
  marks = { prec: [], dep: [] };
  layoutSheet();
  scroller.scrollTop = 0;
  scroller.scrollLeft = 0;
  sel = { r: 0, c: 0 };
  [...$('tabs').children].forEach((b, i) => b.classList.toggle('on', i === index));
  render();
}

function drawTabs() {
  $('tabs').innerHTML = book.sheets.map((s, i) => '<button data-sheet="' + i + '">' + esc(s.name) + '</button>').join('');
}

// ---- saving -------------------------------------------------------------------------------

function formatOf(name) {
  const ext = (name.split('.').pop() || '').toLowerCase();
  return ['xlsx', 'xlsm', 'csv'].includes(ext) ? ext : null;
}

// Says what the saved file would lose, and asks, before anything is written.
async function acceptLosses(format, what) {
  const data = await api('/api/losses?' + query({ format, sheet }));
  if (!data.losses.length) return confirm(what + '?');
  return confirm(what + '? The saved file loses:\n\n- ' + data.losses.join('\n- '));
}

async function save(over) {
  try {
    const name = over ? book.file : prompt('Save as (a file name; it is saved beside the workbook):', book.file.replace(/(\.\w+)?$/, '-edited$1'));
    if (!name) return;
    const format = formatOf(name);
    if (!format) return status(name + ': name an .xlsx, .xlsm or .csv file', true);
    if (!(await acceptLosses(format, over ? 'Save over ' + name : 'Save as ' + name))) return;
    const data = await api('/api/save', { name, over, sheet });
    status('saved ' + data.saved);
  } catch (e) {
    status(e.message, true);
  }
}

async function download(format) {
  try {
    if (!(await acceptLosses(format, 'Download as .' + format))) return;
    const response = await fetch('/api/download?' + query({ format, sheet }), { headers: { 'x-ncsheet-token': TOKEN } });
    if (!response.ok) throw new Error(await response.text());
    const blob = await response.blob();
    const disposition = response.headers.get('content-disposition') || '';
    const match = /filename="([^"]*)"/.exec(disposition);
    const a = document.createElement('a');
    a.href = URL.createObjectURL(blob);
    a.download = match ? match[1] : 'workbook.' + format;
    a.click();
    setTimeout(() => URL.revokeObjectURL(a.href), 10000);
  } catch (e) {
    status(e.message, true);
  }
}

// ---- machining pane -----------------------------------------------------------------------

async function drawChamfer(at) {
  try {
    const g = await api('/api/chamfer?' + query(at));
    const pts = [g.a, g.b, g.centre1, g.centre2, g.tip1, g.tip2, { z: 0, x: 0 }];
    const zs = pts.map((p) => p.z), xs = pts.map((p) => p.x);
    const pad = g.nose * 2 + 1;
    const minZ = Math.min(...zs) - pad, maxZ = Math.max(...zs) + pad;
    const minX = Math.min(...xs.filter((x) => x > 0)) - pad, maxX = Math.max(...xs) + pad;
    const W = 400, H = 300, k = Math.min(W / (maxZ - minZ), H / (maxX - minX));
    const X = (z) => ((z - minZ) * k).toFixed(2), Y = (x) => (H - (x - minX) * k).toFixed(2);
    const inner = g.kind !== 'outer';
    // The part: material below the contour (outer) or beyond the bore (inner), face at Z = 0.
    const edge = inner ? maxX : minX;
    const contour = 'M' + X(minZ) + ',' + Y(g.a.x) + ' L' + X(g.a.z) + ',' + Y(g.a.x) + ' L' + X(g.b.z) + ',' + Y(g.b.x) +
      ' L' + X(0) + ',' + Y(edge) + ' L' + X(minZ) + ',' + Y(edge) + ' Z';
    const circle = (c, label, tip) => '<circle cx="' + X(c.z) + '" cy="' + Y(c.x) + '" r="' + (g.nose * k).toFixed(2) + '" fill="none" stroke="#1a73e8"/>' +
      '<circle cx="' + X(tip.z) + '" cy="' + Y(tip.x) + '" r="3" fill="#d93025"/>' +
      '<text x="' + (Number(X(tip.z)) + 5) + '" y="' + (Number(Y(tip.x)) - 5) + '" font-size="12">' + label + '</text>';
    $('chamfer').innerHTML = '<div>' + esc(g.cell) + ': ' + esc(g.kind) + ' chamfer, XA ' + g.xa.toFixed(6) + ' ZA ' + g.za.toFixed(6) +
      ', XB ' + g.xb.toFixed(6) + ' ZB ' + g.zb.toFixed(6) + '</div>' +
      '<svg viewBox="0 0 ' + W + ' ' + H + '"><path d="' + contour + '" fill="#ddd" stroke="#333"/>' +
      '<line x1="' + X(0) + '" y1="0" x2="' + X(0) + '" y2="' + H + '" stroke="#999" stroke-dasharray="4 3"/>' +
      circle(g.centre1, 'T1', g.tip1) + circle(g.centre2, 'T2', g.tip2) + '</svg>';
  } catch (e) {
    $('chamfer').textContent = e.message;
  }
}

// The arcs an ARCH_FIT call fits over the true curve, and the deviation along the curve's
// normal magnified so that its largest reaches a twentieth of the drawing.
async function drawArchFit(at) {
  try {
    const g = await api('/api/archfit?' + query(at));
    const xs = g.curve.map((p) => p.x), ys = g.curve.map((p) => p.y);
    const span = Math.max(Math.max(...xs) - Math.min(...xs), Math.max(...ys) - Math.min(...ys)) || 1;
    const most = Math.max(...g.curve.map((p) => p.d)) || 1e-12;
    const gain = span / 20 / most;
    const pad = span / 12;
    const minX = Math.min(...xs) - pad, maxY = Math.max(...ys) + pad;
    const W = 400, k = W / (span + 2 * pad), H = (Math.max(...ys) - Math.min(...ys) + 2 * pad) * k;
    const X = (x) => ((x - minX) * k).toFixed(2), Y = (y) => ((maxY - y) * k).toFixed(2);
    const curve = 'M' + g.curve.map((p) => X(p.x) + ',' + Y(p.y)).join(' L');
    const magnified = 'M' + g.curve.map((p) => X(p.x + p.n[0] * p.d * gain) + ',' + Y(p.y + p.n[1] * p.d * gain)).join(' L');
    // SVG's y runs down: a counter-clockwise arc in the part is clockwise on screen.
    const arcs = g.arcs.map((a) => '<path class="arc" d="M' + X(a.start[0]) + ',' + Y(a.start[1]) + ' A' + (a.radius * k).toFixed(2) + ',' +
      (a.radius * k).toFixed(2) + ' 0 0 ' + (a.ccw ? 0 : 1) + ' ' + X(a.end[0]) + ',' + Y(a.end[1]) + '" fill="none" stroke="#1f5fd0" stroke-width="2"/>' +
      '<circle cx="' + X(a.end[0]) + '" cy="' + Y(a.end[1]) + '" r="2.5" fill="#1f5fd0"/>').join('');
    $('arcs').innerHTML = '<div>' + esc(g.cell) + ': ' + esc(g.kind) + ' piece, ' + g.arcs.length + ' arcs within ' + g.tolerance +
      ' mm (largest deviation ' + g.deviation.toExponential(2) + ' mm)</div>' +
      '<svg viewBox="0 0 ' + W + ' ' + H.toFixed(1) + '"><path d="' + curve + '" fill="none" stroke="#999" stroke-width="5" stroke-opacity="0.5"/>' + arcs +
      '<path id="deviation" d="' + magnified + '" fill="none" stroke="#d02020" stroke-width="1"/></svg>' +
      '<div class="note">grey: the true curve; blue: the arcs and their joints; red: the deviation ×' + gain.toPrecision(3) + ' along the normal</div>';
  } catch (e) {
    $('arcs').textContent = e.message;
  }
}

// A cam design sheet's discs, each fitted with arcs and drawn by the library.
async function fitCams() {
  try {
    const g = await api('/api/camsheet?' + query({ sheet, tol: $('camtol').value }));
    $('cams').innerHTML = g.discs.map((d) => '<div>disc ' + esc(d.disc) + ': ' + d.arcs + ' arcs</div><img alt="cam ' + esc(d.disc) +
      '" style="width:100%" src="data:image/svg+xml;charset=utf-8,' + encodeURIComponent(d.svg) + '">').join('');
  } catch (e) {
    $('cams').textContent = e.message;
  }
}

// ---- ball path: plan and section from the server, 3D drawn here ----------------------------

let ball = null;                 // {points: Float64Array-like [x,y,z,...], lo, hi}
let orbit = { yaw: -0.6, pitch: 0.9 };

async function drawBallPath(at) {
  try {
    const g = await api('/api/ballpath?' + query(at));
    const svgImg = (svg, alt) => '<img alt="' + alt + '" src="data:image/svg+xml;charset=utf-8,' + encodeURIComponent(svg) + '">';
    $('ballpath').innerHTML = '<div>' + esc(g.cell) + ': ' + g.count + ' points, from ' + g.first.map((v) => v.toFixed(3)).join(', ') +
      ' to ' + g.last.map((v) => v.toFixed(3)).join(', ') + '</div>' +
      '<h2>Plan</h2>' + svgImg(g.plan, 'plan') + '<h2>Section</h2>' + svgImg(g.section, 'section') +
      '<h2>3D</h2><canvas id="view3d" width="800" height="640" title="Drag to orbit"></canvas>';
    ball = { points: g.points, lo: g.stock[0], hi: g.stock[1] };
    draw3d();
    const canvas = $('view3d');
    let from = null;
    canvas.addEventListener('mousedown', (e) => { from = [e.clientX, e.clientY]; });
    window.addEventListener('mouseup', () => { from = null; });
    canvas.addEventListener('mousemove', (e) => {
      if (!from) return;
      orbit.yaw += (e.clientX - from[0]) * 0.01;
      orbit.pitch = Math.max(0, Math.min(Math.PI / 2, orbit.pitch + (e.clientY - from[1]) * 0.01));
      from = [e.clientX, e.clientY];
      requestAnimationFrame(draw3d);
    });
  } catch (e) {
    $('ballpath').textContent = e.message;
  }
}

// The colour of depth t in 0..1, as the plan's: dark blue deep to light yellow high.
function depthColour(t) {
  const stops = [[13, 26, 115], [0, 140, 153], [242, 217, 64]];
  const u = Math.max(0, Math.min(1, t)) * 2, i = u < 1 ? 0 : 1, f = u - i;
  return 'rgb(' + stops[i].map((a, j) => Math.round(a + (stops[i + 1][j] - a) * f)).join(',') + ')';
}

// The path in 3D with the stock's box, orbited by yaw and pitch; segments shorter than a
// pixel on screen are merged, so a million points draw at once.
function draw3d() {
  const canvas = $('view3d');
  if (!canvas || !ball) return;
  const ctx = canvas.getContext('2d');
  const W = canvas.width, H = canvas.height;
  ctx.fillStyle = '#fff';
  ctx.fillRect(0, 0, W, H);
  const [lo, hi] = [ball.lo, ball.hi];
  const mid = [0, 1, 2].map((i) => (lo[i] + hi[i]) / 2);
  const size = Math.max(hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]) || 1;
  const k = 0.62 * Math.min(W, H) / size;
  const [cy, sy, cp, sp] = [Math.cos(orbit.yaw), Math.sin(orbit.yaw), Math.cos(orbit.pitch), Math.sin(orbit.pitch)];
  const project = (x, y, z) => {
    const dx = x - mid[0], dy = y - mid[1], dz = z - mid[2];
    const u = dx * cy - dy * sy, v = dx * sy + dy * cy;
    return [W / 2 + u * k, H / 2 - (dz * sp + v * cp) * k];
  };
  // The stock's box.
  ctx.strokeStyle = '#9a8a5a';
  ctx.lineWidth = 1;
  const corner = (i) => project(i & 1 ? hi[0] : lo[0], i & 2 ? hi[1] : lo[1], i & 4 ? hi[2] : lo[2]);
  ctx.beginPath();
  for (const [a, b] of [[0, 1], [1, 3], [3, 2], [2, 0], [4, 5], [5, 7], [7, 6], [6, 4], [0, 4], [1, 5], [2, 6], [3, 7]]) {
    const p = corner(a), q = corner(b);
    ctx.moveTo(p[0], p[1]);
    ctx.lineTo(q[0], q[1]);
  }
  ctx.stroke();
  // The axes at the stock's lowest corner: X red, Y green, Z blue, a tenth of the box long.
  const o = [lo[0], lo[1], lo[2]], len = size / 5;
  [['X', [len, 0, 0], '#d02020'], ['Y', [0, len, 0], '#1a9a3a'], ['Z', [0, 0, len], '#1f5fd0']].forEach(([name, d, colour]) => {
    const p = project(...o), q = project(o[0] + d[0], o[1] + d[1], o[2] + d[2]);
    ctx.strokeStyle = colour;
    ctx.lineWidth = 2;
    ctx.beginPath(); ctx.moveTo(p[0], p[1]); ctx.lineTo(q[0], q[1]); ctx.stroke();
    ctx.fillStyle = colour;
    ctx.font = '14px sans-serif';
    ctx.fillText(name, q[0] + 3, q[1] - 3);
  });
  const pts = ball.points, zspan = hi[2] - lo[2] || 1;
  ctx.lineWidth = 1.2;
  let last = project(pts[0], pts[1], pts[2]), band = -1;
  ctx.beginPath();
  for (let i = 3; i < pts.length; i += 3) {
    const p = project(pts[i], pts[i + 1], pts[i + 2]);
    const b = Math.min(7, Math.floor((pts[i + 2] - lo[2]) / zspan * 8));
    if (Math.abs(p[0] - last[0]) < 0.7 && Math.abs(p[1] - last[1]) < 0.7 && b === band && i + 3 < pts.length) continue;
    if (b !== band) {
      ctx.stroke();
      ctx.strokeStyle = depthColour(b / 7);
      ctx.beginPath();
      ctx.moveTo(last[0], last[1]);
      band = b;
    }
    ctx.lineTo(p[0], p[1]);
    last = p;
  }
  ctx.stroke();
  ctx.fillStyle = '#333';
  ctx.font = '14px sans-serif';
  ctx.fillText('ball path, ' + (pts.length / 3) + ' points drawn; box ' + [0, 1, 2].map((i) => (hi[i] - lo[i]).toFixed(1)).join(' × ') + ' mm; drag to orbit', 8, H - 10);
}

async function loadMacros() {
  try {
    const data = await api('/api/macros');
    const options = [];
    for (const s of data.sources) {
      for (const sub of s.subs) options.push('<option value="' + esc(s.source) + '|' + esc(sub) + '">' + esc(s.label) + ' — ' + esc(sub) + '</option>');
    }
    $('macro').innerHTML = options.join('') || '<option value="">(no macro)</option>';
    dialects = data.dialects;
    $('machine').innerHTML = data.machines.map((m) => '<option>' + esc(m) + '</option>').join('');
    listDialects();
  } catch (e) {
    status(e.message, true);
  }
}

// The dialects that write programs for the chosen machine.
function listDialects() {
  const chosen = $('dialect').value;
  const able = dialects.filter((d) => d.machines.includes($('machine').value)).map((d) => d.name);
  $('dialect').innerHTML = able.map((d) => '<option' + (d === chosen ? ' selected' : '') + '>' + esc(d) + '</option>').join('');
}

function downloadProgram() {
  if (!program) return;
  const a = document.createElement('a');
  a.href = URL.createObjectURL(new Blob([program.text], { type: 'text/plain' }));
  a.download = program.name;
  a.click();
  setTimeout(() => URL.revokeObjectURL(a.href), 10000);
}

async function runMacro() {
  const [source, sub] = $('macro').value.split('|');
  if (!source) return;
  status('running ' + sub + '…');
  try {
    const data = await api('/api/run', { source, sub, dialect: $('dialect').value, machine: $('machine').value, sheet });
    runMoves = data.moves || [];
    program = data.program ? { text: data.program, name: data.download } : null;
    $('dlprogram').disabled = !program;
    showHistory(data.history);
    $('program').innerHTML = (data.message ? '<div>' + esc(data.message) + '</div>' : '') +
      '<ol>' + data.lines.map((l) => '<li>' + esc(l) + '</li>').join('') + '</ol>' +
      (data.printed.length ? '<pre>' + esc(data.printed.join('\n')) + '</pre>' : '');
    $('backplot').innerHTML = data.svg ? '<img alt="backplot" src="data:image/svg+xml;charset=utf-8,' + encodeURIComponent(data.svg) + '">' : '';
    status(sub + ': ' + data.lines.length + ' lines');
    fetched = null; // the macro may have written cells
    render();
  } catch (e) {
    status(e.message, true);
    // A macro that failed partway keeps its writes (as Excel's does), undoable as one step.
    fetched = null;
    api('/api/sheets').then((b) => showHistory(b.history)).catch(() => {});
    render();
  }
}

// ---- events -------------------------------------------------------------------------------

scroller.addEventListener('scroll', () => requestAnimationFrame(render));
window.addEventListener('resize', render);

$('cells').addEventListener('mousedown', (e) => {
  const div = e.target.closest('.c');
  if (!div) return;
  select(Number(div.dataset.r), Number(div.dataset.c));
  scroller.focus();
});
$('cells').addEventListener('dblclick', () => $('formula').focus());

scroller.addEventListener('keydown', (e) => {
  const moves = { ArrowUp: [-1, 0], ArrowDown: [1, 0], ArrowLeft: [0, -1], ArrowRight: [0, 1], Enter: [1, 0], Tab: [0, 1] };
  if ((e.ctrlKey || e.metaKey) && e.key.toLowerCase() === 'z') { e.preventDefault(); history(e.shiftKey ? 'redo' : 'undo'); return; }
  if ((e.ctrlKey || e.metaKey) && e.key.toLowerCase() === 'y') { e.preventDefault(); history('redo'); return; }
  if (moves[e.key]) { e.preventDefault(); select(sel.r + moves[e.key][0], sel.c + moves[e.key][1]); return; }
  if (e.key === 'F2') { e.preventDefault(); $('formula').focus(); return; }
  if (e.key === 'Delete') { e.preventDefault(); commit('', false); return; }
  if (e.key.length === 1 && !e.ctrlKey && !e.metaKey && !e.altKey) {
    e.preventDefault();
    $('formula').value = e.key;
    $('formula').focus();
  }
});

$('formula').addEventListener('keydown', (e) => {
  if (e.key === 'Enter') { e.preventDefault(); commit($('formula').value, true); scroller.focus(); }
  if (e.key === 'Escape') { e.preventDefault(); showSelection(); scroller.focus(); }
});
$('formula').addEventListener('blur', () => setTimeout(showSelection, 0));

$('namebox').addEventListener('keydown', async (e) => {
  if (e.key !== 'Enter') return;
  e.preventDefault();
  try {
    const at = await api('/api/locate?' + query({ sheet, name: $('namebox').value }));
    await goTo(at.sheet, at.r, at.c);
    scroller.focus();
  } catch (err) {
    status(err.message, true);
  }
});

$('tabs').addEventListener('click', (e) => {
  const b = e.target.closest('button');
  if (b) showSheet(Number(b.dataset.sheet));
});
$('links').addEventListener('click', (e) => {
  const a = e.target.closest('a');
  if (a) goTo(Number(a.dataset.sheet), Number(a.dataset.r), Number(a.dataset.c));
});
$('program').addEventListener('click', (e) => {
  const li = e.target.closest('li');
  if (!li) return;
  const line = [...li.parentNode.children].indexOf(li) + 1;
  [...li.parentNode.children].forEach((x) => x.classList.toggle('on', x === li));
  const move = runMoves.find((m) => m.line === line);
  status(move ? 'line ' + line + ': ' + (move.rapid ? 'rapid' : 'feed') + ' from ' + move.from.map((v) => v.toFixed(3)).join(', ') +
    ' to ' + move.to.map((v) => v.toFixed(3)).join(', ') : 'line ' + line + ': no move');
});
$('undo').addEventListener('click', () => history('undo'));
$('redo').addEventListener('click', () => history('redo'));
$('saveas').addEventListener('click', () => save(false));
$('saveover').addEventListener('click', () => save(true));
$('dlxlsx').addEventListener('click', () => download('xlsx'));
$('dlcsv').addEventListener('click', () => download('csv'));
$('run').addEventListener('click', runMacro);
$('fitcam').addEventListener('click', fitCams);
$('machine').addEventListener('change', listDialects);
$('dlprogram').addEventListener('click', downloadProgram);

async function start() {
  try {
    book = await api('/api/sheets');
  } catch (e) {
    status(e.message, true);
    return;
  }
  $('file').textContent = book.file;
  document.title = book.file + ' — ncsheet';
  $('undo').disabled = !book.history.undo;
  $('redo').disabled = !book.history.redo;
  drawTabs();
  await showSheet(Math.min(book.active, book.sheets.length - 1));
  if (book.notes.length) status(book.notes.join('  '));
  loadMacros();
  document.body.dataset.ready = '1';
}

start();
