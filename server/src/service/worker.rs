//! The job workers. Each is a dedicated thread of the service (off the
//! async runtime) that owns one worker process (`worker_process`: this
//! binary as `nvector worker`, under the job memory limit) and runs one job
//! at a time in it: it claims the first queued job from storage, sends the
//! mission to its process, stores the progress the process reports, checks
//! for cancellation (DELETE: the process is killed), shutdown and the time
//! limit, then stores the result. A job can therefore never take the
//! service down: when its process dies (abort, out of memory, killed) the
//! worker records the crash, and the job goes back to the queue or, after
//! `--job-attempts` crashes (at once for `memory_limit`, which would come
//! again), fails with an error saying what happened; the worker starts a
//! new process for the next job.
//!
//! Lanes: the general workers take the first job in queue order (short
//! jobs ahead of long ones submitted up to the long-job delay before
//! them), the short lane's workers take only short jobs, so short work is
//! never stuck behind long work. Idle workers wait on a condition
//! variable, woken when a job is queued (and poll storage twice a second,
//! for jobs queued by another process sharing the database).

use super::job_runner::{JobKind, JobOrder};
use super::meters::{self, Meters, ReasonLabel};
use super::store::JobErrorCode;
use super::store::{JobError, JobRow, JobState, Store};
use super::worker_process::{Message, WorkerProcess};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Condvar, Mutex};
use std::time::{Duration, Instant};

/// Milliseconds since the Unix epoch.
pub fn now_ms() -> i64 {
    std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.as_millis() as i64)
}

/// Shared worker state: wake-ups, shutdown, metrics.
pub struct Workers {
    wake: Mutex<u64>,
    cond: Condvar,
    /// Set on shutdown: workers finish nothing new.
    pub stopping: AtomicBool,
    /// The metric families of this process.
    pub meters: Arc<Meters>,
    /// Ids of the jobs whose stored state this process just changed (for
    /// the event streams).
    pub changes: tokio::sync::broadcast::Sender<String>,
}

impl Workers {
    /// New shared state.
    pub fn new() -> Arc<Workers> {
        Arc::new(Workers {
            wake: Mutex::new(0),
            cond: Condvar::new(),
            stopping: AtomicBool::new(false),
            meters: Arc::new(Meters::new()),
            changes: tokio::sync::broadcast::channel(4096).0,
        })
    }

    /// Tells the event streams that a job changed.
    pub fn changed(&self, id: &str) {
        let _ = self.changes.send(id.to_string());
    }

    /// Wakes one idle worker (a job was queued).
    pub fn notify(&self) {
        if let Ok(mut w) = self.wake.lock() {
            *w += 1;
        }
        self.cond.notify_all();
    }

    fn wait(&self) {
        if let Ok(g) = self.wake.lock() {
            let _ = self.cond.wait_timeout(g, Duration::from_millis(500));
        }
    }
}

/// Starts the lease keeper: refreshes the heartbeat of this process's
/// running jobs every quarter lease, and every half lease puts back in the
/// queue the jobs of processes that stopped beating (killed, crashed, cut
/// off), waking the workers when it did.
pub fn start_lease_keeper(
    store: Arc<dyn Store>,
    workers: Arc<Workers>,
    lease: Duration,
) -> std::thread::JoinHandle<()> {
    std::thread::Builder::new()
        .name("nvector-lease".into())
        .spawn(move || {
            let lease_ms = lease.as_millis().max(1) as i64;
            let beat = (lease / 4).max(Duration::from_millis(10));
            let mut last_sweep = Instant::now();
            while !workers.stopping.load(Ordering::SeqCst) {
                if let Err(e) = store.heartbeat(now_ms()) {
                    tracing::warn!("job heartbeat: {e}");
                }
                if last_sweep.elapsed() >= lease / 2 {
                    last_sweep = Instant::now();
                    match store.requeue_stale(now_ms(), lease_ms) {
                        Ok(0) => {}
                        Ok(n) => {
                            tracing::info!("re-queued {n} job(s) of a process that stopped");
                            workers.notify();
                        }
                        Err(e) => tracing::warn!("re-queueing stale jobs: {e}"),
                    }
                }
                let until = Instant::now() + beat;
                while Instant::now() < until && !workers.stopping.load(Ordering::SeqCst) {
                    std::thread::sleep(Duration::from_millis(20));
                }
            }
        })
        .expect("spawn lease thread")
}

/// How the workers of this process run jobs (flags of `nvector serve`).
#[derive(Debug, Clone)]
pub struct PoolConfig {
    /// General workers (any job, in queue order).
    pub workers: usize,
    /// Short-lane workers (short jobs only).
    pub short_lane_workers: usize,
    /// Memory limit of each worker process (bytes; None: none).
    pub memory_limit: Option<u64>,
    /// A job fails after its worker process died this many times.
    pub attempts: u32,
    /// Jobs of at most this cost are short.
    pub short_cost: i64,
}

/// How long past its time limit a job may run before its worker process
/// is killed: the process stops the propagation at the limit and still
/// has to write the (partial) result.
pub fn time_limit_grace(time_limit_s: f64) -> Duration {
    Duration::from_secs_f64((time_limit_s * 0.1).clamp(5.0, 60.0))
}

/// Starts the worker threads: `workers` general ones, then
/// `short_lane_workers` that take only short jobs.
pub fn start(
    config: &PoolConfig,
    store: Arc<dyn Store>,
    workers: Arc<Workers>,
) -> Vec<std::thread::JoinHandle<()>> {
    let config = Arc::new(config.clone());
    let general = (0..config.workers).map(|i| (format!("nvector-worker-{i}"), i64::MAX));
    let short = (0..config.short_lane_workers)
        .map(|i| (format!("nvector-short-worker-{i}"), config.short_cost));
    general
        .chain(short)
        .map(|(name, max_cost)| {
            let (store, workers, config) = (store.clone(), workers.clone(), config.clone());
            std::thread::Builder::new()
                .name(name)
                .spawn(move || worker_loop(&*store, &workers, &config, max_cost))
                .expect("spawn worker thread")
        })
        .collect()
}

fn worker_loop(store: &dyn Store, workers: &Workers, config: &PoolConfig, max_cost: i64) {
    // This thread's worker process, started for the first job and again
    // after one died or was killed. (Started from this thread, which lives
    // as long as the service: on Linux the process dies with it.)
    let mut process: Option<WorkerProcess> = None;
    while !workers.stopping.load(Ordering::SeqCst) {
        match store.claim_job(now_ms(), max_cost) {
            Ok(Some(job)) => {
                let lane = meters::lane(job.cost, config.short_cost);
                if let Some(started) = job.started {
                    workers
                        .meters
                        .job_queue_wait_ms
                        .get_or_create(&lane)
                        .observe(started.saturating_sub(job.created).max(0) as f64);
                }
                workers.meters.busy_workers.inc();
                workers.changed(&job.id);
                let start = Instant::now();
                run_job(store, workers, config, &mut process, &job);
                workers.changed(&job.id);
                workers.meters.busy_workers.dec();
                workers
                    .meters
                    .job_duration_ms
                    .get_or_create(&lane)
                    .observe(start.elapsed().as_secs_f64() * 1e3);
                // A long job may leave its process holding memory it freed:
                // the next job gets a fresh one.
                if job.cost > config.short_cost {
                    if let Some(p) = process.take() {
                        p.kill();
                    }
                }
            }
            Ok(None) => workers.wait(),
            Err(e) => {
                tracing::error!("claiming a job: {e}");
                std::thread::sleep(Duration::from_millis(500));
            }
        }
    }
    if let Some(p) = process {
        p.kill();
    }
}

fn fail(store: &dyn Store, job: &JobRow, code: &'static str, message: String) {
    let e = JobError { code, message };
    if let Err(err) = store.finish_job(&job.id, JobState::Failed, None, Some(&e), now_ms()) {
        tracing::error!("storing the failure of job {}: {err}", job.id);
    }
}

/// A worker process for the next job: the current one if it is alive (one
/// that died while idle is replaced: not the job's fault), else a new one.
fn ready_process(
    process: &mut Option<WorkerProcess>,
    memory_limit: Option<u64>,
) -> std::io::Result<&mut WorkerProcess> {
    if let Some(p) = process.as_mut() {
        if !p.is_alive() {
            if let Some(dead) = process.take() {
                let why = dead.death();
                tracing::warn!("a worker process died while idle: {}", why.message);
            }
        }
    }
    if process.is_none() {
        *process = Some(WorkerProcess::start(memory_limit)?);
    }
    Ok(process.as_mut().expect("a worker process was just started"))
}

/// Runs one claimed job in this thread's worker process and stores how it
/// ended.
fn run_job(
    store: &dyn Store,
    workers: &Workers,
    config: &PoolConfig,
    process: &mut Option<WorkerProcess>,
    job: &JobRow,
) {
    let body = match store.mission_body_any(&job.mission) {
        Ok(Some(b)) => b,
        Ok(None) => {
            return fail(
                store,
                job,
                JobErrorCode::MissionDeleted.as_str(),
                "the mission was deleted".into(),
            )
        }
        Err(e) => {
            tracing::error!("reading mission {}: {e}", job.mission);
            return fail(
                store,
                job,
                JobErrorCode::Internal.as_str(),
                "storage error reading the mission".into(),
            );
        }
    };
    let order = JobOrder {
        id: job.id.clone(),
        contractor: job.contractor.clone(),
        max_rounds: job.max_rounds.clamp(1, i64::from(u32::MAX)) as u32,
        time_limit_s: job.time_limit_s,
        mission_bytes: body.len(),
        kind: JobKind::of(&job.mission),
    };
    let p = match ready_process(process, config.memory_limit) {
        Ok(p) => p,
        Err(e) => {
            // The machine cannot start a process now (out of processes or
            // memory): the job waits for a later try.
            tracing::error!("starting a worker process: {e}");
            let _ = store.requeue_one(&job.id);
            std::thread::sleep(Duration::from_secs(1));
            return;
        }
    };
    // A process that dies while reading the mission (too large for the
    // memory limit) fails the send: that is this job's crash.
    let sent = p.send(&order, &body);
    drop(body);
    if sent.is_err() {
        if let Some(dead) = process.take() {
            return crashed(store, workers, config, job, dead.death());
        }
    }
    supervise(store, workers, config, process, job);
}

/// Follows the job in its worker process until it ends, is cancelled, runs
/// out of time, or the service stops.
fn supervise(
    store: &dyn Store,
    workers: &Workers,
    config: &PoolConfig,
    process: &mut Option<WorkerProcess>,
    job: &JobRow,
) {
    let start = Instant::now();
    let hard_limit =
        Duration::from_secs_f64(job.time_limit_s.max(0.001)) + time_limit_grace(job.time_limit_s);
    let mut last_saved: Option<Instant> = None;
    let mut unsaved: Option<(i64, f64, f64)> = None;
    let mut last_check = Instant::now();
    let kill = |process: &mut Option<WorkerProcess>| {
        if let Some(p) = process.take() {
            p.kill();
        }
    };
    loop {
        let Some(p) = process.as_mut() else { return };
        match p.next(Duration::from_millis(100)) {
            Ok(Some(Message::Progress {
                round,
                diameter,
                fraction,
            })) => {
                let round = i64::try_from(round).unwrap_or(i64::MAX);
                let diameter = diameter.unwrap_or(f64::INFINITY);
                if last_saved.is_none_or(|t| t.elapsed() >= Duration::from_millis(200)) {
                    last_saved = Some(Instant::now());
                    unsaved = None;
                    let _ = store.progress(&job.id, round, diameter, fraction);
                    workers.changed(&job.id);
                } else {
                    unsaved = Some((round, diameter, fraction));
                }
            }
            Ok(Some(Message::Done { result, timed_out })) => {
                // The last progress (the result's own figures) is stored
                // even when it came within the 200 ms of the one before.
                if let Some((round, diameter, fraction)) = unsaved {
                    let _ = store.progress(&job.id, round, diameter, fraction);
                }
                return store_result(store, job, &result, timed_out);
            }
            Ok(Some(Message::Failed(e))) => return fail(store, job, e.code, e.message),
            Ok(None) => {}
            Err(()) => {
                if let Some(dead) = process.take() {
                    crashed(store, workers, config, job, dead.death());
                }
                return;
            }
        }
        if workers.stopping.load(Ordering::SeqCst) {
            // Shutting down mid-job: put it back for the next start.
            kill(process);
            let _ = store.requeue_one(&job.id);
            return;
        }
        if last_check.elapsed() >= Duration::from_millis(250) {
            last_check = Instant::now();
            // Cancelled, or deleted with its mission: stop the work.
            match store.job_state(&job.id) {
                Ok(Some(JobState::Cancelled)) => return kill(process),
                Ok(None) => return kill(process),
                _ => {}
            }
        }
        if start.elapsed() > hard_limit {
            kill(process);
            return fail(
                store,
                job,
                JobErrorCode::TimeLimit.as_str(),
                past_grace(job),
            );
        }
    }
}

/// Stores a job's result (cut short by its time limit when `timed_out`).
fn store_result(store: &dyn Store, job: &JobRow, result: &str, timed_out: bool) {
    let error = timed_out.then(|| JobError {
        code: JobErrorCode::TimeLimit.as_str(),
        message: format!(
            "time limit of {} s reached (partial, sound result kept)",
            job.time_limit_s
        ),
    });
    if let Err(e) = store.finish_job(
        &job.id,
        JobState::Done,
        Some(result),
        error.as_ref(),
        now_ms(),
    ) {
        tracing::error!("storing the result of job {}: {e}", job.id);
    }
}

/// The failure of a job still running past its time limit and grace.
fn past_grace(job: &JobRow) -> String {
    format!(
        "time limit of {} s reached and the job did not stop within {:.0} s more: \
         its worker process was stopped, no result kept",
        job.time_limit_s,
        time_limit_grace(job.time_limit_s).as_secs_f64()
    )
}

/// Records the death of the worker process that ran `job`: back to the
/// queue, or failed at the last attempt (at the first for `memory_limit`:
/// the same job needs the same memory).
fn crashed(
    store: &dyn Store,
    workers: &Workers,
    config: &PoolConfig,
    job: &JobRow,
    mut error: JobError,
) {
    workers
        .meters
        .worker_deaths
        .get_or_create(&ReasonLabel { reason: error.code })
        .inc();
    let max = if error.code == JobErrorCode::MemoryLimit.as_str() {
        1
    } else {
        i64::from(config.attempts.max(1))
    };
    let attempt = job.crashes + 1;
    if error.code != JobErrorCode::MemoryLimit.as_str() {
        error.message = format!(
            "{} (attempt {attempt} of at most {max}: --job-attempts)",
            error.message
        );
    }
    match store.record_crash(&job.id, &error, max, now_ms()) {
        Ok(Some(JobState::Queued)) => {
            tracing::warn!("job {} re-queued: {}", job.id, error.message);
            workers.notify();
        }
        Ok(Some(_)) => tracing::warn!("job {} failed: {}", job.id, error.message),
        Ok(None) => {}
        Err(e) => tracing::error!("recording the crash of job {}: {e}", job.id),
    }
}
