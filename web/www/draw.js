// Canvas drawing of boxes, kept apart from the API calls.

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

/**
 * Draws a SLAM result: trajectory boxes up to `untilStep`, detection boxes
 * coloured by matching group, landmark boxes, and the truth when present.
 * Returns the drawn trajectory rectangles (for hover).
 */
export function drawResult(canvas, view, result, mission, untilStep) {
  const ctx = canvas.getContext('2d');
  ctx.clearRect(0, 0, canvas.width, canvas.height);
  ctx.lineWidth = 1;
  const traj = result.trajectory || [];
  const last = Math.min(untilStep ?? traj.length - 1, traj.length - 1);
  const stride = Math.max(1, Math.ceil(traj.length / 2000));
  const drawn = [];
  for (let i = 0; i <= last; i += stride) {
    const r = rect(traj[i]);
    if (r) { drawRect(ctx, view, r, 'rgba(74,144,217,0.6)'); drawn.push([i, r]); }
  }
  const group = new Map();
  (result.matching || []).forEach((g, k) => g.forEach((j) => group.set(j, k)));
  (result.detections || []).forEach((b, j) => {
    const r = rect(b);
    const g = group.get(j);
    if (r) drawRect(ctx, view, r, g === undefined ? '#999' : PALETTE[g % PALETTE.length]);
  });
  (result.landmarks || []).forEach((b) => {
    const r = rect(b);
    if (r) drawRect(ctx, view, r, '#b00000', 'rgba(200,0,0,0.2)');
  });
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
  return drawn;
}
