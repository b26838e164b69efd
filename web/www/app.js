// The page's entry: the tabs, the WASM handle, and the features, each in
// its own module (playground.js, slam.js, missions.js; radar.js with its
// own wasm, loaded when its tab opens) drawing
// through the one drawing module (draw.js). The page's first wasm (pkg/)
// is the playground's; the figures, solver and simulator modules (wasm.js) are fetched
// when the SLAM demo or the missions tab opens.
import init, { Nvector } from './pkg/nvector_web.js';
import { $ } from './dom.js';
import { initPlayground, loadPreset, playgroundReady } from './playground.js';
import { initSlam, prepareSlam, sl, slamDemo, slamPreset, slamWoods } from './slam.js';
import { initMissions, redrawResults, refreshLists, shown } from './missions.js';
import { handles, loadFigures, loadSlam } from './wasm.js';

// The radar demo and its wasm module load when its tab first opens.
let radarModule = null;
function openRadar() {
  if (!radarModule) {
    radarModule = import('./radar.js').then((m) => { m.initRadar(); window.nvectorRadar = m.radar; return m.radarDemo(); });
  }
}

document.querySelectorAll('nav button').forEach((b) => b.addEventListener('click', () => {
  document.querySelectorAll('nav button').forEach((x) => x.classList.toggle('active', x === b));
  document.querySelectorAll('.tab').forEach((t) => t.classList.toggle('active', t.id === b.dataset.tab));
  if (b.dataset.tab === 'missions') refreshLists();
  if (b.dataset.tab === 'slam') prepareSlam();
  if (b.dataset.tab === 'missions') loadFigures().catch(() => {});
  if (b.dataset.tab === 'radar') openRadar();
}));

initPlayground();
initSlam();
initMissions();

const params = new URLSearchParams(location.search);
const initialTab = params.get('tab');
if (initialTab) document.querySelector(`nav button[data-tab="${initialTab}"]`)?.click();

init().then(() => {
  const nv = new Nvector();
  playgroundReady(nv);
  // Every method of the three modules, for the browser tests and the
  // console (the figures' and SLAM ones once their module has loaded:
  // `await loadSlam()`).
  const loaded = (key) => {
    if (!handles[key]) throw new Error(`the ${key} WASM module is not loaded yet (open the SLAM demo)`);
    return handles[key];
  };
  window.nvectorHandle = {
    contract: (r) => nv.contract(r),
    modes: () => nv.modes(),
    simulate: (o) => loaded('sim').simulate(o),
    run: (m, c, p) => loaded('slam').run(loaded('sim').readMission(m), c, p),
    outlines: (s) => loaded('figures').outlines(s),
    boundaries: (r) => loaded('figures').boundaries(r),
  };
  window.loadSlam = loadSlam;
  window.nvectorPage = { shown, redrawResults, sl }; // the views, for the browser tests' timings
  $('wasm-status').textContent = 'WASM ready';
  $('wasm-status').dataset.ready = 'true';
  loadPreset(params.get('preset') || 'fig8');
  const demo = params.get('demo');
  if (demo === '1') slamDemo();
  else if (demo === 'range-only') slamPreset(true);
  else if (demo === 'woods') slamWoods();
}).catch((e) => { $('wasm-status').textContent = `WASM failed: ${e}`; });
