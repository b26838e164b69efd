// The SLAM demo's solver, off the page's thread (a module worker, started
// by slam.js): the simulators' module (pkg-sim: `simulate`, and
// `readMission`, which validates a mission and gives the binary form the
// solver reads) and the solver's (pkg-slam: `run`), the same two modules
// the page would otherwise load (scripts/web.sh builds them). The page
// stays responsive while a mission is solved, and a cancel is the page
// terminating this worker (the solver checks no flag the page could set
// while it runs: wasm without shared memory).
//
// Messages in: {id, options, contractors}: simulate with `options` (core's
// simulation request), then run the mission once per contractor, in order.
// Messages out, each with the job's id: {progress: {contractor, index,
// round, diameter, fraction}} after a round (at most one every 50 ms), then
// {mission, results, ms, modules} (the mission's JSON text, each result's
// JSON text, the milliseconds of each run, the module files this worker
// fetched), or {error}.
import initSim, { Nvector as Sim } from './pkg-sim/nvector_web_sim.js';
import initSolver, { Nvector as Solver } from './pkg-slam/nvector_web_slam.js';

const ready = Promise.all([initSim(), initSolver()]).then(() => ({ sim: new Sim(), solver: new Solver() }));

self.onmessage = async (ev) => {
  const { id, options, contractors } = ev.data;
  let h;
  try {
    h = await ready;
  } catch (e) {
    self.postMessage({ id, error: `SLAM WASM failed: ${e.message || e}` });
    return;
  }
  try {
    const mission = h.sim.simulate(JSON.stringify(options));
    const binary = h.sim.readMission(mission);
    const results = [], ms = [];
    for (const [index, contractor] of contractors.entries()) {
      let last = -Infinity;
      const progress = (round, diameter, fraction) => {
        const now = performance.now();
        if (now - last < 50) return;
        last = now;
        self.postMessage({ id, progress: { contractor, index, round, diameter, fraction } });
      };
      const t = performance.now();
      results.push(h.solver.run(binary, contractor, progress));
      ms.push(performance.now() - t);
    }
    const modules = performance.getEntriesByType('resource').map((e) => e.name);
    self.postMessage({ id, mission, results, ms, modules });
  } catch (e) {
    self.postMessage({ id, error: String(e.message || e) });
  }
};
