// REST helpers for /api/v1 (docs/api.md). Each returns parsed JSON or
// throws an Error whose message is the service's error message and path.

/** @param {Response} r */
async function check(r) {
  if (r.ok) return r.status === 204 ? null : r.json();
  let msg = `${r.status} ${r.statusText}`;
  try {
    const e = (await r.json()).error;
    msg = e.path ? `${e.path}: ${e.message}` : e.message;
  } catch (_) { /* not JSON */ }
  throw new Error(msg);
}

/** Uploads a mission file (multipart, field `file`). @param {File|Blob} file */
export async function uploadMission(file) {
  const form = new FormData();
  form.append('file', file, 'mission.json');
  return check(await fetch('/api/v1/missions', { method: 'POST', body: form }));
}

export async function listMissions() { return check(await fetch('/api/v1/missions?limit=100')); }

/** @param {{mission: string, contractor: string, max_rounds: number, time_limit_s: number}} job */
export async function submitJob(job) {
  return check(await fetch('/api/v1/jobs', {
    method: 'POST', headers: { 'Content-Type': 'application/json' }, body: JSON.stringify(job),
  }));
}

export async function getJob(id) { return check(await fetch(`/api/v1/jobs/${id}`)); }
export async function cancelJob(id) { return check(await fetch(`/api/v1/jobs/${id}`, { method: 'DELETE' })); }
export async function getResult(id) { return check(await fetch(`/api/v1/jobs/${id}/result`)); }
export async function deleteMission(id) { return check(await fetch(`/api/v1/missions/${id}`, { method: 'DELETE' })); }
export async function getMission(id) { return check(await fetch(`/api/v1/missions/${id}`)); }
export function resultUrl(id, format) { return `/api/v1/jobs/${id}/result?format=${format}`; }

/** Follows a job's progress (Server-Sent Events) until it ends. */
export function followJob(id, onProgress) {
  return new Promise((resolve) => {
    const es = new EventSource(`/api/v1/jobs/${id}/events`);
    const handle = (ev, end) => {
      const job = JSON.parse(ev.data);
      onProgress(job);
      if (end) { es.close(); resolve(job); }
    };
    es.addEventListener('progress', (ev) => handle(ev, false));
    es.addEventListener('end', (ev) => handle(ev, true));
    es.onerror = () => { es.close(); getJob(id).then(resolve, () => resolve(null)); };
  });
}
