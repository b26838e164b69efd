// The SLAM demo: a mission simulated and run twice in WASM (offline), the
// basic model beside atmost_nvector, each panel fitted to its own result.
import { $, canvasPoint, scheduler } from './dom.js';
import { View, areaOf, drawResult, layerToggles } from './draw.js';
import { loadSlam } from './wasm.js';

let nv = null;
/** The last run: {mission, shown: [{id, result, view}]}, redrawn on legend changes (and read by the browser tests). */
export const sl = { shown: [], mission: null };
let layers = null;
let request = null;

function redraw(moving = false) {
  const l = layers();
  sl.shown.forEach((s) => drawResult($(s.id), s.view, s.result, sl.mission, undefined, l, moving === true));
}

/** Steps of the woods preset: small enough for the browser (core's woods generator, core/src/slam/woods.rs). */
const WOODS_STEPS = 400;

/**
 * Simulates with the controls' options (`woods`: the woods scenario, an
 * odometry2d robot among identical landmarks, at the controls' seed), runs
 * basic and nvector, draws both and writes the summary.
 */
export function slamDemo(woods = false) {
  if (!nv) {
    // The SLAM and figures modules are fetched the first time (wasm.js).
    $('sl-summary').textContent = 'loading the SLAM WASM module…';
    loadSlam().then((h) => { nv = h; slamDemo(woods); }, (e) => {
      $('sl-summary').textContent = `SLAM WASM failed: ${e}`;
      $('sl-summary').dataset.error = String(e);
    });
    return;
  }
  const mode = $('sl-mode').value;
  const seed = Number($('sl-seed').value) | 0;
  const opts = woods === true ? { scenario: 'woods', seed, steps: WOODS_STEPS } : {
    scenario: 'paper', seed, steps: Number($('sl-steps').value), noise: Number($('sl-noise').value),
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
  sl.mission = mission;
  sl.shown = [['sl-basic', basic], ['sl-nv', withNv]].map(([id, result]) => {
    const view = new View($(id));
    view.fit(areaOf(result, mission));
    return { id, result, view };
  });
  redraw();
  const groups = withNv.matching ? withNv.matching.length : 0;
  const n = mission.landmark_count;
  $('sl-basic-cap').textContent = `basic model: max diameter ${Number(basic.metrics.max_trajectory_diameter).toFixed(2)} m`;
  $('sl-nv-cap').textContent = `with atmost_nvector (${mode}): max diameter ${Number(withNv.metrics.max_trajectory_diameter).toFixed(2)} m, ${groups} proved groups of at most ${n} landmarks`;
  const kind = opts.scenario === 'woods' ? `woods (odometry2d, ${n} identical landmarks, scans, max heading width ${Number(withNv.metrics.max_heading_width).toFixed(2)} rad)` : `${opts.layout}${opts.range_only ? ', range only' : ', range + bearing'}`;
  Object.assign($('sl-summary').dataset, {
    basicDiameter: basic.metrics.max_trajectory_diameter, nvectorDiameter: withNv.metrics.max_trajectory_diameter,
    recall: withNv.score.matching_recall, errors: withNv.score.matching_errors, ms: (t2 - t1).toFixed(1),
    truthInside: String(basic.score.truth_inside && withNv.score.truth_inside), contractor: withNv.options.contractor,
    rangeOnly: String(!!opts.range_only), layout: opts.layout || '', detections: mission.detections.length, groups, error: '',
    scenario: opts.scenario, model: mission.model, maxHeadingWidth: withNv.metrics.max_heading_width ?? '',
  });
  $('sl-summary').textContent = `${kind}: detections ${mission.detections.length}; basic ${(t1 - t0).toFixed(1)} ms, ${mode} ${(t2 - t1).toFixed(1)} ms; ratio ${(basic.metrics.max_trajectory_diameter / withNv.metrics.max_trajectory_diameter).toFixed(1)}x; ${groups} proved groups of at most ${n} landmarks; recall ${withNv.score.matching_recall.toFixed(2)}; truth inside ${basic.score.truth_inside && withNv.score.truth_inside}; errors ${withNv.score.matching_errors}`;
}

/** The demo's presets: range + bearing against `best`, range only (P'') against `shapes`. */
export function slamPreset(rangeOnly) {
  $('sl-range-only').checked = rangeOnly;
  $('sl-mode').value = rangeOnly ? 'shapes' : 'best';
  slamDemo();
}

/** The woods preset: the woods scenario (odometry2d), basic against projection (best takes tens of seconds there). */
export function slamWoods() {
  $('sl-mode').value = 'projection';
  slamDemo(true);
}

/** Wires the demo's controls and views. */
export function initSlam() {
  ['steps', 'noise', 'landmarks'].forEach((k) => $(`sl-${k}`).addEventListener('input', () => { $(`sl-${k}-v`).textContent = $(`sl-${k}`).value; }));
  layers = layerToggles($('sl-legend'), () => redraw());
  request = scheduler(redraw);
  // Both views pan and zoom together (drag, wheel), each at its own scale.
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
  $('sl-preset-woods').addEventListener('click', slamWoods);
  $('sl-preset-bearing').addEventListener('click', () => slamPreset(false));
  $('sl-preset-range').addEventListener('click', () => slamPreset(true));
}
