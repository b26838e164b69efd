// The SLAM demo: a mission simulated and run twice in WASM (offline), the
// basic model beside atmost_nvector, both panels at one scale. The solving
// runs in a Web Worker (slam-worker.js): the page stays responsive, shows
// that it is busy, and a Cancel ends the solve (the worker terminated; the
// next run starts a new one).
import { $, canvasPoint, scheduler } from './dom.js';
import { View, areaOf, drawResult, hull, layerToggles, rect } from './draw.js';
import { loadFigures } from './wasm.js';

/**
 * The last run: {mission, shown: [{id, result, view}], options, worker}
 * (options: what was run; worker: the module files the worker fetched),
 * redrawn on legend changes (and read by the browser tests).
 */
export const sl = { shown: [], mission: null, options: null, worker: [] };
let layers = null;
let request = null;

function redraw(moving = false) {
  const l = layers();
  sl.shown.forEach((s) => drawResult($(s.id), s.view, s.result, sl.mission, undefined, l, moving === true));
}

/**
 * The presets, each setting every control to what it runs. Range +
 * bearing (the paper's experiment) against `best`; range only (the
 * paper's P'') against `shapes`; the woods scenario (an odometry2d robot
 * among 17 identical landmarks, with scans; 400 steps, small enough for
 * the browser, core/src/slam/simulate/odometry_scenario.rs) against `best`
 * too (seconds in the worker: the page stays usable, Cancel stops it).
 * Noise, layout and range only are the paper
 * scenario's: the woods preset sets them to their defaults and they are
 * disabled while the scenario is woods.
 */
export const PRESETS = {
  bearing: { scenario: 'paper', steps: 6000, noise: 1, landmarks: 4, layout: 'line', range_only: false, seed: 1, contractor: 'best' },
  range: { scenario: 'paper', steps: 6000, noise: 1, landmarks: 4, layout: 'line', range_only: true, seed: 1, contractor: 'shapes' },
  woods: { scenario: 'woods', steps: 400, noise: 1, landmarks: 17, layout: 'line', range_only: false, seed: 1, contractor: 'best' },
};

/** The controls' values, as a preset names them. */
export function controls() {
  return {
    scenario: $('sl-scenario').value, steps: Number($('sl-steps').value), noise: Number($('sl-noise').value),
    landmarks: Number($('sl-landmarks').value), layout: $('sl-layout').value, range_only: $('sl-range-only').checked,
    seed: Number($('sl-seed').value) | 0, contractor: $('sl-mode').value,
  };
}

/** Sets every control (and the sliders' read-outs) to a preset's values. */
function setControls(p) {
  $('sl-scenario').value = p.scenario;
  for (const k of ['steps', 'noise', 'landmarks']) {
    $(`sl-${k}`).value = String(p[k]);
    $(`sl-${k}-v`).textContent = $(`sl-${k}`).value;
  }
  $('sl-layout').value = p.layout;
  $('sl-range-only').checked = p.range_only;
  $('sl-seed').value = String(p.seed);
  $('sl-mode').value = p.contractor;
  scenarioChanged();
}

/** The paper scenario's own controls are disabled for the woods scenario. */
function scenarioChanged() {
  const woods = $('sl-scenario').value === 'woods';
  for (const id of ['sl-noise', 'sl-layout', 'sl-range-only']) $(id).disabled = woods;
}

/** Core's simulation request for the controls' options (the woods scenario takes seed, steps and landmarks). */
function simulationRequest(c) {
  if (c.scenario === 'woods') return { scenario: 'woods', seed: c.seed, steps: c.steps, landmarks: c.landmarks };
  return { scenario: 'paper', seed: c.seed, steps: c.steps, noise: c.noise, landmarks: c.landmarks, layout: c.layout, range_only: c.range_only };
}

/**
 * One world rectangle for both panels, holding everything either draws
 * with bounds: both results' trajectory boxes, detection boxes, proved
 * groups' boxes and landmark regions, the truth path and the true
 * landmarks. Both panels then have the same world-to-screen transform.
 */
export function sharedArea(results, mission) {
  const rects = [];
  for (const r of results) {
    rects.push(areaOf(r, mission));
    for (const key of ['detections', 'landmarks']) if (Array.isArray(r[key])) for (const b of r[key]) rects.push(rect(b));
    for (const p of Array.isArray(r.landmark_regions) ? r.landmark_regions : []) if (Array.isArray(p)) for (const b of p) rects.push(rect(b));
  }
  const landmarks = mission && mission.truth && Array.isArray(mission.truth.landmarks) ? mission.truth.landmarks : [];
  for (const l of landmarks) if (Array.isArray(l)) rects.push({ x0: l[0], x1: l[0], y0: l[1], y1: l[1] });
  return hull(rects.filter((r) => r && [r.x0, r.x1, r.y0, r.y1].every(Number.isFinite)));
}

// ---- the worker and the busy state ---------------------------------------

let worker = null;
/** The running job: {id, options, startedAt} or null. */
let job = null;
let jobs = 0;

/** The worker, started once (again after a cancel); it loads its two modules at once. */
function solver() {
  if (!worker) {
    worker = new Worker(new URL('./slam-worker.js', import.meta.url), { type: 'module' });
    worker.onmessage = (ev) => onMessage(ev.data);
    worker.onerror = (ev) => {
      ev.preventDefault();
      failed(`SLAM worker failed: ${ev.message || 'its modules did not load'}`);
      stopWorker();
    };
  }
  return worker;
}

function stopWorker() {
  if (worker) worker.terminate();
  worker = null;
}

/** Starts the worker and the figures module (the SLAM tab opened): the first run does not wait for them. */
export function prepareSlam() {
  solver();
  loadFigures().catch(() => {});
}

/** The busy state: the page says it is solving, Cancel is offered, the runs wait. */
function setBusy(on) {
  const tab = $('slam');
  tab.dataset.busy = String(on);
  tab.setAttribute('aria-busy', String(on));
  $('sl-cancel').disabled = !on;
  for (const b of tab.querySelectorAll('button.sl-runs')) b.disabled = on;
  $('sl-progress').hidden = !on;
  if (on) $('sl-progress').removeAttribute('value');
}

function failed(message) {
  job = null;
  setBusy(false);
  const s = $('sl-summary');
  s.textContent = `error: ${message}`;
  s.dataset.error = message;
  s.dataset.state = 'error';
}

/** Cancels the running solve: the worker is terminated, the page usable at once. */
export function slamCancel() {
  if (!job) return;
  stopWorker();
  job = null;
  setBusy(false);
  const s = $('sl-summary');
  s.textContent = 'cancelled: the solve was stopped (the panels keep the last finished run, if any); run again or choose a preset';
  s.dataset.state = 'cancelled';
}

const CONTRACTOR_NAMES = { none: 'basic model' };

function onMessage(m) {
  if (!job || m.id !== job.id) return;
  if (m.error !== undefined) { failed(m.error); return; }
  if (m.progress) {
    const p = m.progress, name = CONTRACTOR_NAMES[p.contractor] || p.contractor;
    // Two runs: the first half of the bar is the basic model's.
    $('sl-progress').value = Math.min(1, (p.index + Math.min(Math.max(p.fraction, 0), 1)) / 2);
    $('sl-summary').textContent = `solving in a worker (${name}, run ${p.index + 1} of 2): round ${p.round}, max diameter ${Number(p.diameter).toFixed(2)} m…`;
    $('sl-summary').dataset.state = 'solving';
    return;
  }
  const done = job;
  job = null;
  let mission, basic, withNv;
  try {
    mission = JSON.parse(m.mission);
    [basic, withNv] = m.results.map((r) => JSON.parse(r));
  } catch (e) {
    failed(String(e.message || e));
    return;
  }
  // The outlines come from the figures module (prepareSlam started it).
  loadFigures().then(() => {
    setBusy(false);
    shown(done.options, mission, basic, withNv, m.ms, m.modules);
  }, (e) => failed(`figures WASM failed: ${e}`));
}

/**
 * Simulates with the controls' options and runs basic and the chosen
 * contractor in the worker; the results are drawn when it answers. A run
 * while one is going is ignored (the buttons are disabled then).
 */
export function slamDemo() {
  if (job) return;
  const options = controls();
  job = { id: ++jobs, options };
  const s = $('sl-summary');
  for (const k of Object.keys(s.dataset)) s.dataset[k] = '';
  s.dataset.state = 'solving';
  s.textContent = 'solving in a worker: simulating the mission…';
  setBusy(true);
  solver().postMessage({ id: job.id, options: simulationRequest(options), contractors: ['none', options.contractor] });
}

/** Draws a finished run in both panels (one transform) and writes the summary. */
function shown(options, mission, basic, withNv, ms, modules) {
  const mode = options.contractor;
  sl.mission = mission;
  sl.options = options;
  sl.worker = modules || [];
  const area = sharedArea([basic, withNv], mission);
  sl.shown = [['sl-basic', basic], ['sl-nv', withNv]].map(([id, result]) => {
    const view = new View($(id));
    view.fit(area);
    return { id, result, view };
  });
  redraw();
  const groups = withNv.matching ? withNv.matching.length : 0;
  const n = mission.landmark_count;
  $('sl-basic-cap').textContent = `basic model: max diameter ${Number(basic.metrics.max_trajectory_diameter).toFixed(2)} m`;
  $('sl-nv-cap').textContent = `with atmost_nvector (${mode}): max diameter ${Number(withNv.metrics.max_trajectory_diameter).toFixed(2)} m, ${groups} proved groups of at most ${n} landmarks`;
  const woods = options.scenario === 'woods';
  const kind = woods ? `woods (odometry2d, ${n} identical landmarks, scans, max heading width ${Number(withNv.metrics.max_heading_width).toFixed(2)} rad)` : `${options.layout}${options.range_only ? ', range only' : ', range + bearing'}`;
  Object.assign($('sl-summary').dataset, {
    basicDiameter: basic.metrics.max_trajectory_diameter, nvectorDiameter: withNv.metrics.max_trajectory_diameter,
    recall: withNv.score.matching_recall, errors: withNv.score.matching_errors, ms: ms[1].toFixed(1),
    truthInside: String(basic.score.truth_inside && withNv.score.truth_inside), contractor: withNv.options.contractor,
    rangeOnly: String(!woods && options.range_only), layout: woods ? '' : options.layout, detections: mission.detections.length, groups, error: '',
    scenario: options.scenario, model: mission.model, maxHeadingWidth: withNv.metrics.max_heading_width ?? '', status: withNv.status, state: 'done',
  });
  $('sl-summary').textContent = `${kind}: ${withNv.status}; detections ${mission.detections.length}; basic ${ms[0].toFixed(1)} ms, ${mode} ${ms[1].toFixed(1)} ms (in a worker); ratio ${(basic.metrics.max_trajectory_diameter / withNv.metrics.max_trajectory_diameter).toFixed(1)}x; ${groups} proved groups of at most ${n} landmarks; recall ${withNv.score.matching_recall.toFixed(2)}; truth inside ${basic.score.truth_inside && withNv.score.truth_inside}; errors ${withNv.score.matching_errors}`;
}

/** Sets every control to a preset (`bearing`, `range`, `woods`) and runs it. */
export function slamRunPreset(name) {
  if (job) return;
  setControls(PRESETS[name]);
  slamDemo();
}

/** The range + bearing preset, or the range-only one (`rangeOnly`). */
export function slamPreset(rangeOnly) {
  slamRunPreset(rangeOnly ? 'range' : 'bearing');
}

/** The woods preset. */
export function slamWoods() {
  slamRunPreset('woods');
}

/** Wires the demo's controls and views. */
export function initSlam() {
  ['steps', 'noise', 'landmarks'].forEach((k) => $(`sl-${k}`).addEventListener('input', () => { $(`sl-${k}-v`).textContent = $(`sl-${k}`).value; }));
  $('sl-scenario').addEventListener('change', scenarioChanged);
  scenarioChanged();
  layers = layerToggles($('sl-legend'), () => redraw());
  request = scheduler(redraw);
  // Both views pan and zoom together (drag, wheel): one transform.
  ['sl-basic', 'sl-nv'].forEach((id) => {
    const c = $(id);
    let drag = null;
    c.addEventListener('pointerdown', (ev) => { drag = canvasPoint(c, ev); c.setPointerCapture(ev.pointerId); });
    c.addEventListener('pointerup', () => { drag = null; });
    c.addEventListener('pointermove', (ev) => {
      if (!drag) return;
      const p = canvasPoint(c, ev);
      sl.shown.forEach((s) => s.view.pan(p[0] - drag[0], p[1] - drag[1]));
      drag = p;
      request(true);
    });
    c.addEventListener('wheel', (ev) => {
      if (!sl.shown.length) return;
      ev.preventDefault();
      const [px, py] = canvasPoint(c, ev);
      sl.shown.forEach((s) => s.view.zoom(ev.deltaY < 0 ? 1.1 : 1 / 1.1, px, py));
      request(true);
    });
  });
  $('sl-run').addEventListener('click', () => slamDemo());
  $('sl-cancel').addEventListener('click', slamCancel);
  $('sl-preset-woods').addEventListener('click', slamWoods);
  $('sl-preset-bearing').addEventListener('click', () => slamPreset(false));
  $('sl-preset-range').addEventListener('click', () => slamPreset(true));
}
