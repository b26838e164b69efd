// The nvector playground: boxes the user draws, contracted by core's
// atmost_nvector in WASM at every change (offline).
import { $, canvasPoint } from './dom.js';
import { View, drawPlayground, hull } from './draw.js';

const PRESETS = {
  // The paper's Figure 2: three boxes, two of which overlap, n = 2.
  fig2: { n: 2, boxes: [[[0, 2], [0, 2]], [[1, 3], [1, 3]], [[5, 6], [5, 6]]] },
  // Figure 8: k = 7, n = 3, groups {1,2}, {4,5}, {7} on the first axis.
  fig8: { n: 3, boxes: [[[0, 2], [0, 5]], [[1, 3], [3, 8]], [[2, 6], [0, 10]], [[5, 7], [0, 10]], [[6, 8], [0, 10]], [[7, 12], [0, 10]], [[11, 13], [0, 10]]] },
  // The Global Constraint Catalogue's example.
  gccat: { n: 2, boxes: [[[1, 6], [2, 6]], [[3, 5], [6, 9]], [[4, 10], [1, 4]], [[5, 9], [3, 7]], [[9, 11], [0, 5]]] },
};

let nv = null;
const pg = { boxes: [], selected: -1, drag: null, view: null, out: null };

/** Loads a preset (fig2, fig8, gccat) and fits the view to it. */
export function loadPreset(name) {
  const p = PRESETS[name] || PRESETS.fig8;
  pg.boxes = p.boxes.map((b) => ({ x0: b[0][0], x1: b[0][1], y0: b[1][0], y1: b[1][1] }));
  $('pg-n').value = p.n;
  pg.view.fit(hull(pg.boxes));
  // Room for the legend in the top right corner.
  pg.view.zoom(0.85, pg.view.canvas.width * 0.4, pg.view.canvas.height * 0.6);
  contractAndDraw();
}

/** Contracts the boxes in WASM and draws the result; the summary's dataset holds the figures. */
function contractAndDraw() {
  const canvas = $('pg-canvas');
  const summary = $('pg-summary');
  pg.out = null;
  if (!nv || pg.boxes.length === 0) {
    drawPlayground(canvas, pg.view, pg.boxes, null, pg.selected);
    $('pg-text').textContent = 'add boxes';
    return;
  }
  const req = {
    format: 'nvector-contract/1', n: Math.max(1, Number($('pg-n').value) | 0),
    contractor: $('pg-mode').value,
    boxes: pg.boxes.map((b) => [[b.x0, b.x1], [b.y0, b.y1]]),
  };
  let out;
  const t0 = performance.now();
  try { out = JSON.parse(nv.contract(JSON.stringify(req))); } catch (e) { $('pg-text').textContent = String(e); drawPlayground(canvas, pg.view, pg.boxes, null, pg.selected); return; }
  const ms = performance.now() - t0;
  pg.out = out;
  drawPlayground(canvas, pg.view, pg.boxes, out, pg.selected);
  const groups = out.groups.map((g) => g.map((i) => i + 1).join(',')).join(' | ');
  $('pg-text').textContent = `${out.status}${out.reason ? ' (' + out.reason + ')' : ''} — groups ${groups} — min distinct in [${out.min_distinct.lower}, ${out.min_distinct.upper}] — ${ms.toFixed(2)} ms`;
  Object.assign(summary.dataset, {
    status: out.status, groups: JSON.stringify(out.groups), minLower: out.min_distinct.lower,
    minUpper: out.min_distinct.upper, ms: ms.toFixed(3), boxes: pg.boxes.length,
  });
}

/** The box (or its resize corner) under a canvas point. */
function hit(px, py) {
  const x = pg.view.wx(px), y = pg.view.wy(py);
  for (let i = pg.boxes.length - 1; i >= 0; i--) {
    const b = pg.boxes[i];
    const corner = Math.abs(pg.view.tx(b.x1) - px) < 8 && Math.abs(pg.view.ty(b.y0) - py) < 8;
    if (corner) return { i, corner: true };
    if (x >= b.x0 && x <= b.x1 && y >= b.y0 && y <= b.y1) return { i, corner: false };
  }
  return null;
}

/** Wires the playground's controls (the WASM handle comes later: playgroundReady). */
export function initPlayground() {
  const c = $('pg-canvas');
  pg.view = new View(c);
  c.addEventListener('pointerdown', (ev) => {
    const [px, py] = canvasPoint(c, ev);
    const h = hit(px, py);
    pg.selected = h ? h.i : -1;
    pg.drag = h ? { ...h, px, py } : { pan: true, px, py };
    c.setPointerCapture(ev.pointerId);
    contractAndDraw();
  });
  c.addEventListener('pointermove', (ev) => {
    if (!pg.drag) return;
    const [px, py] = canvasPoint(c, ev);
    const dx = (px - pg.drag.px) / pg.view.scale, dy = -(py - pg.drag.py) / pg.view.scale;
    if (pg.drag.pan) pg.view.pan(px - pg.drag.px, py - pg.drag.py);
    else {
      const b = pg.boxes[pg.drag.i];
      if (pg.drag.corner) { b.x1 = Math.max(b.x0, b.x1 + dx); b.y0 = Math.min(b.y1, b.y0 + dy); }
      else { b.x0 += dx; b.x1 += dx; b.y0 += dy; b.y1 += dy; }
    }
    pg.drag.px = px; pg.drag.py = py;
    contractAndDraw();
  });
  c.addEventListener('pointerup', () => { pg.drag = null; });
  c.addEventListener('dblclick', (ev) => {
    const [px, py] = canvasPoint(c, ev);
    const x = pg.view.wx(px), y = pg.view.wy(py), s = 40 / pg.view.scale;
    pg.boxes.push({ x0: x - s, x1: x + s, y0: y - s, y1: y + s });
    contractAndDraw();
  });
  c.addEventListener('wheel', (ev) => { ev.preventDefault(); const [px, py] = canvasPoint(c, ev); pg.view.zoom(ev.deltaY < 0 ? 1.1 : 1 / 1.1, px, py); contractAndDraw(); });
  document.addEventListener('keydown', (ev) => {
    if ((ev.key === 'Delete' || ev.key === 'Backspace') && pg.selected >= 0 && document.activeElement === document.body) {
      pg.boxes.splice(pg.selected, 1); pg.selected = -1; contractAndDraw();
    }
  });
  document.querySelectorAll('[data-preset]').forEach((b) => b.addEventListener('click', () => loadPreset(b.dataset.preset)));
  $('pg-clear').addEventListener('click', () => { pg.boxes = []; contractAndDraw(); });
  $('pg-n').addEventListener('input', contractAndDraw);
  $('pg-mode').addEventListener('change', contractAndDraw);
}

/** The WASM handle is loaded: contract from now on. */
export function playgroundReady(handle) { nv = handle; }
