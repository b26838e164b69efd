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

// Shapes depend neither on the view nor on the time shown: their paths are
// built in world coordinates once per (result, mission), each with its step,
// and the time slider only filters them.
const shapeCache = new WeakMap();

/**
 * The detection shapes of a result, in detection order: per shape its step,
 * colour (proved group), Path2D (world coordinates), outline (flat points)
 * and bounding box, whether it has a hole and whether it is a sector. A
 * shape is what the measurement allows around the result's box of p(step)
 * (shapes.js): the annulus, or the annular sector with a bearing, cut by the
 * detection's `region` and the mission's `landmark_region` (what the
 * mission knows, not the contracted box d(j), so that a group's shapes are
 * seen to cross where its landmark is).
 */
export function shapePaths(result, mission) {
  const hit = shapeCache.get(result);
  if (hit && hit.mission === mission) return hit;
  const group = groupOf(result);
  const list = [];
  const dets = (mission && mission.detections) || [];
  const traj = result.trajectory || [];
  const prior = rect(mission.landmark_region);
  (Array.isArray(result.detections) ? result.detections : []).forEach((b, j) => {
    const d = dets[j];
    if (!d) return;
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
    const parts = [];
    addPolygon(parts, poly.outer);
    if (poly.hole) addPolygon(parts, poly.hole);
    const o = poly.outer;
    const bbox = { x0: Infinity, x1: -Infinity, y0: Infinity, y1: -Infinity };
    for (let i = 0; i < o.length; i += 2) {
      bbox.x0 = Math.min(bbox.x0, o[i]); bbox.x1 = Math.max(bbox.x1, o[i]);
      bbox.y0 = Math.min(bbox.y0, o[i + 1]); bbox.y1 = Math.max(bbox.y1, o[i + 1]);
    }
    list.push({ step: d.step, colour: colourOf(group, j), path: new Path2D(parts.join('')), outer: o, hole: poly.hole, bbox, sector: !!sector });
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

/** The hole's bounding box (the hole is small and convex). */
function holeBox(h) {
  const r = { x0: Infinity, x1: -Infinity, y0: Infinity, y1: -Infinity };
  for (let i = 0; i < h.length; i += 2) {
    r.x0 = Math.min(r.x0, h[i]); r.x1 = Math.max(r.x1, h[i]);
    r.y0 = Math.min(r.y0, h[i + 1]); r.y1 = Math.max(r.y1, h[i + 1]);
  }
  return r;
}

const rectPath = (r) => `M${r.x0} ${r.y0}H${r.x1}V${r.y1}H${r.x0}Z`;

// Everything else a result draws, in world coordinates too: one Path2D per
// stroke or fill, built once per (result, mission, last step) from a string.
const sceneCache = new WeakMap();

/** The trajectory, detection boxes, landmark boxes and regions, and truth of a result up to step `last`, as world-coordinate paths. */
function scenePaths(result, mission, last) {
  const hit = sceneCache.get(result);
  if (hit && hit.mission === mission && hit.last === last) return hit;
  const traj = Array.isArray(result.trajectory) ? result.trajectory : [];
  // At most 400 trajectory boxes: enough to see the corridor, few enough
  // to see the shapes through it.
  const stride = Math.max(1, Math.ceil(traj.length / 400));
  const drawn = [], tparts = [];
  for (let i = 0; i <= last; i += stride) {
    const r = rect(traj[i]);
    if (!r) continue;
    tparts.push(rectPath(r));
    drawn.push([i, r]);
  }
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
  // Landmark regions: sub-boxes, each once (groups of one landmark often
  // share boxes).
  const seen = new Set(), regionRects = [];
  let regions = 0;
  (Array.isArray(result.landmark_regions) ? result.landmark_regions : []).forEach((paving) => {
    (Array.isArray(paving) ? paving : []).forEach((b) => {
      const r = rect(b);
      if (!r) return;
      regions++;
      const k = rectPath(r);
      if (!seen.has(k)) { seen.add(k); regionRects.push(r); }
    });
  });
  const lparts = (Array.isArray(result.landmarks) ? result.landmarks : []).map(rect).filter(Boolean).map(rectPath);
  const truth = mission && mission.truth;
  let truthPath = null;
  if (truth && Array.isArray(truth.positions)) {
    const step = Math.max(1, Math.ceil(truth.positions.length / 4000));
    const parts = [];
    truth.positions.slice(0, last + 1).forEach((p, i) => { if (i % step === 0) parts.push(`${i ? 'L' : 'M'}${p[0]} ${p[1]}`); });
    if (parts.length) truthPath = new Path2D(parts.join(''));
  }
  const out = {
    mission, last, drawn, boxes,
    trajectory: new Path2D(tparts.join('')),
    boxPaths: new Map([...boxParts].map(([c, p]) => [c, new Path2D(p.join(''))])),
    regions, regionRects,
    landmarks: new Path2D(lparts.join('')),
    truthPath,
    truthLandmarks: truth && Array.isArray(truth.landmarks) ? truth.landmarks : [],
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

/** Renders the whole picture into `layer` for the view. */
function render(layer, canvas, view, sc, shapes, show, last) {
  layer.width = canvas.width;
  layer.height = canvas.height;
  const ctx = layer.getContext('2d', { willReadFrequently: true });
  ctx.setTransform(view.scale, 0, 0, -view.scale, canvas.width / 2 - view.cx * view.scale, canvas.height / 2 + view.cy * view.scale);
  ctx.lineWidth = 1 / view.scale;
  ctx.strokeStyle = 'rgba(74,144,217,0.5)';
  ctx.stroke(sc.trajectory);
  if (shapes) {
    // Per colour, the union of its shapes at one opacity: each shape filled
    // opaque on a mask (one small path at a time rasterises much faster
    // than one path of thousands of overlapping ones), laid on faintly.
    // Shapes outside the view are skipped, and once one shape covers the
    // whole view, the rest of its colour is. Beyond 400 shapes the masks
    // have half the resolution (a quarter of the pixels to fill; faint fills
    // do not need sharp edges).
    const seen = { x0: view.wx(0), x1: view.wx(canvas.width), y0: view.wy(canvas.height), y1: view.wy(0) };
    const byColour = new Map();
    for (const sh of shapes.list) {
      if (!(sh.step <= last) || !meets(sh.bbox, seen)) continue;
      if (!byColour.has(sh.colour)) byColour.set(sh.colour, []);
      byColour.get(sh.colour).push(sh);
    }
    const res = shapes.count > 400 ? 0.5 : 1;
    for (const [colour, list] of byColour) {
      const m = mask(layer, ctx, res);
      m.fillStyle = colour;
      for (const sh of list) {
        if (holds(sh.outer, seen) && !(sh.hole && meets(holeBox(sh.hole), seen))) {
          m.fillRect(seen.x0, seen.y0, seen.x1 - seen.x0, seen.y1 - seen.y0);
          break;
        }
        m.fill(sh.path, 'nonzero');
      }
      layOn(ctx, m, colour === UNMATCHED ? 0.12 : 0.22);
    }
  }
  if (show('boxes')) for (const [colour, path] of sc.boxPaths) { ctx.strokeStyle = colour; ctx.stroke(path); }
  if (show('regions') && sc.regionRects.length) {
    // Their union at one opacity, the same way (opaque rectangles).
    // Whole pixels, rounded outwards: adjacent sub-boxes leave no seam.
    const m = mask(layer, ctx);
    m.setTransform(1, 0, 0, 1, 0, 0);
    m.fillStyle = '#c80000';
    for (const r of sc.regionRects) {
      const x0 = Math.floor(view.tx(r.x0)), x1 = Math.ceil(view.tx(r.x1)), y0 = Math.floor(view.ty(r.y1)), y1 = Math.ceil(view.ty(r.y0));
      m.fillRect(x0, y0, Math.max(x1 - x0, 1), Math.max(y1 - y0, 1));
    }
    layOn(ctx, m, 0.45);
  }
  if (show('boxes')) {
    ctx.fillStyle = 'rgba(200,0,0,0.12)';
    ctx.fill(sc.landmarks);
    ctx.strokeStyle = '#b00000';
    ctx.stroke(sc.landmarks);
  }
  if (sc.truthPath) {
    ctx.strokeStyle = '#000';
    ctx.stroke(sc.truthPath);
  }
  ctx.setTransform(1, 0, 0, 1, 0, 0);
  ctx.fillStyle = '#000';
  for (const l of sc.truthLandmarks) { ctx.beginPath(); ctx.arc(view.tx(l[0]), view.ty(l[1]), 3, 0, 7); ctx.fill(); }
}

/**
 * Draws a SLAM result: trajectory boxes up to `untilStep`, detection
 * shapes (faint, coloured by proved group), the boxes of the detections
 * made so far, landmark regions and boxes, and the truth when present.
 * `layers` hides shapes, boxes or regions ({shapes: false, ...}); `moving`
 * (during a pan or zoom) allows the picture of the previous view, moved and
 * scaled, and then the canvas's dataset says `stale` = "true" (redraw once
 * the movement stops). Paths are cached in world coordinates and drawn
 * under the view's transform. Writes what was drawn into the canvas's
 * dataset (shapes, sectors, boxes, regions, ms, stale) and returns the drawn
 * trajectory rectangles (for hover).
 */
export function drawResult(canvas, view, result, mission, untilStep, layers = {}, moving = false) {
  const t0 = performance.now();
  const show = (k) => layers[k] !== false;
  const traj = Array.isArray(result.trajectory) ? result.trajectory : [];
  const last = Math.min(untilStep ?? traj.length - 1, traj.length - 1);
  const sc = scenePaths(result, mission, last);
  let shapes = null;
  if (show('shapes') && mission) {
    const all = shapePaths(result, mission);
    const upTo = all.list.filter((sh) => sh.step <= last);
    shapes = { list: all.list, count: upTo.length, sectors: upTo.filter((sh) => sh.sector).length };
  }
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
      render(c.layer, canvas, view, sc, shapes, show, last);
      Object.assign(c, { sc, shapeList: shapes && shapes.list, key, scale: view.scale, cx: view.cx, cy: view.cy, w: canvas.width, h: canvas.height });
    }
    ctx.drawImage(c.layer, 0, 0);
  }
  Object.assign(canvas.dataset, {
    shapes: shapes ? shapes.count : 0, sectors: shapes ? shapes.sectors : 0,
    boxes: show('boxes') ? sc.boxes : 0, regions: show('regions') ? sc.regions : 0,
    stale, ms: (performance.now() - t0).toFixed(2),
  });
  return sc.drawn;
}
