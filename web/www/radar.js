// The radar demo (TDOA passive location, docs/tdoa.md): a radar problem
// simulated and solved in WASM by its own module (web/www/pkg-radar, the
// web-radar crate), loaded the first time the demo opens: the page's main
// module does not carry the TDOA solver. Drawn in the x-y plane in metres:
// receivers, every pulse's box (its emitter's position) coloured by its
// proved group, the emitter regions (one box per group), the truth.
import { $, canvasPoint, scheduler } from './dom.js';
import { PALETTE, UNMATCHED, View, drawAxes, drawLegend, drawRect, hull, rect } from './draw.js';

/** The last run, for the browser tests: {problem, result, ms}. */
export const radar = { problem: null, result: null, ms: 0 };
let mod = null;
let view = null;

/** The module, loaded once. */
async function load() {
  if (!mod) {
    const m = await import('./pkg-radar/nvector_web_radar.js');
    await m.default();
    mod = m;
  }
  return mod;
}

function groupOf(result) {
  const g = new Array(result.pulses.length).fill(-1);
  result.matching.forEach((members, i) => members.forEach((k) => { g[k] = i; }));
  return g;
}

function draw() {
  const c = $('rd-canvas'), ctx = c.getContext('2d');
  const { problem, result } = radar;
  ctx.clearRect(0, 0, c.width, c.height);
  if (!result) return;
  const group = groupOf(result);
  result.pulses.forEach((b, k) => {
    const r = rect(b);
    if (r) drawRect(ctx, view, r, group[k] < 0 ? UNMATCHED : PALETTE[group[k] % PALETTE.length]);
  });
  // An emitter region is metres wide in a view of kilometres: its box, and
  // a ring in its group's colour around it so that it shows at any zoom.
  result.emitters.forEach((b, i) => {
    const r = rect(b);
    if (!r) return;
    const colour = PALETTE[i % PALETTE.length];
    drawRect(ctx, view, r, '#000', `${colour}88`);
    ctx.strokeStyle = colour; ctx.lineWidth = 2;
    ctx.beginPath(); ctx.arc(view.tx((r.x0 + r.x1) / 2), view.ty((r.y0 + r.y1) / 2), 10, 0, 7); ctx.stroke();
    ctx.lineWidth = 1;
  });
  ctx.fillStyle = '#000';
  for (const p of (problem.truth && problem.truth.emitters) || []) {
    ctx.beginPath(); ctx.arc(view.tx(p[0]), view.ty(p[1]), 3, 0, 7); ctx.fill();
  }
  ctx.fillStyle = '#333';
  for (const rc of problem.receivers) {
    const r = rect(rc.position);
    const x = view.tx((r.x0 + r.x1) / 2), y = view.ty((r.y0 + r.y1) / 2);
    ctx.fillRect(x - 4, y - 4, 8, 8);
  }
  drawAxes(ctx, view, 'm');
  drawLegend(ctx, [
    { label: 'receivers', kind: 'fill', colour: '#333' },
    { label: 'pulse boxes (by proved group)', kind: 'outline', colour: PALETTE.slice(0, 3) },
    { label: 'pulses in no group', kind: 'outline', colour: UNMATCHED },
    { label: 'emitter regions (ringed)', kind: 'fill', colour: `${PALETTE[0]}88` },
    { label: 'true emitters', kind: 'dot', colour: '#000' },
  ]);
}

/** Simulates with the controls' options, solves, draws and writes the summary. */
export async function radarDemo() {
  const summary = $('rd-summary');
  try {
    const m = await load();
    const opts = { seed: Number($('rd-seed').value) | 0, emitters: Number($('rd-emitters').value) | 0, pulses: Number($('rd-pulses').value) | 0 };
    const text = m.simulate(JSON.stringify(opts));
    const t0 = performance.now();
    const result = JSON.parse(m.solve(text, $('rd-mode').value));
    radar.ms = performance.now() - t0;
    radar.problem = JSON.parse(text);
    radar.result = result;
  } catch (e) {
    summary.textContent = `error: ${e.message || e}`;
    summary.dataset.error = String(e.message || e);
    return;
  }
  const { problem, result } = radar;
  const rects = result.emitters.map(rect).concat(problem.receivers.map((r) => rect(r.position)));
  for (const p of problem.truth.emitters) rects.push({ x0: p[0], x1: p[0], y0: p[1], y1: p[1] });
  view = new View($('rd-canvas'));
  view.fit(hull(rects));
  draw();
  const s = result.score;
  Object.assign(summary.dataset, {
    pulses: result.pulses.length, groups: result.matching.length, truthInside: String(s.truth_inside),
    errors: s.matching_errors, recall: s.matching_recall, ms: radar.ms.toFixed(1), error: '',
  });
  summary.textContent = `${result.pulses.length} pulses, ${problem.receivers.length} receivers, at most ${problem.emitter_count} emitters: ${result.matching.length} proved groups, recall ${s.matching_recall.toFixed(2)}, matching errors ${s.matching_errors}, truth inside ${s.truth_inside}, ${radar.ms.toFixed(0)} ms (${result.contractor})`;
}

/** Wires the controls and the view (drag to pan, wheel to zoom); the module loads on the first run. */
export function initRadar() {
  $('rd-run').addEventListener('click', radarDemo);
  const c = $('rd-canvas'), request = scheduler(draw);
  let drag = null;
  c.addEventListener('pointerdown', (ev) => { drag = canvasPoint(c, ev); c.setPointerCapture(ev.pointerId); });
  c.addEventListener('pointerup', () => { drag = null; });
  c.addEventListener('pointermove', (ev) => {
    if (!drag || !view) return;
    const p = canvasPoint(c, ev);
    view.pan(p[0] - drag[0], p[1] - drag[1]);
    drag = p;
    request(true);
  });
  c.addEventListener('wheel', (ev) => {
    if (!view) return;
    ev.preventDefault();
    const [px, py] = canvasPoint(c, ev);
    view.zoom(ev.deltaY < 0 ? 1.25 : 1 / 1.25, px, py);
    request(true);
  });
}
