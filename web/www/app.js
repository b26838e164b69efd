// The page: an nvector playground and a SLAM demo that run offline in
// WASM, and the missions view that talks to the service.
import init, { Nvector } from './pkg/nvector_web.js';
import * as api from './api.js';
import { LAYERS, PALETTE, UNMATCHED, View, drawRect, drawResult, hull, rect } from './draw.js';

const $ = (id) => document.getElementById(id);
const el = (tag, text, cls) => { const e = document.createElement(tag); if (text !== undefined) e.textContent = text; if (cls) e.className = cls; return e; };
let nv = null;

// ---- tabs -------------------------------------------------------------
document.querySelectorAll('nav button').forEach((b) => b.addEventListener('click', () => {
  document.querySelectorAll('nav button').forEach((x) => x.classList.toggle('active', x === b));
  document.querySelectorAll('.tab').forEach((t) => t.classList.toggle('active', t.id === b.dataset.tab));
  if (b.dataset.tab === 'missions') refreshLists();
}));
const initialTab = new URLSearchParams(location.search).get('tab');
if (initialTab) document.querySelector(`nav button[data-tab="${initialTab}"]`)?.click();

// ---- playground -------------------------------------------------------
const PRESETS = {
  // The paper's Figure 2: three boxes, two of which overlap, n = 2.
  fig2: { n: 2, boxes: [[[0, 2], [0, 2]], [[1, 3], [1, 3]], [[5, 6], [5, 6]]] },
  // Figure 8: k = 7, n = 3, groups {1,2}, {4,5}, {7} on the first axis.
  fig8: { n: 3, boxes: [[[0, 2], [0, 5]], [[1, 3], [3, 8]], [[2, 6], [0, 10]], [[5, 7], [0, 10]], [[6, 8], [0, 10]], [[7, 12], [0, 10]], [[11, 13], [0, 10]]] },
  // The Global Constraint Catalogue's example.
  gccat: { n: 2, boxes: [[[1, 6], [2, 6]], [[3, 5], [6, 9]], [[4, 10], [1, 4]], [[5, 9], [3, 7]], [[9, 11], [0, 5]]] },
};
const pg = { boxes: [], selected: -1, drag: null, view: new View($('pg-canvas')), out: null };

function loadPreset(name) {
  const p = PRESETS[name];
  pg.boxes = p.boxes.map((b) => ({ x0: b[0][0], x1: b[0][1], y0: b[1][0], y1: b[1][1] }));
  $('pg-n').value = p.n;
  pg.view.fit(hull(pg.boxes));
  pg.view.zoom(0.85, pg.view.canvas.width / 2, pg.view.canvas.height / 2);
  contractAndDraw();
}

function contractAndDraw() {
  const canvas = $('pg-canvas');
  const ctx = canvas.getContext('2d');
  ctx.clearRect(0, 0, canvas.width, canvas.height);
  const summary = $('pg-summary');
  if (!nv || pg.boxes.length === 0) { $('pg-text').textContent = 'add boxes'; return; }
  const req = {
    format: 'nvector-contract/1', n: Math.max(1, Number($('pg-n').value) | 0),
    contractor: $('pg-mode').value,
    boxes: pg.boxes.map((b) => [[b.x0, b.x1], [b.y0, b.y1]]),
  };
  let out;
  const t0 = performance.now();
  try { out = JSON.parse(nv.contract(JSON.stringify(req))); } catch (e) { $('pg-text').textContent = String(e); return; }
  const ms = performance.now() - t0;
  pg.out = out;
  const colour = new Map();
  out.groups.forEach((g, k) => g.forEach((i) => colour.set(i, g.length > 1 ? PALETTE[k % PALETTE.length] : '#555555')));
  // Kernels on the axes.
  (out.kernels || []).forEach((ks, axis) => {
    if (!Array.isArray(ks)) return;
    ctx.fillStyle = 'rgba(0,120,0,0.35)';
    ks.forEach((k) => {
      if (axis === 0) ctx.fillRect(pg.view.tx(k[0]), canvas.height - 8, Math.max((k[1] - k[0]) * pg.view.scale, 2), 8);
      else ctx.fillRect(0, pg.view.ty(k[1]), 8, Math.max((k[1] - k[0]) * pg.view.scale, 2));
    });
  });
  pg.boxes.forEach((b, i) => {
    ctx.setLineDash([4, 3]); ctx.lineWidth = i === pg.selected ? 2 : 1;
    drawRect(ctx, pg.view, b, '#888');
    ctx.setLineDash([]);
    const r = rect(out.boxes[i]);
    if (r) drawRect(ctx, pg.view, r, colour.get(i), colour.get(i) + '33');
    ctx.fillStyle = '#222';
    ctx.fillText(String(i + 1), pg.view.tx(b.x0) + 3, pg.view.ty(b.y1) + 12);
  });
  const groups = out.groups.map((g) => g.map((i) => i + 1).join(',')).join(' | ');
  $('pg-text').textContent = `${out.status}${out.reason ? ' (' + out.reason + ')' : ''} — groups ${groups} — min distinct in [${out.min_distinct.lower}, ${out.min_distinct.upper}] — ${ms.toFixed(2)} ms`;
  Object.assign(summary.dataset, {
    status: out.status, groups: JSON.stringify(out.groups), minLower: out.min_distinct.lower,
    minUpper: out.min_distinct.upper, ms: ms.toFixed(3), boxes: pg.boxes.length,
  });
}

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
const pgc = $('pg-canvas');
const pos = (ev) => { const r = pgc.getBoundingClientRect(); return [(ev.clientX - r.left) * pgc.width / r.width, (ev.clientY - r.top) * pgc.height / r.height]; };
pgc.addEventListener('pointerdown', (ev) => {
  const [px, py] = pos(ev);
  const h = hit(px, py);
  pg.selected = h ? h.i : -1;
  pg.drag = h ? { ...h, px, py } : { pan: true, px, py };
  pgc.setPointerCapture(ev.pointerId);
  contractAndDraw();
});
pgc.addEventListener('pointermove', (ev) => {
  if (!pg.drag) return;
  const [px, py] = pos(ev);
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
pgc.addEventListener('pointerup', () => { pg.drag = null; });
pgc.addEventListener('dblclick', (ev) => {
  const [px, py] = pos(ev);
  const x = pg.view.wx(px), y = pg.view.wy(py), s = 40 / pg.view.scale;
  pg.boxes.push({ x0: x - s, x1: x + s, y0: y - s, y1: y + s });
  contractAndDraw();
});
pgc.addEventListener('wheel', (ev) => { ev.preventDefault(); const [px, py] = pos(ev); pg.view.zoom(ev.deltaY < 0 ? 1.1 : 1 / 1.1, px, py); contractAndDraw(); });
document.addEventListener('keydown', (ev) => {
  if ((ev.key === 'Delete' || ev.key === 'Backspace') && pg.selected >= 0 && document.activeElement === document.body) {
    pg.boxes.splice(pg.selected, 1); pg.selected = -1; contractAndDraw();
  }
});
document.querySelectorAll('[data-preset]').forEach((b) => b.addEventListener('click', () => loadPreset(b.dataset.preset)));
$('pg-clear').addEventListener('click', () => { pg.boxes = []; contractAndDraw(); });
$('pg-n').addEventListener('input', contractAndDraw);
$('pg-mode').addEventListener('change', contractAndDraw);

// ---- legends ----------------------------------------------------------
// A legend with the layers a user can hide and the colours' meanings; the
// views it belongs to are redrawn when a box is (un)ticked.
const LAYER_NAMES = { shapes: 'detection shapes (annuli, sectors)', boxes: 'detection and landmark boxes', regions: 'landmark regions' };
function legend(id, redraw) {
  const box = $(id);
  for (const k of LAYERS) {
    const input = el('input'); input.type = 'checkbox'; input.checked = true; input.dataset.layer = k;
    input.addEventListener('change', redraw);
    const label = el('label'); label.append(input, ` ${LAYER_NAMES[k]}`);
    box.append(label);
  }
  const key = (colours, text) => {
    const span = el('span', undefined, 'key');
    colours.forEach((c) => { const i = el('i'); i.style.background = c; span.append(i); });
    span.append(` ${text}`);
    box.append(span);
  };
  key(['rgba(74,144,217,0.8)'], 'trajectory');
  key(PALETTE.slice(0, 4), 'proved groups');
  key([UNMATCHED], 'unmatched');
  key(['#b00000'], 'landmarks');
  key(['#000'], 'truth');
  return () => Object.fromEntries([...box.querySelectorAll('input[data-layer]')].map((i) => [i.dataset.layer, i.checked]));
}

// ---- redraws ----------------------------------------------------------
// Pan, zoom and sliders redraw at most once a frame; during a pan or zoom
// the shapes of the previous view are moved (redraw(true)), and drawn again
// for the new view once the movement stops.
function scheduler(redraw) {
  let frame = 0, full = false, settle = 0;
  const request = (moving) => {
    if (!moving) full = true;
    if (!frame) frame = requestAnimationFrame(() => { frame = 0; const f = full; full = false; redraw(!f); });
    if (moving) { clearTimeout(settle); settle = setTimeout(() => request(false), 150); }
  };
  return request;
}

// ---- SLAM demo --------------------------------------------------------
['steps', 'noise', 'landmarks'].forEach((k) => $(`sl-${k}`).addEventListener('input', () => { $(`sl-${k}-v`).textContent = $(`sl-${k}`).value; }));
const sl = { shown: [] }; // [{id, result, view}] of the last run, redrawn on legend changes
function slamRedraw(moving = false) {
  const layers = slLayers();
  sl.shown.forEach((s) => drawResult($(s.id), s.view, s.result, sl.mission, undefined, layers, moving === true));
}
const slLayers = legend('sl-legend', () => slamRedraw());
const requestSlam = scheduler(slamRedraw);
// Both views pan and zoom together (drag, wheel).
['sl-basic', 'sl-nv'].forEach((id) => {
  const c = $(id);
  let drag = null;
  const at = (ev) => { const r = c.getBoundingClientRect(); return [(ev.clientX - r.left) * c.width / r.width, (ev.clientY - r.top) * c.height / r.height]; };
  c.addEventListener('pointerdown', (ev) => { drag = at(ev); c.setPointerCapture(ev.pointerId); });
  c.addEventListener('pointerup', () => { drag = null; });
  c.addEventListener('pointermove', (ev) => {
    if (!drag) return;
    const p = at(ev);
    sl.shown.forEach((s) => s.view.pan(p[0] - drag[0], p[1] - drag[1]));
    drag = p;
    requestSlam(true);
  });
  c.addEventListener('wheel', (ev) => {
    if (!sl.shown.length) return;
    ev.preventDefault();
    const [px, py] = at(ev);
    sl.shown.forEach((s) => s.view.zoom(ev.deltaY < 0 ? 1.1 : 1 / 1.1, px, py));
    requestSlam(true);
  });
});
function slamDemo() {
  if (!nv) return;
  const mode = $('sl-mode').value;
  const opts = {
    scenario: 'paper', seed: Number($('sl-seed').value) | 0, steps: Number($('sl-steps').value), noise: Number($('sl-noise').value),
    landmarks: Number($('sl-landmarks').value), layout: $('sl-layout').value, range_only: $('sl-range-only').checked,
  };
  let mission, basic, withNv, t0, t1, t2;
  try {
    const missionText = nv.simulate(JSON.stringify(opts));
    mission = JSON.parse(missionText);
    t0 = performance.now();
    basic = JSON.parse(nv.run(missionText, 'none', () => {}));
    t1 = performance.now();
    withNv = JSON.parse(nv.run(missionText, mode, () => {}));
    t2 = performance.now();
  } catch (e) {
    $('sl-summary').textContent = `error: ${e.message || e}`;
    $('sl-summary').dataset.error = String(e.message || e);
    return;
  }
  const area = hull(basic.trajectory.map(rect));
  sl.mission = mission;
  sl.shown = [['sl-basic', basic], ['sl-nv', withNv]].map(([id, result]) => { const view = new View($(id)); view.fit(area); return { id, result, view }; });
  slamRedraw();
  $('sl-basic-cap').textContent = `basic model: max diameter ${Number(basic.metrics.max_trajectory_diameter).toFixed(2)} m`;
  $('sl-nv-cap').textContent = `with atmost_nvector (${mode}): max diameter ${Number(withNv.metrics.max_trajectory_diameter).toFixed(2)} m`;
  const kind = `${opts.layout}${opts.range_only ? ', range only' : ', range + bearing'}`;
  Object.assign($('sl-summary').dataset, {
    basicDiameter: basic.metrics.max_trajectory_diameter, nvectorDiameter: withNv.metrics.max_trajectory_diameter,
    recall: withNv.score.matching_recall, errors: withNv.score.matching_errors, ms: (t2 - t1).toFixed(1),
    truthInside: String(basic.score.truth_inside && withNv.score.truth_inside), contractor: withNv.options.contractor,
    rangeOnly: String(opts.range_only), layout: opts.layout, detections: mission.detections.length, error: '',
  });
  $('sl-summary').textContent = `${kind}: detections ${mission.detections.length}; basic ${(t1 - t0).toFixed(1)} ms, ${mode} ${(t2 - t1).toFixed(1)} ms; ratio ${(basic.metrics.max_trajectory_diameter / withNv.metrics.max_trajectory_diameter).toFixed(1)}x; recall ${withNv.score.matching_recall.toFixed(2)}; truth inside ${basic.score.truth_inside && withNv.score.truth_inside}; errors ${withNv.score.matching_errors}`;
}
/** The demo's presets: range + bearing against `best`, range only (P'') against `shapes`. */
function slamPreset(rangeOnly) {
  $('sl-range-only').checked = rangeOnly;
  $('sl-mode').value = rangeOnly ? 'shapes' : 'best';
  slamDemo();
}
$('sl-run').addEventListener('click', slamDemo);
$('sl-preset-bearing').addEventListener('click', () => slamPreset(false));
$('sl-preset-range').addEventListener('click', () => slamPreset(true));

// ---- missions (service) -----------------------------------------------
// Jobs submitted from this browser are remembered in localStorage (the API
// lists missions, not jobs), so a reload still lists them and their results.
let pendingFile = null;
let currentJob = null; // the job the cancel button stops
const shown = []; // up to two {result, mission, jobId, view, drawn}
const JOBS_KEY = 'nvector.jobs';
const fail = (e) => { $('ms-state').textContent = `error: ${e.message}`; };
function savedJobs() { try { return JSON.parse(localStorage.getItem(JOBS_KEY) || '[]'); } catch (_) { return []; } }
function saveJobs(jobs) { try { localStorage.setItem(JOBS_KEY, JSON.stringify(jobs.slice(0, 50))); } catch (_) { /* private mode */ } }
function rememberJob(job) { saveJobs([job, ...savedJobs().filter((j) => j.id !== job.id)]); }

function setFile(f) { pendingFile = f; $('ms-submit').disabled = !f; $('ms-state').textContent = f ? `ready: ${f.name || 'mission'}` : ''; }
$('ms-file').addEventListener('change', (ev) => setFile(ev.target.files[0] || null));
const drop = $('drop');
drop.addEventListener('dragover', (ev) => { ev.preventDefault(); drop.classList.add('over'); });
drop.addEventListener('dragleave', () => drop.classList.remove('over'));
drop.addEventListener('drop', (ev) => { ev.preventDefault(); drop.classList.remove('over'); setFile(ev.dataTransfer.files[0] || null); });

async function refreshLists() {
  try {
    const ms = await api.listMissions();
    const ul = $('ms-missions');
    ul.replaceChildren();
    ms.missions.forEach((m) => {
      const li = el('li'); li.dataset.id = m.id;
      li.append(el('span', `${m.name} (${m.steps} steps, ${m.detections} detections) `));
      const run = el('button', 'run', 'run'); run.title = 'run a job on this mission with the contractor and limits above';
      run.addEventListener('click', () => runJob(m.id, m.name));
      const del = el('button', 'delete', 'delete'); del.title = 'delete this mission and its jobs';
      del.addEventListener('click', async () => {
        if (!confirm(`Delete mission ${m.name} and its jobs?`)) return;
        try { await api.deleteMission(m.id); saveJobs(savedJobs().filter((j) => j.mission !== m.id)); } catch (e) { fail(e); }
        refreshLists();
      });
      li.append(run, ' ', del);
      ul.append(li);
    });
    if (!ms.missions.length) ul.append(el('li', 'no mission yet: upload one above', 'hint'));
  } catch (e) { $('ms-missions').textContent = `service unavailable: ${e.message}`; }
  await refreshJobs();
}

function jobItem(job) {
  const id = `job-${job.id}`;
  let li = $(id);
  if (!li) { li = el('li'); li.id = id; $('ms-jobs').prepend(li); }
  li.dataset.state = job.state;
  li.replaceChildren(el('span', `${job.name} · ${job.contractor}: ${job.state} `));
  if (job.state === 'done') {
    const show = el('button', 'show', 'show');
    show.addEventListener('click', () => showResult(job.id, job.mission).catch(fail));
    li.append(show);
  } else if (job.state === 'queued' || job.state === 'running') {
    const cancel = el('button', 'cancel', 'cancel');
    cancel.addEventListener('click', () => api.cancelJob(job.id).catch(fail));
    li.append(cancel);
  } else if (job.error) li.title = job.error;
  return li;
}

async function refreshJobs() {
  const jobs = savedJobs();
  const kept = [];
  for (const j of jobs) {
    try {
      const now = await api.getJob(j.id);
      kept.push({ ...j, state: now.state, error: now.error });
    } catch (_) { $(`job-${j.id}`)?.remove(); /* deleted, or another service */ }
  }
  saveJobs(kept);
  kept.slice().reverse().forEach(jobItem);
}

/** Queues a job on a stored mission with the chosen contractor and limits, follows it and shows its result. */
async function runJob(missionId, name) {
  const summary = $('rv-summary');
  const contractor = $('ms-mode').value;
  try {
    const job = await api.submitJob({ mission: missionId, contractor, max_rounds: Number($('ms-rounds').value), time_limit_s: Number($('ms-limit').value) });
    const entry = { id: job.id, mission: missionId, name, contractor, state: job.state };
    rememberJob(entry);
    jobItem(entry);
    currentJob = job.id;
    $('ms-cancel').disabled = false;
    $('ms-progress').value = 0;
    summary.dataset.state = 'queued';
    const end = await api.followJob(job.id, (j) => {
      $('ms-progress').value = j.progress.fraction;
      const d = j.progress.max_trajectory_diameter;
      $('ms-state').textContent = `${name}, ${contractor}: ${j.state} — round ${j.progress.round}, max diameter ${d == null ? '∞' : `${Number(d).toFixed(3)} m`}`;
      jobItem({ ...entry, state: j.state, error: j.error });
      summary.dataset.state = j.state;
    });
    if (currentJob === job.id) $('ms-cancel').disabled = true;
    if (!end) return;
    Object.assign(entry, { state: end.state, error: end.error });
    rememberJob(entry);
    jobItem(entry);
    if (end.state === 'done') {
      const result = await showResult(job.id, missionId);
      $('ms-progress').value = 1;
      $('ms-state').textContent = `${name}, ${contractor}: done — ${result.status}, ${result.metrics.rounds} rounds, max diameter ${Number(result.metrics.max_trajectory_diameter).toFixed(3)} m, ${Number(result.metrics.elapsed_ms).toFixed(1)} ms`;
    } else {
      $('ms-state').textContent = `${name}, ${contractor}: ${end.state}${end.error ? ` — ${end.error}` : ''}`;
      summary.dataset.state = end.state;
    }
  } catch (e) {
    fail(e);
    summary.dataset.state = 'error';
  }
}

$('ms-submit').addEventListener('click', async () => {
  $('ms-submit').disabled = true;
  try {
    const m = await api.uploadMission(pendingFile);
    refreshLists();
    await runJob(m.id, m.name);
  } catch (e) {
    fail(e);
    $('rv-summary').dataset.state = 'error';
  } finally { $('ms-submit').disabled = !pendingFile; }
});
$('ms-cancel').addEventListener('click', () => { if (currentJob) api.cancelJob(currentJob).catch(fail); });

/** Shows a finished job's result in the left panel; the one shown before moves to the right. */
async function showResult(jobId, missionId) {
  const [result, mission] = await Promise.all([api.getResult(jobId), api.getMission(missionId)]);
  const i = shown.findIndex((s) => s.jobId === jobId);
  if (i >= 0) shown.splice(i, 1);
  shown.unshift({ result, mission, jobId });
  shown.length = Math.min(shown.length, 2);
  for (const [fmt, id] of [['json', 'rv-json'], ['csv', 'rv-csv'], ['svg', 'rv-svg']]) $(id).href = api.resultUrl(jobId, fmt);
  const area = hull(shown.flatMap((s) => s.result.trajectory.map(rect)));
  shown.forEach((s, k) => { s.view = new View($(`rv-${k}`)); s.view.fit(area); });
  $('rv-time').max = String(Math.max(...shown.map((s) => s.result.trajectory.length)) - 1);
  $('rv-time').value = $('rv-time').max;
  redrawResults();
  Object.assign($('rv-summary').dataset, {
    trajectory: result.trajectory.length, detections: result.detections.length, landmarks: result.landmarks.length,
    diameter: result.metrics.max_trajectory_diameter, truthInside: String(result.score ? result.score.truth_inside : ''), state: 'drawn',
    shown: shown.length, diameters: shown.map((s) => s.result.metrics.max_trajectory_diameter).join(','),
    contractors: shown.map((s) => s.result.options.contractor).join(','),
  });
  $('rv-summary').textContent = `${result.mission}: ${result.status}, ${result.trajectory.length} positions, ${result.detections.length} detections, ${result.landmarks.length} landmarks, max diameter ${result.metrics.max_trajectory_diameter}`;
  return result;
}
/** Draws the shown results; `moving` (pan, zoom) lets the shapes of the previous view be moved instead of redrawn. */
function redrawResults(moving = false) {
  const t = Number($('rv-time').value);
  const layers = rvLayers();
  shown.forEach((s, k) => {
    s.drawn = drawResult($(`rv-${k}`), s.view, s.result, s.mission, t, layers, moving === true);
    $(`rv-cap-${k}`).textContent = `${s.result.mission} — ${s.result.options.contractor} — max diameter ${Number(s.result.metrics.max_trajectory_diameter).toFixed(2)}`;
  });
  if (shown.length === 1) {
    const c = $('rv-1'); const ctx = c.getContext('2d');
    ctx.clearRect(0, 0, c.width, c.height);
    ctx.fillStyle = '#777'; ctx.font = '14px system-ui, sans-serif'; ctx.textAlign = 'center';
    ctx.fillText('To compare, run another job:', c.width / 2, c.height / 2 - 10);
    ctx.fillText('choose a contractor (none for the basic', c.width / 2, c.height / 2 + 12);
    ctx.fillText('model) and press run next to the mission.', c.width / 2, c.height / 2 + 32);
    $('rv-cap-1').textContent = '';
  }
}
const requestResults = scheduler(redrawResults);
$('rv-time').addEventListener('input', () => requestResults(false));
const rvLayers = legend('rv-legend', () => redrawResults());
[0, 1].forEach((k) => {
  const c = $(`rv-${k}`);
  let drag = null;
  c.addEventListener('pointerdown', (ev) => { drag = [ev.clientX, ev.clientY]; c.setPointerCapture(ev.pointerId); });
  c.addEventListener('pointerup', () => { drag = null; });
  c.addEventListener('pointermove', (ev) => {
    const s = shown[k];
    if (!s) return;
    if (drag) { s.view.pan(ev.clientX - drag[0], ev.clientY - drag[1]); drag = [ev.clientX, ev.clientY]; requestResults(true); return; }
    const r = c.getBoundingClientRect();
    const x = s.view.wx((ev.clientX - r.left) * c.width / r.width), y = s.view.wy((ev.clientY - r.top) * c.height / r.height);
    const found = (s.drawn || []).find(([, b]) => x >= b.x0 && x <= b.x1 && y >= b.y0 && y <= b.y1);
    const tip = $('rv-tip');
    if (found) {
      const [i, b] = found;
      tip.hidden = false; tip.style.left = `${ev.clientX + 12}px`; tip.style.top = `${ev.clientY + 12}px`;
      tip.textContent = `step ${i}: x [${b.x0.toFixed(3)}, ${b.x1.toFixed(3)}] y [${b.y0.toFixed(3)}, ${b.y1.toFixed(3)}]`;
    } else tip.hidden = true;
  });
  c.addEventListener('wheel', (ev) => { ev.preventDefault(); const s = shown[k]; if (!s) return; const r = c.getBoundingClientRect(); s.view.zoom(ev.deltaY < 0 ? 1.1 : 1 / 1.1, (ev.clientX - r.left) * c.width / r.width, (ev.clientY - r.top) * c.height / r.height); requestResults(true); });
});

// ---- start ------------------------------------------------------------
init().then(() => {
  nv = new Nvector();
  window.nvectorHandle = nv; // for the browser tests and the console
  window.nvectorPage = { shown, redrawResults, sl }; // the views, for the browser tests' timings
  $('wasm-status').textContent = 'WASM ready';
  $('wasm-status').dataset.ready = 'true';
  loadPreset(new URLSearchParams(location.search).get('preset') || 'fig8');
  const demo = new URLSearchParams(location.search).get('demo');
  if (demo === '1') slamDemo();
  else if (demo === 'range-only') slamPreset(true);
}).catch((e) => { $('wasm-status').textContent = `WASM failed: ${e}`; });
