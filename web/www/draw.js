// Canvas drawing of boxes and detection shapes, kept apart from the API calls.

import { addPolygon, shapePolygons } from './shapes.js';

export const PALETTE = ['#e6194b', '#3cb44b', '#4363d8', '#f58231', '#911eb4', '#42d4f4', '#f032e6', '#9a6324'];

/** A number from a JSON bound ("inf" / "-inf" allowed). */
export function num(b) {
  if (b === 'inf') return Infinity;
  if (b === '-inf') return -Infinity;
  return b;
}

/** The first two axes of a JSON box as {x0, x1, y0, y1}, or null. */
export function rect(box) {
  if (!Array.isArray(box) || box.length < 2) return null;
  const r = { x0: num(box[0][0]), x1: num(box[0][1]), y0: num(box[1][0]), y1: num(box[1][1]) };
  return [r.x0, r.x1, r.y0, r.y1].every(Number.isFinite) ? r : null;
}

/** A view: world rectangle -> canvas, y up, with pan and zoom. */
export class View {
  constructor(canvas) { this.canvas = canvas; this.fit({ x0: -1, x1: 1, y0: -1, y1: 1 }); }
  fit(r) {
    const pad = 0.05 * Math.max(r.x1 - r.x0, r.y1 - r.y0, 1e-9);
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

/** Draws one rectangle. */
export function drawRect(ctx, view, r, stroke, fill) {
  const x = view.tx(r.x0), y = view.ty(r.y1);
  const w = Math.max((r.x1 - r.x0) * view.scale, 1), h = Math.max((r.y1 - r.y0) * view.scale, 1);
  if (fill) { ctx.fillStyle = fill; ctx.fillRect(x, y, w, h); }
  if (stroke) { ctx.strokeStyle = stroke; ctx.strokeRect(x, y, w, h); }
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


/** The layers a user can hide (legend checkboxes). */
export const LAYERS = ['shapes', 'boxes', 'regions'];

/** Colour of a detection in no proved group. */
export const UNMATCHED = '#999999';

/** An input interval (`[lo, hi]` or a number) as [lo, hi], or null. */
function interval(v) {
  if (typeof v === 'number') return [v, v];
  if (Array.isArray(v) && v.length === 2) return [num(v[0]), num(v[1])];
  return null;
}

/**
 * The heading interval at a step from the mission's heading channel (`yaw`
 * for auv3d): value ± error, or [lo, hi]; the channel's sample
 * min(step, steps - 1), as the solver reads it (core/src/slam/model.rs).
 */
export function headingAt(mission, step) {
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

/** The intersection of two rectangles (either may be null: no cut). */
function cutOf(a, b) {
  if (!a || !b) return a || b;
  return { x0: Math.max(a.x0, b.x0), x1: Math.min(a.x1, b.x1), y0: Math.max(a.y0, b.y0), y1: Math.min(a.y1, b.y1) };
}

// Shapes do not depend on the view: their paths are built in world
// coordinates once per (result, mission, last step), and rendered into a
// layer (an offscreen canvas) per view; while the user pans or zooms, the
// layer of the previous view is moved and scaled (one drawImage) until the
// caller asks for a full redraw.
const shapeCache = new WeakMap();
const layerCache = new WeakMap();

/**
 * The detection shapes of a result up to step `last`: one Path2D per colour
 * (world coordinates), the number of shapes and of sectors among them. A
 * shape is what the measurement allows around the result's box of p(step)
 * (shapes.js): the annulus, or the annular sector with a bearing, cut by the
 * detection's `region` and the mission's `landmark_region` (what the
 * mission knows, not the contracted box d(j), so that a group's shapes are
 * seen to cross where its landmark is).
 */
export function shapePaths(result, mission, last) {
  const hit = shapeCache.get(result);
  if (hit && hit.mission === mission && hit.last === last) return hit;
  const group = groupOf(result);
  const parts = new Map();
  let count = 0, sectors = 0;
  const dets = (mission && mission.detections) || [];
  const traj = result.trajectory || [];
  const prior = rect(mission.landmark_region);
  (Array.isArray(result.detections) ? result.detections : []).forEach((b, j) => {
    const d = dets[j];
    if (!d || !(d.step <= last)) return;
    const pbox = traj[d.step];
    const P = rect(pbox);
    let range = interval(d.range);
    if (!P || !range) return;
    if (Array.isArray(pbox) && pbox.length > 2) {
      // 3-D: the horizontal distance is at least sqrt(lo^2 - dz^2) for the
      // largest depth difference dz between the position and the landmark.
      const cz = Array.isArray(b) && b.length > 2 ? b[2] : ['-inf', 'inf'];
      const dz = Math.max(Math.abs(num(pbox[2][1]) - num(cz[0])), Math.abs(num(cz[1]) - num(pbox[2][0])));
      range = [Number.isFinite(dz) ? Math.sqrt(Math.max(0, range[0] * range[0] - dz * dz)) : 0, range[1]];
    }
    let sector = null;
    const bearing = interval(d.bearing);
    const heading = bearing && headingAt(mission, d.step);
    if (heading) sector = [heading[0] + bearing[0], heading[1] + bearing[1]];
    const poly = shapePolygons(P, range, cutOf(rect(d.region), prior), sector);
    if (!poly) return;
    const colour = colourOf(group, j);
    if (!parts.has(colour)) parts.set(colour, []);
    addPolygon(parts.get(colour), poly.outer);
    if (poly.hole) addPolygon(parts.get(colour), poly.hole);
    count++;
    if (sector) sectors++;
  });
  const paths = new Map([...parts].map(([colour, p]) => [colour, new Path2D(p.join(''))]));
  const out = { mission, last, paths, count, sectors };
  shapeCache.set(result, out);
  return out;
}

/** Fills the shapes, faintly, into a canvas-sized layer under the view's transform. */
function renderLayer(layer, canvas, view, shapes) {
  layer.width = canvas.width;
  layer.height = canvas.height;
  const ctx = layer.getContext('2d', { willReadFrequently: true });
  ctx.setTransform(view.scale, 0, 0, -view.scale, canvas.width / 2 - view.cx * view.scale, canvas.height / 2 + view.cy * view.scale);
  for (const [colour, path] of shapes.paths) {
    ctx.globalAlpha = colour === UNMATCHED ? 0.12 : 0.22;
    ctx.fillStyle = colour;
    ctx.fill(path, 'nonzero');
  }
}

/**
 * Draws the shapes layer: rendered for this view, or, when `moving` and a
 * layer of the same shapes exists for another view, that layer moved and
 * scaled to this view (returns true then: the caller redraws when the
 * movement stops).
 */
function drawShapes(ctx, canvas, view, shapes, moving) {
  let c = layerCache.get(canvas);
  const same = c && c.shapes === shapes && c.scale === view.scale && c.cx === view.cx && c.cy === view.cy && c.w === canvas.width && c.h === canvas.height;
  if (!same && moving && c && c.shapes === shapes) {
    const k = view.scale / c.scale, w = canvas.width, h = canvas.height;
    ctx.drawImage(c.layer, w / 2 - (w / 2) * k + (c.cx - view.cx) * view.scale, h / 2 - (h / 2) * k - (c.cy - view.cy) * view.scale, w * k, h * k);
    return true;
  }
  if (!same) {
    if (!c) { c = { layer: document.createElement('canvas') }; layerCache.set(canvas, c); }
    renderLayer(c.layer, canvas, view, shapes);
    Object.assign(c, { shapes, scale: view.scale, cx: view.cx, cy: view.cy, w: canvas.width, h: canvas.height });
  }
  ctx.drawImage(c.layer, 0, 0);
  return false;
}

/**
 * Draws a SLAM result: trajectory boxes up to `untilStep`, detection
 * shapes (faint, coloured by proved group), the detection boxes of the detections
 * made so far, landmark boxes and landmark regions, and the truth when
 * present. `layers` hides shapes, boxes or regions ({shapes: false, ...});
 * `moving` (during a pan or zoom) allows the shapes of the previous view,
 * moved, and then the canvas's dataset says `stale` = "true" (redraw once
 * the movement stops). Writes what was drawn into the canvas's dataset
 * (shapes, sectors, boxes, regions, ms, stale) and returns the drawn
 * trajectory rectangles (for hover).
 */
export function drawResult(canvas, view, result, mission, untilStep, layers = {}, moving = false) {
  const t0 = performance.now();
  const show = (k) => layers[k] !== false;
  const ctx = canvas.getContext('2d');
  ctx.clearRect(0, 0, canvas.width, canvas.height);
  ctx.lineWidth = 1;
  const traj = Array.isArray(result.trajectory) ? result.trajectory : [];
  const last = Math.min(untilStep ?? traj.length - 1, traj.length - 1);
  const stats = { shapes: 0, sectors: 0, boxes: 0, regions: 0, stale: false };
  const dets = (mission && mission.detections) || [];
  const made = (j) => !dets[j] || dets[j].step <= last;


  // At most 400 trajectory boxes: enough to see the corridor, few enough
  // to see the shapes through it.
  const stride = Math.max(1, Math.ceil(traj.length / 400));
  const drawn = [];
  const tpath = new Path2D();
  for (let i = 0; i <= last; i += stride) {
    const r = rect(traj[i]);
    if (!r) continue;
    tpath.rect(view.tx(r.x0), view.ty(r.y1), Math.max((r.x1 - r.x0) * view.scale, 1), Math.max((r.y1 - r.y0) * view.scale, 1));
    drawn.push([i, r]);
  }
  ctx.strokeStyle = 'rgba(74,144,217,0.5)';
  ctx.stroke(tpath);

  if (show('shapes') && mission) {
    const s = shapePaths(result, mission, last);
    stats.stale = drawShapes(ctx, canvas, view, s, moving);
    stats.shapes = s.count;
    stats.sectors = s.sectors;
  }

  if (show('boxes')) {
    const group = groupOf(result);
    const byColour = new Map();
    (Array.isArray(result.detections) ? result.detections : []).forEach((b, j) => {
      const r = rect(b);
      if (!r || !made(j)) return;
      const colour = colourOf(group, j);
      let path = byColour.get(colour);
      if (!path) { path = new Path2D(); byColour.set(colour, path); }
      path.rect(view.tx(r.x0), view.ty(r.y1), Math.max((r.x1 - r.x0) * view.scale, 1), Math.max((r.y1 - r.y0) * view.scale, 1));
      stats.boxes++;
    });
    for (const [colour, path] of byColour) { ctx.strokeStyle = colour; ctx.stroke(path); }
  }

  if (show('regions') && Array.isArray(result.landmark_regions)) {
    const path = new Path2D();
    result.landmark_regions.forEach((paving) => {
      (Array.isArray(paving) ? paving : []).forEach((b) => {
        const r = rect(b);
        if (!r) return;
        path.rect(view.tx(r.x0), view.ty(r.y1), Math.max((r.x1 - r.x0) * view.scale, 1.5), Math.max((r.y1 - r.y0) * view.scale, 1.5));
        stats.regions++;
      });
    });
    ctx.fillStyle = 'rgba(200,0,0,0.55)';
    ctx.fill(path);
  }

  if (show('boxes')) {
    (Array.isArray(result.landmarks) ? result.landmarks : []).forEach((b) => {
      const r = rect(b);
      if (r) drawRect(ctx, view, r, '#b00000', 'rgba(200,0,0,0.12)');
    });
  }

  const truth = mission && mission.truth;
  if (truth) {
    ctx.strokeStyle = '#000'; ctx.beginPath();
    const step = Math.max(1, Math.ceil(truth.positions.length / 4000));
    truth.positions.slice(0, last + 1).forEach((p, i) => {
      if (i % step) return;
      if (i === 0) ctx.moveTo(view.tx(p[0]), view.ty(p[1])); else ctx.lineTo(view.tx(p[0]), view.ty(p[1]));
    });
    ctx.stroke();
    ctx.fillStyle = '#000';
    truth.landmarks.forEach((l) => { ctx.beginPath(); ctx.arc(view.tx(l[0]), view.ty(l[1]), 3, 0, 7); ctx.fill(); });
  }
  Object.assign(canvas.dataset, stats, { ms: (performance.now() - t0).toFixed(2) });
  return drawn;
}
