// The missions tab: missions uploaded to the service, jobs run and
// followed (Server-Sent Events), and the last two results drawn side by
// side, each panel fitted to its own result and drawn from core's
// description of the figure (figure.js: the CLI's picture).
import * as api from './api.js';
import { $, el, scheduler } from './dom.js';
import { View, drawMessage, layerToggles } from './draw.js';
import { drawFigure, figureArea, figureOf } from './figure.js';
import { handles, loadFigures } from './wasm.js';

// Jobs submitted from this browser are remembered in localStorage (the API
// lists missions, not jobs), so a reload still lists them and their results.
let pendingFile = null;
let currentJob = null; // the job the cancel button stops
/** Up to two {result, mission, jobId, view, drawn}, the newest first (left). */
export const shown = [];
const JOBS_KEY = 'nvector.jobs';
let layers = null;
let request = null;
let uploading = false;
/**
 * Shows an error as one: in the error colour beside the controls (and in
 * the list item `near`, when the action came from one), the progress bar
 * cleared.
 */
function fail(e, near) {
  const msg = `error: ${e && e.message ? e.message : e}`;
  const state = $('ms-state');
  state.textContent = msg;
  state.classList.add('error');
  $('ms-progress').value = 0;
  $('ms-progress').classList.add('error');
  if (near) {
    near.querySelector('.error')?.remove();
    near.append(el('span', ` ${msg}`, 'error'));
  }
}
/** Plain news in the state line (an earlier error's colour removed). */
function tell(text) {
  const state = $('ms-state');
  state.textContent = text;
  state.classList.remove('error');
  $('ms-progress').classList.remove('error');
}
/** A size in bytes, for reading. */
function size(n) {
  if (!Number.isFinite(n)) return '?';
  if (n < 1024) return `${n} B`;
  return n < 1024 * 1024 ? `${(n / 1024).toFixed(1)} kB` : `${(n / 1024 / 1024).toFixed(1)} MB`;
}
/** A time in ms since the epoch as local "YYYY-MM-DD HH:MM". */
function when(ms) {
  const d = new Date(ms), p = (x) => String(x).padStart(2, '0');
  return Number.isFinite(ms) ? `${d.getFullYear()}-${p(d.getMonth() + 1)}-${p(d.getDate())} ${p(d.getHours())}:${p(d.getMinutes())}` : '?';
}
function savedJobs() { try { return JSON.parse(localStorage.getItem(JOBS_KEY) || '[]'); } catch (_) { return []; } }
function saveJobs(jobs) { try { localStorage.setItem(JOBS_KEY, JSON.stringify(jobs.slice(0, 50))); } catch (_) { /* private mode */ } }
function rememberJob(job) { saveJobs([job, ...savedJobs().filter((j) => j.id !== job.id)]); }

function setFile(f) { pendingFile = f; $('ms-submit').disabled = !f || uploading; tell(f ? `ready: ${f.name || 'mission'}` : ''); }

/** Lists the service's missions and this browser's jobs. */
export async function refreshLists() {
  try {
    const ms = await api.listMissions();
    const ul = $('ms-missions');
    ul.replaceChildren();
    ms.missions.forEach((m) => {
      const li = el('li'); li.dataset.id = m.id;
      // Id, date and size: two uploads of one file are told apart.
      const id = el('code', m.id.slice(0, 10)); id.title = m.id;
      li.append(el('span', `${m.name} `), id, el('span', ` · ${when(m.created_ms)} · ${size(m.bytes)} · ${m.steps} steps, ${m.detections} detections `));
      const run = el('button', 'run', 'run'); run.title = 'run a job on this mission with the contractor and limits above';
      run.addEventListener('click', () => runJob(m.id, m.name, li));
      const del = el('button', 'delete', 'delete'); del.title = 'delete this mission and its jobs';
      del.addEventListener('click', async () => {
        if (!confirm(`Delete mission ${m.name} and its jobs?`)) return;
        try { await api.deleteMission(m.id); saveJobs(savedJobs().filter((j) => j.mission !== m.id)); } catch (e) { fail(e, li); return; }
        refreshLists();
      });
      li.append(run, ' ', del);
      ul.append(li);
    });
    if (!ms.missions.length) ul.append(el('li', 'no mission yet: upload one above', 'hint'));
  } catch (e) { $('ms-missions').replaceChildren(el('li', `service unavailable: ${e.message}`, 'error')); }
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
    show.addEventListener('click', () => showResult(job.id, job.mission).catch((e) => fail(e, li)));
    li.append(show);
  } else if (job.state === 'queued' || job.state === 'running') {
    const cancel = el('button', 'cancel', 'cancel');
    cancel.addEventListener('click', () => api.cancelJob(job.id).catch((e) => fail(e, li)));
    li.append(cancel);
  } else if (job.error) { li.title = job.error; li.append(el('span', job.error, 'error')); }
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
async function runJob(missionId, name, near) {
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
    tell(`${name}, ${contractor}: ${job.state}`);
    summary.dataset.state = 'queued';
    const end = await api.followJob(job.id, (j) => {
      $('ms-progress').value = j.progress.fraction;
      const d = j.progress.max_trajectory_diameter;
      tell(`${name}, ${contractor}: ${j.state} — ${Math.floor(100 * j.progress.fraction)} % of the estimated work, round ${j.progress.round}, max diameter ${d == null ? '∞' : `${Number(d).toFixed(3)} m`}`);
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
      tell(`${name}, ${contractor}: done — ${result.status}, ${result.metrics.rounds} rounds, max diameter ${Number(result.metrics.max_trajectory_diameter).toFixed(3)} m, ${Number(result.metrics.elapsed_ms).toFixed(1)} ms`);
    } else if (end.state === 'cancelled') {
      tell(`${name}, ${contractor}: cancelled`);
      $('ms-progress').value = 0;
      summary.dataset.state = end.state;
    } else {
      fail(`${name}, ${contractor}: ${end.state}${end.error ? ` — ${end.error}` : ''}`, near);
      summary.dataset.state = end.state;
    }
  } catch (e) {
    fail(e, near);
    summary.dataset.state = 'error';
  }
}

/** "k proved groups of at most n landmarks" (the matching's groups, not landmarks). */
export function groupsText(result, mission) {
  const k = Array.isArray(result.matching) ? result.matching.length : 0;
  const n = mission && mission.landmark_count;
  const g = `${k} proved group${k === 1 ? '' : 's'}`;
  const text = n === undefined || n === null ? `${g} (number of landmarks not given)` : `${g} of at most ${n} landmark${n === 1 ? '' : 's'}`;
  return text + outliersText(result, mission);
}

/** With max_outliers: the detections proved false, and the drops nothing accounts for (then no group can be proved). */
function outliersText(result, mission) {
  const m = result.metrics || {};
  if (m.open_outliers === undefined) return '';
  const q = mission && mission.max_outliers;
  const open = m.open_outliers > 0 ? `, ${m.open_outliers} not accounted for, so no group can be proved` : '';
  return ` (max_outliers ${q}: ${m.false_detections} proved false${open})`;
}

/** A number of metres, rounded for reading. */
const metres = (d) => (Number.isFinite(Number(d)) ? `${Number(d).toFixed(Number(d) >= 100 ? 1 : 2)} m` : '∞');

/** Shows a finished job's result in the left panel; the one shown before moves to the right. */
async function showResult(jobId, missionId) {
  // The outlines come from the figures module (wasm.js), fetched with the first result.
  const [result, mission] = await Promise.all([api.getResult(jobId), api.getMission(missionId), loadFigures()]);
  const i = shown.findIndex((s) => s.jobId === jobId);
  if (i >= 0) shown.splice(i, 1);
  shown.unshift({ result, mission, jobId });
  shown.length = Math.min(shown.length, 2);
  for (const [fmt, id] of [['json', 'rv-json'], ['csv', 'rv-csv'], ['svg', 'rv-svg']]) $(id).href = api.resultUrl(jobId, fmt);
  // Each panel fitted to its own result's figure (its view: what core's
  // description draws): a 10 m result beside a 600 m one stays readable.
  const core = handles.figures;
  shown.forEach((s, k) => { s.view = new View($(`rv-${k}`)); s.view.fit(figureArea(figureOf(core, s, s.result.trajectory.length - 1))); });
  // The detection shapes are the page's own (the CLI's figure has none):
  // shown on request, from the legend's boxes.
  layers.set('shapes', false);
  $('rv-time').max = String(Math.max(...shown.map((s) => s.result.trajectory.length)) - 1);
  $('rv-time').value = $('rv-time').max;
  redrawResults();
  Object.assign($('rv-summary').dataset, {
    trajectory: result.trajectory.length, detections: result.detections.length, landmarks: result.landmarks.length,
    groups: (result.matching || []).length, landmarkCount: mission.landmark_count ?? '',
    diameter: result.metrics.max_trajectory_diameter, truthInside: String(result.score ? result.score.truth_inside : ''), state: 'drawn',
    shown: shown.length, diameters: shown.map((s) => s.result.metrics.max_trajectory_diameter).join(','),
    contractors: shown.map((s) => s.result.options.contractor).join(','),
  });
  $('rv-summary').textContent = `${result.mission}: ${result.status}, ${result.trajectory.length} positions, ${result.detections.length} detections, ${groupsText(result, mission)}, max diameter ${metres(result.metrics.max_trajectory_diameter)}`;
  return result;
}

/** Draws the shown results (whole, during a pan or zoom too: a figure is a few thousand rectangles at most). */
export function redrawResults() {
  const t = Number($('rv-time').value);
  const l = layers();
  shown.forEach((s, k) => {
    const last = Math.min(t, s.result.trajectory.length - 1);
    s.drawn = drawFigure(handles.figures, $(`rv-${k}`), s.view, s, last, l);
    const fig = figureOf(handles.figures, s, last);
    $(`rv-cap-${k}`).textContent = `${fig.title} — ${fig.subtitle}`;
  });
  if (shown.length === 1) {
    drawMessage($('rv-1'), ['To compare, run another job:', 'choose a contractor (none for the basic', 'model) and press run next to the mission.']);
    $('rv-cap-1').textContent = '';
  }
}

/** Wires the tab's controls and views. */
export function initMissions() {
  $('ms-file').addEventListener('change', (ev) => setFile(ev.target.files[0] || null));
  const drop = $('drop');
  drop.addEventListener('dragover', (ev) => { ev.preventDefault(); drop.classList.add('over'); });
  drop.addEventListener('dragleave', () => drop.classList.remove('over'));
  drop.addEventListener('drop', (ev) => { ev.preventDefault(); drop.classList.remove('over'); setFile(ev.dataTransfer.files[0] || null); });
  // One upload per chosen file: the button is off while it uploads, and
  // the file is forgotten once stored (run it again from the list).
  $('ms-submit').addEventListener('click', async () => {
    if (uploading || !pendingFile) return;
    uploading = true;
    $('ms-submit').disabled = true;
    const file = pendingFile;
    try {
      tell(`uploading ${file.name || 'mission'}…`);
      $('ms-progress').value = 0;
      const m = await api.uploadMission(file);
      setFile(null);
      $('ms-file').value = '';
      refreshLists();
      uploading = false;
      await runJob(m.id, m.name);
    } catch (e) {
      fail(e);
      $('rv-summary').dataset.state = 'error';
    } finally { uploading = false; $('ms-submit').disabled = !pendingFile; }
  });
  $('ms-cancel').addEventListener('click', () => { if (currentJob) api.cancelJob(currentJob).catch((e) => fail(e)); });
  request = scheduler(redrawResults);
  $('rv-time').addEventListener('input', () => request(false));
  layers = layerToggles($('rv-legend'), () => redrawResults());
  [0, 1].forEach((k) => {
    const c = $(`rv-${k}`);
    let drag = null;
    c.addEventListener('pointerdown', (ev) => { drag = [ev.clientX, ev.clientY]; c.setPointerCapture(ev.pointerId); });
    c.addEventListener('pointerup', () => { drag = null; });
    c.addEventListener('pointermove', (ev) => {
      const s = shown[k];
      if (!s) return;
      if (drag) { s.view.pan(ev.clientX - drag[0], ev.clientY - drag[1]); drag = [ev.clientX, ev.clientY]; request(true); return; }
      const r = c.getBoundingClientRect();
      const x = s.view.wx((ev.clientX - r.left) * c.width / r.width), y = s.view.wy((ev.clientY - r.top) * c.height / r.height);
      const found = (s.drawn || []).find(([, b]) => x >= b.x0 && x <= b.x1 && y >= b.y0 && y <= b.y1);
      const tip = $('rv-tip');
      if (found) {
        const [i, b] = found;
        tip.hidden = false; tip.style.left = `${ev.clientX + 12}px`; tip.style.top = `${ev.clientY + 12}px`;
        tip.textContent = `step ${i}: x [${b.x0.toFixed(3)}, ${b.x1.toFixed(3)}] m, y [${b.y0.toFixed(3)}, ${b.y1.toFixed(3)}] m`;
      } else tip.hidden = true;
    });
    c.addEventListener('wheel', (ev) => { ev.preventDefault(); const s = shown[k]; if (!s) return; const r = c.getBoundingClientRect(); s.view.zoom(ev.deltaY < 0 ? 1.1 : 1 / 1.1, (ev.clientX - r.left) * c.width / r.width, (ev.clientY - r.top) * c.height / r.height); request(true); });
  });
}
