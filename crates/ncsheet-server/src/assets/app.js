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
  // Past --timeout the workbook is still computing: look again until it answers.
  if (response.status === 503 && !busyTimer) busyTimer = setTimeout(refreshAfterBusy, 1000);
  if (!response.ok) throw new Error((data && data.error) || text || response.statusText);
  return data;
}

let busyTimer = null;
function refreshAfterBusy() {
  busyTimer = null;
  fetched = null;
  render();
  api('/api/sheets').then((b) => showHistory(b.history)).catch(() => {});
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
  [...$('tabs').children].forEach(b => b.classList.toggle('on', Number(b.dataset.sheet) === index));
  render();
}

// Tabs in the workbook's tab order (a macro may have moved or added sheets anywhere); each
// button keeps its sheet's number, which the server's requests name.
function drawTabs() {
  const order = book.order || book.sheets.map((_, i) => i);
  $('tabs').innerHTML = order.map(i => '<button data-sheet="' + i + '">' + esc(book.sheets[i].name) + '</button>').join('');
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

let ball = null;                 // {points: [x,y,z,...], lo, hi}
let orbit = { yaw: -0.6, pitch: 0.9, zoom: 1 };
let view3d = null;               // the renderer of the 3D view: WebGL, or the 2D canvas without it

async function drawBallPath(at) {
  try {
    const g = await api('/api/ballpath?' + query(at));
    const svgImg = (svg, alt) => '<img alt="' + alt + '" src="data:image/svg+xml;charset=utf-8,' + encodeURIComponent(svg) + '">';
    if (view3d) view3d.dispose();
    $('ballpath').innerHTML = '<div>' + esc(g.cell) + ': ' + g.count + ' points, from ' + g.first.map((v) => v.toFixed(3)).join(', ') +
      ' to ' + g.last.map((v) => v.toFixed(3)).join(', ') + '</div>' +
      '<h2>Plan</h2>' + svgImg(g.plan, 'plan') + '<h2>Section</h2>' + svgImg(g.section, 'section') +
      '<h2>3D</h2><div id="view3dbox"><canvas id="view3d" width="800" height="640" title="Drag to orbit, wheel to zoom"></canvas>' +
      '<canvas id="view3dlabels" width="800" height="640"></canvas></div><div id="view3dinfo" class="note"></div>';
    ball = { points: g.points, lo: g.stock[0], hi: g.stock[1] };
    view3d = glView($('view3d'), $('view3dlabels')) || canvasView($('view3d'), $('view3dlabels'));
    $('view3d').dataset.renderer = view3d.kind;
    $('view3dinfo').textContent = 'ball path, ' + (ball.points.length / 3) + ' points drawn; box ' +
      [0, 1, 2].map((i) => (ball.hi[i] - ball.lo[i]).toFixed(1)).join(' × ') + ' mm; drag to orbit, wheel to zoom; drawn by ' + view3d.name;
    view3d.draw();
    orbitWithMouse($('view3d'));
  } catch (e) {
    $('ballpath').textContent = e.message;
  }
}

let dragFrom = null;
window.addEventListener('mouseup', () => { dragFrom = null; });

function orbitWithMouse(canvas) {
  canvas.addEventListener('mousedown', (e) => { dragFrom = [e.clientX, e.clientY]; e.preventDefault(); });
  canvas.addEventListener('mousemove', (e) => {
    if (!dragFrom) return;
    orbit.yaw += (e.clientX - dragFrom[0]) * 0.01;
    orbit.pitch = Math.max(-Math.PI / 2, Math.min(Math.PI / 2, orbit.pitch + (e.clientY - dragFrom[1]) * 0.01));
    dragFrom = [e.clientX, e.clientY];
    requestAnimationFrame(() => view3d && view3d.draw());
  });
  canvas.addEventListener('wheel', (e) => {
    e.preventDefault();
    orbit.zoom = Math.max(0.1, Math.min(20, orbit.zoom * Math.exp(-e.deltaY * 0.001)));
    requestAnimationFrame(() => view3d && view3d.draw());
  }, { passive: false });
}

// The colour of depth t in 0..1, as the plan's: dark blue deep to light yellow high.
function depthRgb(t) {
  const stops = [[13, 26, 115], [0, 140, 153], [242, 217, 64]];
  const u = Math.max(0, Math.min(1, t)) * 2, i = u < 1 ? 0 : 1, f = u - i;
  return stops[i].map((a, j) => a + (stops[i + 1][j] - a) * f);
}

function depthColour(t) {
  return 'rgb(' + depthRgb(t).map(Math.round).join(',') + ')';
}

// A round step (1, 2 or 5 times a power of ten) that cuts `span` into about 5 to 10 parts.
function gridStep(span) {
  const rough = (span || 1) / 8, power = Math.pow(10, Math.floor(Math.log10(rough)));
  return [1, 2, 5, 10].map((m) => m * power).find((s) => s >= rough);
}

function ticks(a, b, step) {
  const out = [];
  for (let i = Math.ceil(a / step - 1e-9); i * step <= b + 1e-9 * step; i++) out.push(i * step);
  return out;
}

// The scene in millimetres about the stock's middle: the stock's edges, the floor grid, the
// axes with their graduations (X red, Y green, Z blue, from the stock's lowest corner), as
// line segments [x0,y0,z0,x1,y1,z1, ...] with their colours and the labels to write.
function scene() {
  const [lo, hi] = [ball.lo, ball.hi];
  const size = Math.max(hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]) || 1;
  const segments = [], labels = [];
  const line = (p, q, rgb) => segments.push({ p, q, rgb });
  const boxRgb = [154, 138, 90], gridRgb = [222, 222, 222];
  const step = gridStep(Math.max(hi[0] - lo[0], hi[1] - lo[1]));
  for (const x of ticks(lo[0], hi[0], step)) line([x, lo[1], lo[2]], [x, hi[1], lo[2]], gridRgb);
  for (const y of ticks(lo[1], hi[1], step)) line([lo[0], y, lo[2]], [hi[0], y, lo[2]], gridRgb);
  const corner = (i) => [i & 1 ? hi[0] : lo[0], i & 2 ? hi[1] : lo[1], i & 4 ? hi[2] : lo[2]];
  for (const [a, b] of [[0, 1], [1, 3], [3, 2], [2, 0], [4, 5], [5, 7], [7, 6], [6, 4], [0, 4], [1, 5], [2, 6], [3, 7]]) line(corner(a), corner(b), boxRgb);
  const tick = size * 0.025, axes = [
    { name: 'X', axis: 0, out: [0, -1, 0], rgb: [208, 32, 32] },
    { name: 'Y', axis: 1, out: [-1, 0, 0], rgb: [26, 154, 58] },
    { name: 'Z', axis: 2, out: [-1, 0, 0], rgb: [31, 95, 208] },
  ];
  for (const a of axes) {
    const span = hi[a.axis] - lo[a.axis];
    const along = (v) => { const p = lo.slice(); p[a.axis] = v; return p; };
    const end = lo[a.axis] + Math.max(span, size * 0.2);
    line(along(lo[a.axis]), along(end), a.rgb);
    const s = gridStep(Math.max(span, size * 0.2));
    const digits = Math.max(0, -Math.floor(Math.log10(s)));
    for (const v of ticks(lo[a.axis], end, s)) {
      const p = along(v), q = p.map((c, i) => c + a.out[i] * tick);
      line(p, q, a.rgb);
      labels.push({ at: p.map((c, i) => c + a.out[i] * tick * 2.6), text: v.toFixed(digits), rgb: a.rgb });
    }
    labels.push({ at: along(end + size * 0.08), text: a.name, rgb: a.rgb, bold: true });
  }
  return { segments, labels, size, mid: [0, 1, 2].map((i) => (lo[i] + hi[i]) / 2) };
}

// The camera: orbiting the stock's middle at yaw (about Z) and pitch, Z up; perspective.
// Returns the column-major matrix from millimetres about the middle to clip space.
function cameraMatrix(size, aspect) {
  const [sy, cy, sp, cp] = [Math.sin(orbit.yaw), Math.cos(orbit.yaw), Math.sin(orbit.pitch), Math.cos(orbit.pitch)];
  const dir = [cp * sy, -cp * cy, sp];          // from the middle to the eye
  const up = [-sp * sy, sp * cy, cp];           // square to dir, up on the screen
  const right = [dir[1] * up[2] - dir[2] * up[1], dir[2] * up[0] - dir[0] * up[2], dir[0] * up[1] - dir[1] * up[0]].map((v) => -v);
  const fov = 35 * Math.PI / 180, distance = size * 2.4 / orbit.zoom;
  const eye = dir.map((v) => v * distance);
  const dot = (a, b) => a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
  const view = [
    right[0], up[0], dir[0], 0,
    right[1], up[1], dir[1], 0,
    right[2], up[2], dir[2], 0,
    -dot(right, eye), -dot(up, eye), -dot(dir, eye), 1,
  ];
  const near = distance / 100, far = distance + size * 4, f = 1 / Math.tan(fov / 2);
  const projection = [f / aspect, 0, 0, 0, 0, f, 0, 0, 0, 0, (far + near) / (near - far), -1, 0, 0, 2 * far * near / (near - far), 0];
  const out = new Float32Array(16);
  for (let c = 0; c < 4; c++) {
    for (let r = 0; r < 4; r++) {
      let sum = 0;
      for (let k = 0; k < 4; k++) sum += projection[k * 4 + r] * view[c * 4 + k];
      out[c * 4 + r] = sum;
    }
  }
  return out;
}

// Where a point (mm about the middle) lands on a canvas W × H, or null behind the eye.
function toScreen(m, p, W, H) {
  const x = m[0] * p[0] + m[4] * p[1] + m[8] * p[2] + m[12];
  const y = m[1] * p[0] + m[5] * p[1] + m[9] * p[2] + m[13];
  const w = m[3] * p[0] + m[7] * p[1] + m[11] * p[2] + m[15];
  if (w <= 0) return null;
  return [(x / w + 1) * W / 2, (1 - y / w) * H / 2];
}

// The graduations' numbers and the axes' names, written over the 3D view; a number that
// would overlap one written already (an axis seen end-on) is left out.
function drawLabels(canvas, labels, m, mid) {
  const ctx = canvas.getContext('2d');
  ctx.clearRect(0, 0, canvas.width, canvas.height);
  const written = [];
  for (const l of labels) {
    const s = toScreen(m, l.at.map((c, i) => c - mid[i]), canvas.width, canvas.height);
    if (!s) continue;
    if (!l.bold && written.some((w) => Math.abs(w[0] - s[0]) < 40 && Math.abs(w[1] - s[1]) < 24)) continue;
    written.push(s);
    ctx.fillStyle = 'rgb(' + l.rgb.join(',') + ')';
    ctx.font = (l.bold ? 'bold 28px' : '22px') + ' sans-serif';
    ctx.textAlign = 'center';
    ctx.textBaseline = 'middle';
    ctx.fillText(l.text, s[0], s[1]);
  }
}

const VERTEX_SHADER = 'attribute vec3 position; attribute vec3 colour; uniform mat4 camera; varying vec3 shade;' +
  'void main() { shade = colour; gl_Position = camera * vec4(position, 1.0); }';
const FRAGMENT_SHADER = 'precision mediump float; varying vec3 shade; void main() { gl_FragColor = vec4(shade, 1.0); }';

function compiled(gl, type, text) {
  const shader = gl.createShader(type);
  gl.shaderSource(shader, text);
  gl.compileShader(shader);
  if (!gl.getShaderParameter(shader, gl.COMPILE_STATUS)) throw new Error(gl.getShaderInfoLog(shader));
  return shader;
}

// The path as a WebGL line strip coloured by Z, over the scene's lines; null where the
// browser gives no WebGL context (the 2D canvas draws it then).
function glView(canvas, overlay) {
  let gl = null;
  try {
    gl = canvas.getContext('webgl', { antialias: true, preserveDrawingBuffer: true });
  } catch (e) {
    gl = null;
  }
  if (!gl) return null;
  try {
    return glRenderer(gl, canvas, overlay);
  } catch (e) {
    // A context that cannot compile or link the two small shaders draws nothing: the 2D canvas does.
    return null;
  }
}

function glRenderer(gl, canvas, overlay) {
  const program = gl.createProgram();
  gl.attachShader(program, compiled(gl, gl.VERTEX_SHADER, VERTEX_SHADER));
  gl.attachShader(program, compiled(gl, gl.FRAGMENT_SHADER, FRAGMENT_SHADER));
  gl.linkProgram(program);
  if (!gl.getProgramParameter(program, gl.LINK_STATUS)) throw new Error(gl.getProgramInfoLog(program));
  const s = scene();
  const pts = ball.points, n = pts.length / 3, zlo = ball.lo[2], zspan = ball.hi[2] - ball.lo[2] || 1;
  // Positions about the middle, so that single precision keeps the micrometres.
  const path = new Float32Array(pts.length), pathColour = new Float32Array(pts.length);
  for (let i = 0; i < n; i++) {
    for (let j = 0; j < 3; j++) path[3 * i + j] = pts[3 * i + j] - s.mid[j];
    const rgb = depthRgb((pts[3 * i + 2] - zlo) / zspan);
    for (let j = 0; j < 3; j++) pathColour[3 * i + j] = rgb[j] / 255;
  }
  const lines = new Float32Array(s.segments.length * 6), lineColour = new Float32Array(s.segments.length * 6);
  s.segments.forEach((seg, i) => {
    for (let j = 0; j < 3; j++) {
      lines[6 * i + j] = seg.p[j] - s.mid[j];
      lines[6 * i + 3 + j] = seg.q[j] - s.mid[j];
      lineColour[6 * i + j] = lineColour[6 * i + 3 + j] = seg.rgb[j] / 255;
    }
  });
  const buffer = (data) => {
    const b = gl.createBuffer();
    gl.bindBuffer(gl.ARRAY_BUFFER, b);
    gl.bufferData(gl.ARRAY_BUFFER, data, gl.STATIC_DRAW);
    return b;
  };
  const buffers = { path: buffer(path), pathColour: buffer(pathColour), lines: buffer(lines), lineColour: buffer(lineColour) };
  const position = gl.getAttribLocation(program, 'position'), colour = gl.getAttribLocation(program, 'colour');
  const camera = gl.getUniformLocation(program, 'camera');
  const bind = (where, b) => {
    gl.bindBuffer(gl.ARRAY_BUFFER, b);
    gl.enableVertexAttribArray(where);
    gl.vertexAttribPointer(where, 3, gl.FLOAT, false, 0, 0);
  };
  const info = gl.getExtension('WEBGL_debug_renderer_info');
  const renderer = info ? gl.getParameter(info.UNMASKED_RENDERER_WEBGL) : gl.getParameter(gl.RENDERER);
  return {
    kind: 'webgl',
    name: 'WebGL (' + renderer + ')',
    draw() {
      const m = cameraMatrix(s.size, canvas.width / canvas.height);
      gl.viewport(0, 0, canvas.width, canvas.height);
      gl.clearColor(1, 1, 1, 1);
      gl.clear(gl.COLOR_BUFFER_BIT | gl.DEPTH_BUFFER_BIT);
      gl.enable(gl.DEPTH_TEST);
      gl.useProgram(program);
      gl.uniformMatrix4fv(camera, false, m);
      bind(position, buffers.lines);
      bind(colour, buffers.lineColour);
      gl.drawArrays(gl.LINES, 0, lines.length / 3);
      bind(position, buffers.path);
      bind(colour, buffers.pathColour);
      gl.drawArrays(gl.LINE_STRIP, 0, n);
      drawLabels(overlay, s.labels, m, s.mid);
    },
    dispose() {
      const lose = gl.getExtension('WEBGL_lose_context');
      if (lose) lose.loseContext();
    },
  };
}

// The same scene on a 2D canvas, for a browser without WebGL: segments shorter than a pixel
// on screen are merged, so a million points draw at once.
function canvasView(canvas, overlay) {
  const ctx = canvas.getContext('2d');
  const s = scene();
  const draw = () => {
    const W = canvas.width, H = canvas.height;
    const m = cameraMatrix(s.size, W / H);
    const project = (x, y, z) => toScreen(m, [x - s.mid[0], y - s.mid[1], z - s.mid[2]], W, H) || [W / 2, H / 2];
    ctx.fillStyle = '#fff';
    ctx.fillRect(0, 0, W, H);
    ctx.lineWidth = 1;
    for (const seg of s.segments) {
      const p = project(...seg.p), q = project(...seg.q);
      ctx.strokeStyle = 'rgb(' + seg.rgb.join(',') + ')';
      ctx.beginPath(); ctx.moveTo(p[0], p[1]); ctx.lineTo(q[0], q[1]); ctx.stroke();
    }
    const pts = ball.points, zlo = ball.lo[2], zspan = ball.hi[2] - ball.lo[2] || 1;
    ctx.lineWidth = 1.2;
    let last = project(pts[0], pts[1], pts[2]), band = -1;
    ctx.beginPath();
    for (let i = 3; i < pts.length; i += 3) {
      const p = project(pts[i], pts[i + 1], pts[i + 2]);
      const b = Math.min(7, Math.floor((pts[i + 2] - zlo) / zspan * 8));
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
    drawLabels(overlay, s.labels, m, s.mid);
  };
  return { kind: '2d', name: 'a 2D canvas (this browser gives no WebGL)', draw, dispose() {} };
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
    $('backplot').innerHTML = (data.svg ? '<img alt="backplot" src="data:image/svg+xml;charset=utf-8,' + encodeURIComponent(data.svg) + '">' : '') +
      (data.part ? '<div id="partsaid" class="note">' + esc(data.part.said) + '</div>' : '');
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
