// The missions tab's picture of a result: the figure core describes for
// every renderer (core/src/figure.rs `describe`, through the figures
// module's `describe`), the one the CLI's PNG and the service's SVG draw:
// the same layers (the landmark regions of the drawn groups as their
// boxes, the tightest groups outlined), colours, opacities and legend
// labels, axes labelled in metres. What the page adds: pan and zoom, the
// time slider (the figure of the result up to a step), the layer toggles,
// and the detection shapes on request (off by default: the CLI's figure
// has none).
import { drawAxes, rect, shapePaths, UNMATCHED } from './draw.js';

/** The figure layers each toggle of the legend (draw.js LAYER_NAMES) hides. */
const TOGGLE = {
  trajectory: 'trajectory', headings: 'headings', headings_unknown: 'headings', detections: 'boxes',
  regions: 'regions', groups: 'groups', truth_path: 'truth', truth_headings: 'truth', truth_landmarks: 'truth',
};

/** `#rrggbb` and an opacity as a CSS colour. */
function rgba(hex, a) {
  const n = parseInt(String(hex).slice(1), 16);
  return `rgba(${(n >> 16) & 255},${(n >> 8) & 255},${n & 255},${a})`;
}

/**
 * The result up to step `last` (the time slider): the trajectory, the
 * headings and the truth's path cut after it, the detections of later
 * steps left out ("empty", the result format's empty box: not drawn, the
 * groups keep their indices).
 */
function upTo(result, mission, last) {
  const n = Array.isArray(result.trajectory) ? result.trajectory.length : 0;
  if (last >= n - 1) return [result, mission];
  const dets = (mission && mission.detections) || [];
  const r = { ...result, trajectory: result.trajectory.slice(0, last + 1) };
  if (Array.isArray(result.headings)) r.headings = result.headings.slice(0, last + 1);
  if (Array.isArray(result.detections)) r.detections = result.detections.map((b, j) => (dets[j] && dets[j].step <= last ? b : 'empty'));
  let m = mission;
  if (mission && mission.truth) {
    const t = { ...mission.truth };
    if (Array.isArray(t.positions)) t.positions = t.positions.slice(0, last + 1);
    if (Array.isArray(t.headings)) t.headings = t.headings.slice(0, last + 1);
    m = { landmark_count: mission.landmark_count, truth: t };
  }
  return [r, m];
}

/**
 * The figure of a shown result `s` ({result, mission}) up to step `last`,
 * from core through the figures module's handle `core`; cached per step.
 */
export function figureOf(core, s, last) {
  if (!s.figures) s.figures = new Map();
  let f = s.figures.get(last);
  if (!f) {
    const [r, m] = upTo(s.result, s.mission, last);
    f = JSON.parse(core.describe(JSON.stringify(r), m ? JSON.stringify(m) : ''));
    if (s.figures.size > 8) s.figures.clear();
    s.figures.set(last, f);
  }
  return f;
}

/** Draws one figure layer in world coordinates (the context's transform maps metres to pixels; `px`: a pixel in metres). */
function drawLayer(ctx, l, px) {
  const fill = l.fill_alpha > 0 ? rgba(l.colour, l.fill_alpha) : null;
  // Hairlines (under 1 px) as 1 px at half strength, as the CLI draws them.
  const stroke = l.line_width > 0 ? (l.line_width < 1 ? rgba(l.colour, 0.5) : l.colour) : null;
  ctx.lineWidth = Math.max(l.line_width, 1) * px;
  if (l.kind === 'rects') {
    for (const r of l.rects) {
      if (fill) { ctx.fillStyle = fill; ctx.fillRect(r[0], r[2], r[1] - r[0], r[3] - r[2]); }
      if (stroke) { ctx.strokeStyle = stroke; ctx.strokeRect(r[0], r[2], r[1] - r[0], r[3] - r[2]); }
    }
  } else if (l.kind === 'path' && l.points.length) {
    ctx.lineJoin = 'round';
    ctx.beginPath();
    l.points.forEach((p, i) => (i ? ctx.lineTo(p[0], p[1]) : ctx.moveTo(p[0], p[1])));
    // A white halo under the line: visible over any colour.
    ctx.strokeStyle = 'rgba(255,255,255,0.9)'; ctx.lineWidth = (l.line_width + 2.5) * px; ctx.stroke();
    ctx.strokeStyle = l.colour; ctx.lineWidth = l.line_width * px; ctx.stroke();
  } else if (l.kind === 'points') {
    ctx.fillStyle = l.colour;
    for (const p of l.points) { ctx.beginPath(); ctx.arc(p[0], p[1], 4 * px, 0, 2 * Math.PI); ctx.fill(); }
  } else if (l.kind === 'polygons') {
    for (const poly of l.polygons) {
      ctx.beginPath();
      poly.forEach((p, i) => (i ? ctx.lineTo(p[0], p[1]) : ctx.moveTo(p[0], p[1])));
      if (poly.length > 2) ctx.closePath();
      if (fill && poly.length > 2) { ctx.fillStyle = fill; ctx.fill(); }
      if (stroke) { ctx.strokeStyle = stroke; ctx.stroke(); }
    }
  }
}

/** The legend entry of a layer, in draw.js's legend kinds. */
function legendEntry(l) {
  if (l.kind === 'path') return { label: l.label, kind: 'line', colour: l.colour };
  if (l.kind === 'points') return { label: l.label, kind: 'dot', colour: l.colour };
  if (l.fill_alpha > 0) return { label: l.label, kind: 'fill', colour: rgba(l.colour, Math.max(l.fill_alpha, 0.35)) };
  return { label: l.label, kind: l.kind === 'polygons' ? 'line' : 'outline', colour: l.colour };
}

/**
 * The legend under a canvas (an element made once, after it): one line per
 * drawn layer, its key in the layer's colour, the figure's label.
 */
function htmlLegend(canvas, entries) {
  let box = canvas.parentElement.querySelector('.figlegend');
  if (!box) {
    box = document.createElement('ul');
    box.className = 'figlegend';
    canvas.after(box);
  }
  box.replaceChildren(...entries.map((e) => {
    const li = document.createElement('li');
    const key = document.createElement('i');
    const c = Array.isArray(e.colour) ? e.colour[0] : e.colour;
    key.className = `k-${e.kind}`;
    if (e.kind === 'line' || e.kind === 'outline') key.style.borderColor = c; else key.style.background = c;
    li.append(key, e.label);
    return li;
  }));
}

/** The detection shapes on request (page only), each group's at one opacity, over the figure's layers. */
function drawShapes(ctx, view, s, last, show) {
  const shapes = shapePaths(s.result, s.mission);
  const byColour = new Map();
  let n = 0, sectors = 0;
  for (const sh of shapes.list) {
    if (!(sh.step <= last) || (sh.unmatched && !show('unmatched'))) continue;
    n++; if (sh.sector) sectors++;
    if (!byColour.has(sh.colour)) byColour.set(sh.colour, []);
    byColour.get(sh.colour).push(sh);
  }
  const c = ctx.canvas, m = document.createElement('canvas');
  m.width = c.width; m.height = c.height;
  const mc = m.getContext('2d');
  for (const [colour, list] of byColour) {
    mc.setTransform(1, 0, 0, 1, 0, 0); mc.clearRect(0, 0, m.width, m.height);
    mc.setTransform(ctx.getTransform());
    mc.fillStyle = colour;
    for (const sh of list) mc.fill(sh.path, 'nonzero');
    const t = ctx.getTransform();
    ctx.setTransform(1, 0, 0, 1, 0, 0);
    ctx.globalAlpha = colour === UNMATCHED ? 0.12 : 0.22;
    ctx.drawImage(m, 0, 0);
    ctx.globalAlpha = 1;
    ctx.setTransform(t);
  }
  return { shapes: n, sectors };
}

/**
 * Draws the figure of the shown result `s` up to step `last` on `canvas`
 * through `view` (pan, zoom): the figure's layers bottom to top (those
 * whose toggle is off left out), the detection shapes when asked, the axes
 * in metres with their labels ("x (m)", "y (m)"), and the legend (under
 * the canvas, beside the picture as the CLI's). Writes what was drawn into the
 * canvas's dataset (legend, axes, unit, groups, regions, shapes, sectors,
 * layers, ms) and returns the hoverable trajectory boxes ([step, rect]).
 */
export function drawFigure(core, canvas, view, s, last, layers = {}) {
  const t0 = performance.now();
  const show = (k) => layers[k] !== false;
  const fig = figureOf(core, s, last);
  const ctx = canvas.getContext('2d');
  ctx.setTransform(1, 0, 0, 1, 0, 0);
  ctx.clearRect(0, 0, canvas.width, canvas.height);
  ctx.setTransform(view.scale, 0, 0, -view.scale, canvas.width / 2 - view.cx * view.scale, canvas.height / 2 + view.cy * view.scale);
  const px = 1 / view.scale;
  const drawn = fig.layers.filter((l) => show(TOGGLE[l.name] || l.name));
  for (const l of drawn) {
    // The shapes go under the proved groups' outlines and the truth.
    if (l.name === 'groups' && show('shapes') && s.mission) s.shapesDrawn = drawShapes(ctx, view, s, last, show);
    drawLayer(ctx, l, px);
  }
  if (!drawn.some((l) => l.name === 'groups')) s.shapesDrawn = show('shapes') && s.mission ? drawShapes(ctx, view, s, last, show) : null;
  else if (!show('shapes') || !s.mission) s.shapesDrawn = null;
  ctx.setTransform(1, 0, 0, 1, 0, 0);
  drawAxes(ctx, view, 'm');
  // The axes' labels in the corners the ticks leave free: x at the bottom
  // right, y at the top left, over a white halo.
  ctx.font = 'bold 11px system-ui, sans-serif';
  const label = (text, x, y, align, base) => {
    ctx.textAlign = align; ctx.textBaseline = base;
    ctx.strokeStyle = 'rgba(255,255,255,0.9)'; ctx.lineWidth = 3; ctx.strokeText(text, x, y);
    ctx.fillStyle = '#222'; ctx.fillText(text, x, y);
  };
  label(fig.x_label, canvas.width - 4, canvas.height - 4, 'right', 'bottom');
  label(fig.y_label, 4, 3, 'left', 'top');
  ctx.lineWidth = 1;
  const entries = drawn.map(legendEntry);
  if (s.shapesDrawn && s.shapesDrawn.shapes) entries.push({ label: 'detection shapes (page only)', kind: 'fill', colour: 'rgba(230,25,75,0.3)' });
  if (!entries.length) entries.push({ label: 'nothing to draw', kind: 'outline', colour: '#ccc' });
  // The legend beside the plot, as the CLI's: under the canvas, not over
  // the picture.
  htmlLegend(canvas, entries);
  const count = (name, key) => { const l = drawn.find((x) => x.name === name); return l ? l[key].length : 0; };
  Object.assign(canvas.dataset, {
    legend: entries.map((e) => e.label).join('|'), legendBox: '', xLabel: fig.x_label, yLabel: fig.y_label,
    layers: drawn.map((l) => l.name).join(','), groups: count('groups', 'rects'), regions: count('regions', 'rects'),
    shapes: s.shapesDrawn ? s.shapesDrawn.shapes : 0, sectors: s.shapesDrawn ? s.shapesDrawn.sectors : 0,
    stale: false, ms: (performance.now() - t0).toFixed(2),
  });
  // The boxes a pointer can hover: at most 2000, every k-th and the last.
  const traj = Array.isArray(s.result.trajectory) ? s.result.trajectory : [];
  const stride = Math.max(1, Math.ceil((last + 1) / 2000));
  const hover = [];
  for (let i = 0; i <= last; i += stride) { const r = rect(traj[i]); if (r) hover.push([i, r]); }
  return hover;
}

/** The view of a figure: its `view` [x0, x1, y0, y1] as a rectangle for View.fit. */
export function figureArea(fig) {
  const [x0, x1, y0, y1] = fig.view;
  return { x0, x1, y0, y1 };
}
