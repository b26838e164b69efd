// The page's modules fetched on demand (scripts/web.sh builds them from
// the nvector-web crate, one cargo feature each): the figures module
// (pkg-figures/: the outlines and region boundaries draw.js draws),
// fetched the first time the SLAM demo or the missions tab draws; the SLAM
// module (pkg-slam/: the solver and the simulators), fetched the first
// time the SLAM demo runs. The module fetched with the page (pkg/, app.js)
// is the playground's atmost_nvector alone.
import { useCore } from './draw.js';

/** The loaded handles, null before their module has loaded. */
export const handles = { figures: null, slam: null };
const loading = { figures: null, slam: null };

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

/** The SLAM module's handle (`simulate`, `run`), with the figures module loaded too. */
export function loadSlam() {
  return Promise.all([load('slam', './pkg-slam/nvector_web_slam.js'), loadFigures()]).then(([h]) => h);
}
