// The page's one drawing module: views (pan, zoom, fit), axes in metres
// with a scale bar, the legend drawn in each canvas, the layer toggles, the
// playground's picture and a SLAM result's picture. Geometry that core knows
// (the detection shapes' outlines, the landmark regions' boundaries) comes
// from core through the wasm facade (`Nvector.outlines`,
// core/src/outline.rs); nothing here recomputes it.

export const PALETTE = ['#e6194b', '#3cb44b', '#4363d8', '#f58231', '#911eb4', '#42d4f4', '#f032e6', '#9a6324'];
/** Colour of a detection in no proved group. */
export const UNMATCHED = '#999999';
const TRAJECTORY = 'rgb(74,144,217)';
const REGION = '#c80000';
const TRUTH = '#000000';
const KERNEL = 'rgba(0,120,0,0.35)';
/** The headings' colour (core/src/figure.rs HEADINGS). */
const HEADING = '#e67e22';
/** Most heading wedges drawn (core/src/figure.rs MAX_HEADING_MARKS). */
const MAX_HEADINGS = 48;

let core = null;
/** The wasm handle whose `outlines` gives the shapes' polygons (set once it is loaded). */
export function useCore(nv) { core = nv; }

/** A number from a JSON bound ("inf" / "-inf" allowed). */
export function num(b) {
  if (b === 'inf' || b === '+inf') return Infinity;
  if (b === '-inf') return -Infinity;
  return b;
}


/** The first two axes of a JSON box as {x0, x1, y0, y1}, or null. */
export function rect(box) {
  if (!Array.isArray(box) || box.length < 2 || !Array.isArray(box[0]) || !Array.isArray(box[1])) return null;
  const r = { x0: num(box[0][0]), x1: num(box[0][1]), y0: num(box[1][0]), y1: num(box[1][1]) };
  return [r.x0, r.x1, r.y0, r.y1].every(Number.isFinite) ? r : null;
}

/** Hull of rectangles. */
export function hull(rects) {
  const h = { x0: Infinity, x1: -Infinity, y0: Infinity, y1: -Infinity };
  for (const r of rects) {
    if (!r) continue;
    h.x0 = Math.min(h.x0, r.x0); h.x1 = Math.max(h.x1, r.x1);
    h.y0 = Math.min(h.y0, r.y0); h.y1 = Math.max(h.y1, r.y1);
  }
  return Number.isFinite(h.x0) ? h : { x0: -1, x1: 1, y0: -1, y1: 1 };
}

/** The area a result covers: its trajectory boxes and the truth path. */
export function areaOf(result, mission) {
  const rects = (result.trajectory || []).map(rect);
  const truth = mission && mission.truth && Array.isArray(mission.truth.positions) ? mission.truth.positions : [];
  for (const p of truth) if (Array.isArray(p)) rects.push({ x0: p[0], x1: p[0], y0: p[1], y1: p[1] });
  return hull(rects);
}

/** A view: world rectangle -> canvas, y up, same scale on both axes, with pan and zoom. */
export class View {
  constructor(canvas) { this.canvas = canvas; this.fit({ x0: -1, x1: 1, y0: -1, y1: 1 }); }
  fit(r) {
    const pad = 0.06 * Math.max(r.x1 - r.x0, r.y1 - r.y0, 1e-9);
    const w = this.canvas.width, h = this.canvas.height;
    this.scale = Math.min(w / (r.x1 - r.x0 + 2 * pad), h / (r.y1 - r.y0 + 2 * pad));
    this.cx = (r.x0 + r.x1) / 2; this.cy = (r.y0 + r.y1) / 2;
  }
  tx(x) { return this.canvas.width / 2 + (x - this.cx) * this.scale; }
  ty(y) { return this.canvas.height / 2 - (y - this.cy) * this.scale; }
  wx(px) { return this.cx + (px - this.canvas.width / 2) / this.scale; }
  wy(py) { return this.cy - (py - this.canvas.height / 2) / this.scale; }
  zoom(factor, px, py) {
    const wx = this.wx(px), wy = this.wy(py);
    this.scale *= factor;
    this.cx = wx - (px - this.canvas.width / 2) / this.scale;
    this.cy = wy + (py - this.canvas.height / 2) / this.scale;
  }
  pan(dx, dy) { this.cx -= dx / this.scale; this.cy += dy / this.scale; }
}

/** Draws one rectangle (screen coordinates from the view). */
export function drawRect(ctx, view, r, stroke, fill) {
  const x = view.tx(r.x0), y = view.ty(r.y1);
  const w = Math.max((r.x1 - r.x0) * view.scale, 1), h = Math.max((r.y1 - r.y0) * view.scale, 1);
  if (fill) { ctx.fillStyle = fill; ctx.fillRect(x, y, w, h); }
  if (stroke) { ctx.strokeStyle = stroke; ctx.strokeRect(x, y, w, h); }
}

// ---- axes, scale bar, legend (screen space, drawn over the picture) -----

/** A round step (1, 2 or 5 times a power of ten) giving about `target` ticks over `span`. */
export function niceStep(span, target) {
  const raw = span / target;
  const p = 10 ** Math.floor(Math.log10(raw));
  for (const m of [1, 2, 5, 10]) if (m * p >= raw * 0.999) return m * p;
  return 10 * p;
}

/**
 * A scale bar's text: a length (a round step of `niceStep`) with its unit,
 * in kilometres from 1000 m, in centimetres below 1 m and millimetres below
 * 1 cm ("50 km", "200 m", "5 cm"); a bare number without a unit. The digits
 * are the step's own, rounded to 12 significant ones (no float residue
 * such as 0.30000000000000004).
 */
export function scaleLabel(len, unit) {
  const clean = (v) => String(Number(v.toPrecision(12)));
  if (unit !== 'm') return unit ? `${clean(len)} ${unit}` : clean(len);
  if (len >= 1000) return `${clean(len / 1000)} km`;
  if (len >= 1 || len === 0) return `${clean(len)} m`;
  if (len >= 0.01) return `${clean(len * 100)} cm`;
  return `${clean(len * 1000)} mm`;
}

/** A tick label: as many decimals as the step needs, no more. */
function label(v, step) {
  const d = Math.max(0, -Math.floor(Math.log10(step) + 1e-9));
  const s = (Math.abs(v) < step / 2 ? 0 : v).toFixed(Math.min(d, 6));
  return s;
}

/**
 * Axes on the canvas: ticks and labels every round step on the bottom and
 * left edges, a faint grid, and a scale bar (bottom right) of one step with
 * its length and unit (`scaleLabel`: "50 km", not "50000 m"). Writes `axes`
 * ("ticks x, ticks y, step"), `unit` and `scaleBar` (the bar's text) into
 * the canvas's dataset.
 */
export function drawAxes(ctx, view, unit) {
  const c = ctx.canvas, w = c.width, h = c.height;
  const x0 = view.wx(0), x1 = view.wx(w), y0 = view.wy(h), y1 = view.wy(0);
  const step = niceStep(Math.max(x1 - x0, y1 - y0), 5);
  ctx.save();
  ctx.setTransform(1, 0, 0, 1, 0, 0);
  ctx.font = '10px system-ui, sans-serif';
  ctx.lineWidth = 1;
  let nx = 0, ny = 0;
  ctx.textAlign = 'center'; ctx.textBaseline = 'bottom';
  for (let v = Math.ceil(x0 / step) * step; v <= x1; v += step) {
    const px = Math.round(view.tx(v)) + 0.5;
    ctx.strokeStyle = 'rgba(0,0,0,0.07)'; ctx.beginPath(); ctx.moveTo(px, 0); ctx.lineTo(px, h); ctx.stroke();
    ctx.strokeStyle = '#444'; ctx.beginPath(); ctx.moveTo(px, h); ctx.lineTo(px, h - 5); ctx.stroke();
    if (px > 24 && px < w - 24) { halo(ctx, label(v, step), px, h - 6); nx++; }
  }
  ctx.textAlign = 'left'; ctx.textBaseline = 'middle';
  for (let v = Math.ceil(y0 / step) * step; v <= y1; v += step) {
    const py = Math.round(view.ty(v)) + 0.5;
    ctx.strokeStyle = 'rgba(0,0,0,0.07)'; ctx.beginPath(); ctx.moveTo(0, py); ctx.lineTo(w, py); ctx.stroke();
    ctx.strokeStyle = '#444'; ctx.beginPath(); ctx.moveTo(0, py); ctx.lineTo(5, py); ctx.stroke();
    if (py > 14 && py < h - 20) { halo(ctx, label(v, step), 7, py); ny++; }
  }
  // Scale bar: one step long, bottom right.
  const len = step * view.scale, bx = w - 12 - len, by = h - 22;
  ctx.strokeStyle = '#000'; ctx.lineWidth = 2;
  ctx.beginPath(); ctx.moveTo(bx, by - 4); ctx.lineTo(bx, by); ctx.lineTo(bx + len, by); ctx.lineTo(bx + len, by - 4); ctx.stroke();
  ctx.textAlign = 'center'; ctx.textBaseline = 'bottom';
  const bar = scaleLabel(step, unit);
  halo(ctx, bar, bx + len / 2, by - 3);
  ctx.restore();
  Object.assign(c.dataset, { axes: `${nx},${ny},${step}`, unit: unit || '', scaleBar: bar });
}

/** Text with a white halo, readable over any picture. */
function halo(ctx, text, x, y) {
  ctx.strokeStyle = 'rgba(255,255,255,0.85)'; ctx.lineWidth = 3; ctx.strokeText(text, x, y);
  ctx.fillStyle = '#222'; ctx.fillText(text, x, y);
  ctx.lineWidth = 1;
}

/**
 * A legend box in the canvas's top right corner. `entries`: {label, kind,
 * colour} with kind 'line' (a path), 'fill' (a translucent area), 'outline'
 * (a box's outline), 'dashed' (a dashed outline) or 'dot'. Writes the labels
 * into the canvas's dataset (`legend`, joined by '|').
 */
export function drawLegend(ctx, entries) {
  const c = ctx.canvas;
  ctx.save();
  ctx.setTransform(1, 0, 0, 1, 0, 0);
  ctx.font = '11px system-ui, sans-serif';
  const wText = Math.max(...entries.map((e) => ctx.measureText(e.label).width), 0);
  const lh = 15, bw = wText + 34, bh = entries.length * lh + 8, x = c.width - bw - 6, y = 6;
  ctx.fillStyle = 'rgba(255,255,255,0.88)'; ctx.strokeStyle = '#bbb'; ctx.lineWidth = 1;
  ctx.fillRect(x, y, bw, bh); ctx.strokeRect(x + 0.5, y + 0.5, bw - 1, bh - 1);
  ctx.textAlign = 'left'; ctx.textBaseline = 'middle';
  entries.forEach((e, i) => {
    const sx = x + 6, sy = y + 4 + i * lh + lh / 2;
    const colours = Array.isArray(e.colour) ? e.colour : [e.colour];
    const k = 18 / colours.length;
    colours.forEach((col, j) => {
      const ax = sx + j * k;
      ctx.setLineDash(e.kind === 'dashed' ? [3, 2] : []);
      if (e.kind === 'line') { ctx.strokeStyle = 'rgba(255,255,255,0.9)'; ctx.lineWidth = 4; ctx.beginPath(); ctx.moveTo(ax, sy); ctx.lineTo(ax + k, sy); ctx.stroke(); ctx.strokeStyle = col; ctx.lineWidth = 2; ctx.beginPath(); ctx.moveTo(ax, sy); ctx.lineTo(ax + k, sy); ctx.stroke(); }
      else if (e.kind === 'fill') { ctx.fillStyle = col; ctx.fillRect(ax, sy - 5, k, 10); }
      else if (e.kind === 'dot') { ctx.fillStyle = col; ctx.beginPath(); ctx.arc(ax + k / 2, sy, 3, 0, 7); ctx.fill(); }
      else { ctx.strokeStyle = col; ctx.lineWidth = 1.5; ctx.strokeRect(ax + 1, sy - 4.5, k - 2, 9); }
      ctx.setLineDash([]);
    });
    ctx.fillStyle = '#222'; ctx.fillText(e.label, sx + 24, sy);
  });
  ctx.restore();
  c.dataset.legend = entries.map((e) => e.label).join('|');
  c.dataset.legendBox = [x, y, bw, bh].map(Math.round).join();
}

// ---- layer toggles --------------------------------------------------------

/** The layers of a SLAM picture a user can hide, and their names. */
export const LAYER_NAMES = {
  trajectory: 'trajectory boxes', shapes: 'detection shapes (rings, sectors)', unmatched: 'shapes of unmatched detections',
  boxes: 'detection boxes', groups: 'proved groups', regions: 'landmark regions', headings: 'headings (odometry2d)', truth: 'truth',
};
export const LAYERS = Object.keys(LAYER_NAMES);

/**
 * Checkboxes, one per layer, in the element `box`; `redraw` is called when
 * one changes. Returns a function giving {layer: shown}; its `set(layer,
 * on)` ticks a box without redrawing.
 */
export function layerToggles(box, redraw) {
  for (const k of LAYERS) {
    const input = document.createElement('input');
    input.type = 'checkbox'; input.checked = true; input.dataset.layer = k;
    input.addEventListener('change', redraw);
    const l = document.createElement('label'); l.append(input, ` ${LAYER_NAMES[k]}`);
    box.append(l);
  }
  const get = () => Object.fromEntries([...box.querySelectorAll('input[data-layer]')].map((i) => [i.dataset.layer, i.checked]));
  get.set = (k, on) => { const i = box.querySelector(`input[data-layer='${k}']`); if (i) i.checked = on; };
  return get;
}

// ---- the playground -------------------------------------------------------

/**
 * The playground's picture: the atmost_nvalue kernels on the axes (green),
 * the input boxes dashed, the contracted boxes filled in their group's
 * colour (grey for a box alone in its group), numbered; axes (no unit: the
 * playground's boxes are abstract) and the legend.
 */
export function drawPlayground(canvas, view, boxes, out, selected) {
  const ctx = canvas.getContext('2d');
  ctx.setTransform(1, 0, 0, 1, 0, 0);
  ctx.clearRect(0, 0, canvas.width, canvas.height);
  drawAxes(ctx, view, '');
  const colour = new Map();
  (out ? out.groups : []).forEach((g, k) => g.forEach((i) => colour.set(i, g.length > 1 ? PALETTE[k % PALETTE.length] : '#555555')));
  (out && out.kernels || []).forEach((ks, axis) => {
    if (!Array.isArray(ks)) return;
    ctx.fillStyle = KERNEL;
    ks.forEach((k) => {
      if (axis === 0) ctx.fillRect(view.tx(k[0]), canvas.height - 8, Math.max((k[1] - k[0]) * view.scale, 2), 8);
      else ctx.fillRect(0, view.ty(k[1]), 8, Math.max((k[1] - k[0]) * view.scale, 2));
    });
  });
  ctx.font = '10px system-ui, sans-serif'; ctx.textAlign = 'left'; ctx.textBaseline = 'alphabetic';
  boxes.forEach((b, i) => {
    ctx.setLineDash([4, 3]); ctx.lineWidth = i === selected ? 2 : 1;
    drawRect(ctx, view, b, '#888');
    ctx.setLineDash([]);
    const r = out && rect(out.boxes[i]);
    if (r) drawRect(ctx, view, r, colour.get(i), colour.get(i) + '33');
    ctx.fillStyle = '#222';
    ctx.fillText(String(i + 1), view.tx(b.x0) + 3, view.ty(b.y1) + 12);
  });
  drawLegend(ctx, [
    { label: 'input box', kind: 'dashed', colour: '#888' },
    { label: 'contracted, in a group', kind: 'fill', colour: PALETTE.slice(0, 3).map((c) => c + '88') },
    { label: 'alone (singleton)', kind: 'fill', colour: '#55555588' },
    { label: 'kernel on an axis', kind: 'fill', colour: KERNEL },
  ]);
}

// ---- a SLAM result --------------------------------------------------------

/** An input interval (`[lo, hi]` or a number) as [lo, hi], or null. */
function interval(v) {
  if (typeof v === 'number') return [v, v];
  if (Array.isArray(v) && v.length === 2) return [num(v[0]), num(v[1])];
  return null;
}

/**
 * The heading interval at a step: the result's heading variable
 * (odometry2d), else the mission's heading channel (`yaw` for auv3d): value
 * ± error, or [lo, hi]; the channel's sample min(step, steps - 1), as the
 * solver reads it (core/src/slam/model.rs).
 */
export function headingAt(mission, result, step) {
  if (Array.isArray(result.headings) && result.headings[step] !== undefined) return interval(result.headings[step]);
  const ch = mission && mission.inputs && mission.inputs[mission.model === 'auv3d' ? 'yaw' : 'heading'];
  if (!ch) return null;
  const i = Math.min(step, mission.steps - 1);
  if (Array.isArray(ch.value)) {
    const e = Array.isArray(ch.error) ? ch.error[i] : ch.error;
    return [num(ch.value[i]) - num(e), num(ch.value[i]) + num(e)];
  }
  if (Array.isArray(ch.lo) && Array.isArray(ch.hi)) return [num(ch.lo[i]), num(ch.hi[i])];
  return null;
}

/** The group index of each detection (proved groups of `matching`). */
function groupOf(result) {
  const group = new Map();
  (result.matching || []).forEach((g, k) => g.forEach((j) => group.set(j, k)));
  return group;
}

const colourOf = (group, j) => {
  const g = group.get(j);
  return g === undefined ? UNMATCHED : PALETTE[g % PALETTE.length];
};

/** The intersection of two JSON boxes' axes (either may be absent). */
function cutAxes(a, b, dim) {
  const axes = [];
  for (let k = 0; k < dim; k++) {
    const u = (a && interval(a[k])) || [-Infinity, Infinity], v = (b && interval(b[k])) || [-Infinity, Infinity];
    axes.push([Math.max(u[0], v[0]), Math.min(u[1], v[1])]);
  }
  return axes;
}

/** Flat [x, y, ...] numbers -> an SVG path piece (every digit kept: no vertex moved inwards). */
function pathOf(parts, a, from, n) {
  parts.push(`M${a[from]} ${a[from + 1]}`);
  for (let i = 1; i < n; i++) parts.push(`L${a[from + 2 * i]} ${a[from + 2 * i + 1]}`);
  parts.push('Z');
}

// Shapes depend neither on the view nor on the time shown: their polygons
// come from core once per (result, mission), each with its step, and the
// time slider only filters them.
const shapeCache = new WeakMap();

/**
 * The detection shapes of a result: per shape its step, colour (proved
 * group), Path2D (world coordinates), outer polygon (flat points), hole and
 * bounding box, and whether it is a sector. A shape is what the measurement
 * allows around the result's box of p(step), cut by the detection's
 * `region` and the mission's `landmark_region` (what the mission knows, not
 * the contracted box d(j), so that a group's shapes are seen to cross where
 * its landmark is); in 3-D the depth is cut by the result's d(j). The
 * polygons enclose the shapes (core/src/outline.rs). A sensor offset widens
 * the centre by its length (the range is measured from the sensor).
 */
export function shapePaths(result, mission) {
  const hit = shapeCache.get(result);
  if (hit && hit.mission === mission) return hit;
  const group = groupOf(result);
  const dets = (mission && mission.detections) || [];
  const traj = result.trajectory || [];
  const off = mission && Array.isArray(mission.sensor_offset) ? Math.hypot(...mission.sensor_offset.map(Number)) * (1 + 1e-9) : 0;
  // The request to core: flat numbers (Nvector.outlines, web/src/lib.rs).
  const req = [], meta = [];
  const put = (iv) => { req.push(iv[0], iv[1]); };
  (Array.isArray(result.detections) ? result.detections : []).forEach((b, j) => {
    const d = dets[j];
    const range = d && interval(d.range);
    if (!range) return;
    const pbox = traj[d.step];
    const centre = Array.isArray(pbox) && pbox.length <= 3 ? pbox.map(interval) : null;
    if (!centre || !rect(pbox) || !centre.every((a) => a && a.every(Number.isFinite))) return;
    const dim = centre.length;
    if (off) for (const k of [0, 1]) centre[k] = [centre[k][0] - off, centre[k][1] + off];
    const cut = cutAxes(d.region, mission.landmark_region, dim);
    if (dim > 2) cut[2] = cutAxes(Array.isArray(b) ? [b[2]] : null, d.depth !== undefined ? [d.depth] : null, 1)[0];
    if (cut.some(([lo, hi]) => !(lo <= hi)) || !(range[0] <= range[1])) return;
    const bearing = d.bearing !== undefined && interval(d.bearing);
    const heading = bearing && headingAt(mission, result, d.step);
    const sector = !!(heading && heading.every(Number.isFinite) && bearing.every(Number.isFinite));
    req.push(dim);
    centre.forEach(put);
    put(range);
    req.push(sector ? 1 : 0);
    if (sector) { put(heading); put(bearing); }
    cut.forEach(put);
    meta.push({ step: d.step, colour: colourOf(group, j), sector });
  });
  const flat = req.length && core ? core.outlines(Float64Array.from(req)) : [];
  const list = [];
  let at = 0;
  meta.forEach((m) => {
    const no = flat[at], nh = flat[at + 1];
    at += 2;
    if (!no) return;
    const parts = [];
    pathOf(parts, flat, at, no);
    const outer = flat.subarray(at, at + 2 * no);
    at += 2 * no;
    let hole = null;
    if (nh) { pathOf(parts, flat, at, nh); hole = flat.subarray(at, at + 2 * nh); at += 2 * nh; }
    const bbox = boxOf(outer);
    list.push({ ...m, path: new Path2D(parts.join('')), outer, hole, bbox, unmatched: m.colour === UNMATCHED });
  });
  const out = { mission, list };
  shapeCache.set(result, out);
  return out;
}

/** Whether a convex counter-clockwise polygon holds the rectangle r. */
function holds(pts, r) {
  const n = pts.length;
  for (let i = 0; i < n; i += 2) {
    const ax = pts[i], ay = pts[i + 1], ex = pts[(i + 2) % n] - ax, ey = pts[(i + 3) % n] - ay;
    for (const [x, y] of [[r.x0, r.y0], [r.x1, r.y0], [r.x1, r.y1], [r.x0, r.y1]]) {
      if (ex * (y - ay) - ey * (x - ax) < 0) return false;
    }
  }
  return true;
}

const meets = (a, b) => a.x0 <= b.x1 && b.x0 <= a.x1 && a.y0 <= b.y1 && b.y0 <= a.y1;

/** The bounding box of a flat point list. */
function boxOf(h) {
  const r = { x0: Infinity, x1: -Infinity, y0: Infinity, y1: -Infinity };
  for (let i = 0; i < h.length; i += 2) {
    r.x0 = Math.min(r.x0, h[i]); r.x1 = Math.max(r.x1, h[i]);
    r.y0 = Math.min(r.y0, h[i + 1]); r.y1 = Math.max(r.y1, h[i + 1]);
  }
  return r;
}

const rectPath = (r) => `M${r.x0} ${r.y0}H${r.x1}V${r.y1}H${r.x0}Z`;

/**
 * The proved groups' boxes to outline: identical boxes once, and a box
 * holding a smaller one left out (it says nothing the smaller one does not
 * say about where a landmark is), so that a beacon seen by many groups shows
 * a handful of outlines, not a stack of them. Smallest first; each with its
 * group's colour.
 */
function groupOutlines(result) {
  const all = (Array.isArray(result.landmarks) ? result.landmarks : [])
    .map((b, k) => ({ r: rect(b), colour: PALETTE[k % PALETTE.length] }))
    .filter((g) => g.r)
    .sort((a, b) => (a.r.x1 - a.r.x0) * (a.r.y1 - a.r.y0) - (b.r.x1 - b.r.x0) * (b.r.y1 - b.r.y0));
  const kept = [];
  for (const g of all) {
    const inside = (k) => g.r.x0 <= k.r.x0 && k.r.x1 <= g.r.x1 && g.r.y0 <= k.r.y0 && k.r.y1 <= g.r.y1;
    if (!kept.some(inside)) kept.push(g);
  }
  return kept;
}

// Everything else a result draws, in world coordinates too, built once per
// (result, mission, last step).
const sceneCache = new WeakMap();
const regionCache = new WeakMap();

/**
 * The landmark regions: their distinct boxes (filled as a union on a mask)
 * and the boundary of the union of all of them (from core,
 * Nvector.boundaries) as one Path2D of segments.
 */
function regionPaths(result) {
  const hit = regionCache.get(result);
  if (hit) return hit;
  const regions = (Array.isArray(result.landmark_regions) ? result.landmark_regions : [])
    .map((p) => (Array.isArray(p) ? p.map(rect).filter(Boolean) : []));
  // One union over all groups' regions: groups of one landmark share
  // most of their boxes, and one outline per beacon area reads, where one
  // per group drew a grid.
  const rects = [], seen = new Set();
  for (const p of regions) {
    for (const r of p) {
      const k = rectPath(r);
      if (!seen.has(k)) { seen.add(k); rects.push(r); }
    }
  }
  const count = regions.reduce((s, p) => s + p.length, 0);
  const parts = [];
  let segments = 0;
  if (rects.length && core) {
    const req = [rects.length];
    for (const r of rects) req.push(r.x0, r.x1, r.y0, r.y1);
    const flat = core.boundaries(Float64Array.from(req));
    segments = Math.max(flat[0], 0); // -1: too many boxes to trace, the fill alone
    for (let k = 0, at = 1; k < segments; k++, at += 4) parts.push(`M${flat[at]} ${flat[at + 1]}L${flat[at + 2]} ${flat[at + 3]}`);
  }
  const out = { count, rects, segments, path: parts.length ? new Path2D(parts.join('')) : null };
  regionCache.set(result, out);
  return out;
}

/**
 * The trajectory (strided to at most 2000 boxes for its envelope, and the
 * boxes a pointer can hover), detection boxes, proved groups, and truth of a
 * result up to step `last`, as world-coordinate paths.
 */
function scenePaths(result, mission, last) {
  const hit = sceneCache.get(result);
  if (hit && hit.mission === mission && hit.last === last) return hit;
  const traj = Array.isArray(result.trajectory) ? result.trajectory : [];
  const stride = Math.max(1, Math.ceil(traj.length / 2000));
  const drawn = [];
  for (let i = 0; i <= last; i += stride) {
    const r = rect(traj[i]);
    if (r) drawn.push([i, r]);
  }
  if (last % stride && rect(traj[last])) drawn.push([last, rect(traj[last])]);
  const dets = (mission && mission.detections) || [];
  const group = groupOf(result);
  const boxParts = new Map();
  let boxes = 0;
  (Array.isArray(result.detections) ? result.detections : []).forEach((b, j) => {
    const r = rect(b);
    if (!r || (dets[j] && !(dets[j].step <= last))) return;
    const colour = colourOf(group, j);
    if (!boxParts.has(colour)) boxParts.set(colour, []);
    boxParts.get(colour).push(rectPath(r));
    boxes++;
  });
  const truth = mission && mission.truth;
  let truthPath = null;
  if (truth && Array.isArray(truth.positions)) {
    const step = Math.max(1, Math.ceil(truth.positions.length / 4000));
    const parts = [];
    let pen = false;
    truth.positions.slice(0, last + 1).forEach((p, i) => {
      if (!Array.isArray(p)) { pen = false; return; }
      if (i % step === 0 || i === last) { parts.push(`${pen ? 'L' : 'M'}${p[0]} ${p[1]}`); pen = true; }
    });
    if (parts.length) truthPath = new Path2D(parts.join(''));
  }
  // odometry2d: the heading interval of every k-th step (at most
  // MAX_HEADINGS, the last kept) with a bounded box, as core's figure.
  const heads = [];
  if (Array.isArray(result.headings)) {
    const cand = [];
    for (let i = 0; i <= last; i++) {
      const r = rect(traj[i]), h = interval(result.headings[i]);
      if (r && h && h[0] <= h[1]) cand.push([i, r, h]);
    }
    const k = Math.max(1, Math.ceil(cand.length / MAX_HEADINGS));
    cand.forEach((c, j) => { if (j % k === 0 || j === cand.length - 1) heads.push(c); });
    heads.stride = k;
  }
  const trueHeadings = truth && Array.isArray(truth.headings) && Array.isArray(truth.positions) ? truth.headings : [];
  const out = {
    mission, last, drawn, boxes, stride, heads,
    trueHeads: heads.filter(([i]) => Number.isFinite(trueHeadings[i]) && Array.isArray(truth.positions[i])).map(([i]) => [truth.positions[i], trueHeadings[i]]),
    boxPaths: new Map([...boxParts].map(([c, p]) => [c, new Path2D(p.join(''))])),
    groups: groupOutlines(result),
    truthPath,
    truthLandmarks: truth && Array.isArray(truth.landmarks) ? truth.landmarks.filter(Array.isArray) : [],
  };
  sceneCache.set(result, out);
  return out;
}

// The picture of a view is rendered into a layer (an offscreen canvas per
// canvas) and copied; while the user pans or zooms, the layer of the
// previous view is moved and scaled (one drawImage) until the caller asks
// for a full redraw.
const layerCache = new WeakMap();

// One mask canvas per layer and resolution, for unions drawn at one
// opacity: cleared, set to the layer's transform (scaled by `res`).
const masks = new WeakMap();
function mask(layer, ctx, res = 1) {
  let all = masks.get(layer);
  if (!all) { all = new Map(); masks.set(layer, all); }
  let m = all.get(res);
  if (!m) { m = document.createElement('canvas'); all.set(res, m); }
  const w = Math.ceil(layer.width * res), h = Math.ceil(layer.height * res);
  if (m.width !== w || m.height !== h) { m.width = w; m.height = h; }
  const mc = m.getContext('2d');
  mc.setTransform(1, 0, 0, 1, 0, 0);
  mc.clearRect(0, 0, w, h);
  mc.scale(res, res);
  mc.transform(...(({ a, b, c, d, e, f }) => [a, b, c, d, e, f])(ctx.getTransform()));
  return mc;
}

/** Draws a mask onto ctx (the layer's size) with an opacity, whatever ctx's transform. */
function layOn(ctx, mc, alpha) {
  const t = ctx.getTransform();
  ctx.setTransform(1, 0, 0, 1, 0, 0);
  ctx.globalAlpha = alpha;
  ctx.drawImage(mc.canvas, 0, 0, ctx.canvas.width, ctx.canvas.height);
  ctx.globalAlpha = 1;
  ctx.setTransform(t);
}

/** Rectangles filled opaque on a mask in whole pixels, rounded outwards (adjacent boxes leave no seam). */
function fillRects(m, view, rects) {
  m.setTransform(1, 0, 0, 1, 0, 0);
  for (const r of rects) {
    const x0 = Math.floor(view.tx(r.x0)), x1 = Math.ceil(view.tx(r.x1)), y0 = Math.floor(view.ty(r.y1)), y1 = Math.ceil(view.ty(r.y0));
    m.fillRect(x0, y0, Math.max(x1 - x0, 1), Math.max(y1 - y0, 1));
  }
}

/** Renders the whole picture into `layer` for the view; returns what was drawn. */
function render(layer, canvas, view, sc, shapes, regions, show, last) {
  layer.width = canvas.width;
  layer.height = canvas.height;
  const ctx = layer.getContext('2d', { willReadFrequently: true });
  ctx.setTransform(view.scale, 0, 0, -view.scale, canvas.width / 2 - view.cx * view.scale, canvas.height / 2 + view.cy * view.scale);
  const px = 1 / view.scale;
  ctx.lineWidth = px;
  const seen = { x0: view.wx(0), x1: view.wx(canvas.width), y0: view.wy(canvas.height), y1: view.wy(0) };
  // The trajectory's envelope: the union of its (strided) boxes at one
  // opacity, however many overlap, under everything else.
  if (show('trajectory') && sc.drawn.length) {
    const m = mask(layer, ctx);
    m.fillStyle = TRAJECTORY;
    fillRects(m, view, sc.drawn.map(([, r]) => r).filter((r) => meets(r, seen)));
    layOn(ctx, m, 0.3);
  }
  let drawnShapes = 0, drawnSectors = 0;
  if (shapes) {
    // Per colour, the union of its shapes at one opacity: each shape filled
    // opaque on a mask, laid on faintly. Shapes outside the view are
    // skipped, and once one shape covers the whole view, the rest of its
    // colour is. Beyond 400 shapes the masks have half the resolution.
    const byColour = new Map();
    for (const sh of shapes.list) {
      if (!(sh.step <= last) || (sh.unmatched && !show('unmatched'))) continue;
      drawnShapes++; if (sh.sector) drawnSectors++;
      if (!meets(sh.bbox, seen)) continue;
      if (!byColour.has(sh.colour)) byColour.set(sh.colour, []);
      byColour.get(sh.colour).push(sh);
    }
    const res = drawnShapes > 400 ? 0.5 : 1;
    for (const [colour, list] of byColour) {
      const m = mask(layer, ctx, res);
      m.fillStyle = colour;
      for (const sh of list) {
        if (holds(sh.outer, seen) && !(sh.hole && meets(boxOf(sh.hole), seen))) {
          m.fillRect(seen.x0, seen.y0, seen.x1 - seen.x0, seen.y1 - seen.y0);
          break;
        }
        m.fill(sh.path, 'nonzero');
      }
      layOn(ctx, m, colour === UNMATCHED ? 0.12 : 0.22);
    }
  }
  if (show('regions') && regions.rects.length) {
    // The union of the regions' boxes at one opacity, and its boundary.
    const m = mask(layer, ctx);
    m.fillStyle = REGION;
    fillRects(m, view, regions.rects.filter((r) => meets(r, seen)));
    layOn(ctx, m, 0.22);
    if (regions.path) { ctx.strokeStyle = REGION; ctx.lineWidth = 1.2 * px; ctx.stroke(regions.path); }
  }
  if (show('boxes')) {
    ctx.lineWidth = px;
    ctx.globalAlpha = 0.6;
    for (const [colour, path] of sc.boxPaths) { ctx.strokeStyle = colour; ctx.stroke(path); }
    ctx.globalAlpha = 1;
  }
  if (show('groups')) {
    ctx.lineWidth = 2 * px;
    for (const g of sc.groups) { ctx.strokeStyle = g.colour; ctx.strokeRect(g.r.x0, g.r.y0, g.r.x1 - g.r.x0, g.r.y1 - g.r.y0); }
  }
  let headings = 0;
  if (show('headings') && sc.heads.length) {
    // A wedge of 14 pixels from the box's centre over the heading
    // interval; a circle when it is 2 pi wide or more.
    const R = 14 * px;
    ctx.lineWidth = px; ctx.strokeStyle = HEADING; ctx.fillStyle = 'rgba(230,126,34,0.25)';
    for (const [, r, h] of sc.heads) {
      const x = r.x0 / 2 + r.x1 / 2, y = r.y0 / 2 + r.y1 / 2;
      if (!meets({ x0: x - R, x1: x + R, y0: y - R, y1: y + R }, seen)) continue;
      ctx.beginPath();
      if (!(h[1] - h[0] < 2 * Math.PI)) { ctx.arc(x, y, R, 0, 2 * Math.PI); ctx.stroke(); } else { ctx.moveTo(x, y); ctx.arc(x, y, R, h[0], h[1]); ctx.closePath(); ctx.fill(); ctx.stroke(); }
      headings++;
    }
  }
  if (show('truth') && sc.trueHeads.length) {
    // The true heading: a tick from the true position.
    const R = 14 * px;
    ctx.strokeStyle = TRUTH; ctx.lineWidth = px; ctx.beginPath();
    for (const [p, t] of sc.trueHeads) { ctx.moveTo(p[0], p[1]); ctx.lineTo(p[0] + R * Math.cos(t), p[1] + R * Math.sin(t)); }
    ctx.stroke();
  }
  if (show('truth') && sc.truthPath) {
    // A white halo under a black line: visible over any colour.
    ctx.lineJoin = 'round';
    ctx.strokeStyle = 'rgba(255,255,255,0.9)'; ctx.lineWidth = 4 * px; ctx.stroke(sc.truthPath);
    ctx.strokeStyle = TRUTH; ctx.lineWidth = 1.6 * px; ctx.stroke(sc.truthPath);
  }
  ctx.setTransform(1, 0, 0, 1, 0, 0);
  if (show('truth')) {
    for (const l of sc.truthLandmarks) {
      ctx.fillStyle = '#fff'; ctx.beginPath(); ctx.arc(view.tx(l[0]), view.ty(l[1]), 4.5, 0, 7); ctx.fill();
      ctx.fillStyle = TRUTH; ctx.beginPath(); ctx.arc(view.tx(l[0]), view.ty(l[1]), 3, 0, 7); ctx.fill();
    }
  }
  return { shapes: drawnShapes, sectors: drawnSectors, headings };
}

/** The legend entries of a SLAM picture: what is drawn, with counts. */
function resultLegend(result, mission, sc, drawn, regions, show) {
  const e = [];
  const truth = mission && mission.truth;
  if (show('truth') && sc.truthPath) e.push({ label: 'truth path', kind: 'line', colour: TRUTH });
  if (show('truth') && sc.truthLandmarks.length) e.push({ label: 'true landmarks', kind: 'dot', colour: TRUTH });
  if (show('trajectory')) e.push({ label: sc.stride > 1 ? `trajectory boxes (1 in ${sc.stride})` : 'trajectory boxes', kind: 'fill', colour: 'rgba(74,144,217,0.45)' });
  const k = Array.isArray(result.matching) ? result.matching.length : 0;
  if (show('groups') && k) e.push({ label: `proved groups (${k}${sc.groups.length < k ? `, ${sc.groups.length} drawn` : ''})`, kind: 'outline', colour: PALETTE.slice(0, 3) });
  if (show('regions') && regions.rects.length) e.push({ label: 'landmark regions', kind: 'fill', colour: 'rgba(200,0,0,0.4)' });
  if (show('headings') && sc.heads.length) e.push({ label: `heading (interval)${sc.heads.stride > 1 ? `, 1 step in ${sc.heads.stride}` : ''}`, kind: 'fill', colour: 'rgba(230,126,34,0.5)' });
  if (show('truth') && sc.trueHeads.length) e.push({ label: 'true heading', kind: 'line', colour: TRUTH });
  if (drawn.shapes) e.push({ label: 'detection shapes', kind: 'fill', colour: [...PALETTE.slice(0, 2).map((c) => c + '55'), '#99999955'] });
  if (show('boxes') && sc.boxes) e.push({ label: 'detection boxes', kind: 'outline', colour: [PALETTE[0], UNMATCHED] });
  if (!truth && !e.length) e.push({ label: 'nothing to draw', kind: 'outline', colour: '#ccc' });
  return e;
}

/**
 * Draws a SLAM result: the trajectory's envelope (boxes up to `untilStep`,
 * translucent, under the rest), detection shapes (faint, coloured by proved
 * group; unmatched ones grey), landmark regions (filled faintly, outlined),
 * detection boxes, the proved groups' boxes as outlines, odometry2d's
 * headings as wedges (every k-th step, at most 48; a circle when 2 pi wide
 * or more), the truth path on top with a halo and the true headings; then axes in metres and the legend. `layers` hides
 * layers ({shapes: false, ...}); `moving` (during a pan or zoom) allows the
 * picture of the previous view, moved and scaled, and then the canvas's
 * dataset says `stale` = "true". Writes what was drawn into the canvas's
 * dataset (shapes, sectors, boxes, regions, groups, legend, axes, ms, stale)
 * and returns the hoverable trajectory rectangles.
 */
export function drawResult(canvas, view, result, mission, untilStep, layers = {}, moving = false) {
  const t0 = performance.now();
  const show = (k) => layers[k] !== false;
  const traj = Array.isArray(result.trajectory) ? result.trajectory : [];
  const last = Math.min(untilStep ?? traj.length - 1, traj.length - 1);
  const sc = scenePaths(result, mission, last);
  const regions = regionPaths(result);
  const shapes = show('shapes') && mission ? shapePaths(result, mission) : null;
  const key = LAYERS.map(show).join();
  const ctx = canvas.getContext('2d');
  ctx.setTransform(1, 0, 0, 1, 0, 0);
  ctx.clearRect(0, 0, canvas.width, canvas.height);
  let c = layerCache.get(canvas);
  if (!c) { c = { layer: document.createElement('canvas') }; layerCache.set(canvas, c); }
  const same = c.sc === sc && c.shapeList === (shapes && shapes.list) && c.key === key && c.w === canvas.width && c.h === canvas.height;
  const sameView = same && c.scale === view.scale && c.cx === view.cx && c.cy === view.cy;
  let stale = false;
  if (same && !sameView && moving) {
    const k = view.scale / c.scale, w = canvas.width, h = canvas.height;
    ctx.drawImage(c.layer, w / 2 - (w / 2) * k + (c.cx - view.cx) * view.scale, h / 2 - (h / 2) * k - (c.cy - view.cy) * view.scale, w * k, h * k);
    stale = true;
  } else {
    if (!sameView) {
      const drawn = render(c.layer, canvas, view, sc, shapes, regions, show, last);
      Object.assign(c, { sc, shapeList: shapes && shapes.list, key, scale: view.scale, cx: view.cx, cy: view.cy, w: canvas.width, h: canvas.height, drawn });
    }
    ctx.drawImage(c.layer, 0, 0);
  }
  drawAxes(ctx, view, 'm');
  drawLegend(ctx, resultLegend(result, mission, sc, c.drawn, regions, show));
  Object.assign(canvas.dataset, {
    shapes: c.drawn.shapes, sectors: c.drawn.sectors, headings: c.drawn.headings,
    boxes: show('boxes') ? sc.boxes : 0, regions: show('regions') ? regions.count : 0,
    regionSegments: show('regions') ? regions.segments : 0, groups: show('groups') ? sc.groups.length : 0,
    stale, ms: (performance.now() - t0).toFixed(2),
  });
  return sc.drawn;
}

/** A message in an empty canvas (centred lines). */
export function drawMessage(canvas, lines) {
  const ctx = canvas.getContext('2d');
  ctx.setTransform(1, 0, 0, 1, 0, 0);
  ctx.clearRect(0, 0, canvas.width, canvas.height);
  ctx.fillStyle = '#777'; ctx.font = '14px system-ui, sans-serif'; ctx.textAlign = 'center'; ctx.textBaseline = 'alphabetic';
  lines.forEach((l, i) => ctx.fillText(l, canvas.width / 2, canvas.height / 2 - 10 + 22 * i));
  canvas.dataset.legend = '';
}
