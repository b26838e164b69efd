// The page's modules fetched on demand (scripts/web.sh builds them from
// the nvector-web crate, one cargo feature each): the figures module
// (pkg-figures/: the outlines and region boundaries draw.js draws),
// fetched the first time the SLAM demo or the missions tab draws. The SLAM
// demo's two modules (pkg-slam/: the solver, `run`; pkg-sim/: the
// simulators, `simulate`, and the mission reader, `readMission`) are
// loaded by the demo's worker (slam-worker.js), off the page's thread;
// `loadSlam` loads them on the page itself, for the console and the
// browser tests (`window.nvectorHandle`). The module fetched with the page
// (pkg/, app.js) is the playground's atmost_nvector alone.
import { useCore } from './draw.js';

/** The loaded handles, null before their module has loaded. */
export const handles = { figures: null, slam: null, sim: null };
const loading = { figures: null, slam: null, sim: null };

/** A module's handle, loaded once (a failed load is tried again at the next call). */
function load(key, url) {
  if (!loading[key]) {
    loading[key] = import(url).then(async (m) => {
      await m.default();
      handles[key] = new m.Nvector();
      return handles[key];
    });
    loading[key].catch(() => { loading[key] = null; });
  }
  return loading[key];
}

/** The figures module's handle, which draw.js then uses for the outlines. */
export function loadFigures() {
  return load('figures', './pkg-figures/nvector_web_figures.js').then((h) => { useCore(h); return h; });
}

/**
 * The SLAM modules on the page's thread (the demo itself runs them in its
 * worker): `simulate` (the simulators' module) and `run`
 * (the solver's), both modules fetched at once, with the figures module
 * loaded too. `run` takes the mission's JSON text: the simulators' module
 * reads and validates it (`readMission`, the errors naming the JSON path)
 * and hands the solver's module its binary form (the solver's module has
 * no JSON reader).
 */
export function loadSlam() {
  return Promise.all([
    load('slam', './pkg-slam/nvector_web_slam.js'),
    load('sim', './pkg-sim/nvector_web_sim.js'),
    loadFigures(),
  ]).then(([solver, sim]) => ({
    simulate: (o) => sim.simulate(o),
    run: (m, c, p) => solver.run(sim.readMission(m), c, p),
  }));
}
