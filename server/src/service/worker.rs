//! The job workers: dedicated threads off the async runtime, one
//! propagation each. A worker claims the oldest queued job from storage,
//! runs it with a progress callback that persists progress regularly and
//! checks for cancellation (DELETE) and the time limit, then stores the
//! result. Idle workers wait on a condition variable, woken when a job is
//! queued (and poll storage every second, for jobs queued by another
//! process sharing the database).

use super::store::{JobRow, Store};
use nvector_core::slam::mission::Mission;
use nvector_core::slam::propagator::{solve_model, Association, Progress, SolveOptions};
use nvector_core::slam::result::write_result;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
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
    /// Job durations (ms) of finished jobs, for the histogram.
    pub durations: Mutex<Vec<f64>>,
    /// Jobs currently running in this process.
    pub running: AtomicU64,
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
            durations: Mutex::new(Vec::new()),
            running: AtomicU64::new(0),
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

/// Starts `n` worker threads.
pub fn start(
    n: usize,
    store: Arc<dyn Store>,
    workers: Arc<Workers>,
) -> Vec<std::thread::JoinHandle<()>> {
    (0..n.max(1))
        .map(|i| {
            let store = store.clone();
            let workers = workers.clone();
            std::thread::Builder::new()
                .name(format!("nvector-worker-{i}"))
                .spawn(move || worker_loop(store, workers))
                .expect("spawn worker thread")
        })
        .collect()
}

fn worker_loop(store: Arc<dyn Store>, workers: Arc<Workers>) {
    while !workers.stopping.load(Ordering::SeqCst) {
        match store.claim_job(now_ms()) {
            Ok(Some(job)) => {
                workers.running.fetch_add(1, Ordering::SeqCst);
                workers.changed(&job.id);
                let id = job.id.clone();
                let start = Instant::now();
                run_job(&*store, &workers, job);
                workers.changed(&id);
                workers.running.fetch_sub(1, Ordering::SeqCst);
                if let Ok(mut d) = workers.durations.lock() {
                    d.push(start.elapsed().as_secs_f64() * 1e3);
                }
            }
            Ok(None) => workers.wait(),
            Err(e) => {
                tracing::error!("claiming a job: {e}");
                std::thread::sleep(Duration::from_millis(500));
            }
        }
    }
}

fn run_job(store: &dyn Store, workers: &Workers, job: JobRow) {
    let body = match store.mission_body_any(&job.mission) {
        Ok(Some(b)) => b,
        Ok(None) => {
            let _ = store.finish_job(
                &job.id,
                "failed",
                None,
                Some("the mission was deleted"),
                now_ms(),
            );
            return;
        }
        Err(e) => {
            tracing::error!("reading mission {}: {e}", job.mission);
            let _ = store.finish_job(
                &job.id,
                "failed",
                None,
                Some("storage error reading the mission"),
                now_ms(),
            );
            return;
        }
    };
    let mission = match Mission::from_json(&body) {
        Ok(m) => {
            drop(body);
            m
        }
        Err(e) => {
            let _ = store.finish_job(&job.id, "failed", None, Some(&e.to_string()), now_ms());
            return;
        }
    };
    let association = Association::parse(&job.contractor).unwrap_or(Association::None);
    let options = SolveOptions {
        association,
        max_rounds: job.max_rounds.clamp(1, u32::MAX as i64) as u32,
        tolerance: 1e-9,
    };
    let cancel = AtomicBool::new(false);
    let start = Instant::now();
    let limit = Duration::from_secs_f64(job.time_limit_s.max(0.001));
    let mut last_saved = Instant::now() - Duration::from_secs(1);
    let mut timed_out = false;
    let mut progress = |p: &Progress| {
        if last_saved.elapsed() >= Duration::from_millis(200) {
            last_saved = Instant::now();
            let _ = store.progress(
                &job.id,
                p.round as i64,
                p.max_trajectory_diameter,
                p.fraction,
            );
            workers.changed(&job.id);
            if let Ok(Some(s)) = store.job_state(&job.id) {
                if s == "cancelled" {
                    cancel.store(true, Ordering::SeqCst);
                }
            }
        }
        if start.elapsed() > limit {
            timed_out = true;
            cancel.store(true, Ordering::SeqCst);
        }
        if workers.stopping.load(Ordering::SeqCst) {
            cancel.store(true, Ordering::SeqCst);
        }
    };
    let solution = solve_model(&mission, &options, &mut progress, &cancel);
    let elapsed_ms = start.elapsed().as_secs_f64() * 1e3;
    if workers.stopping.load(Ordering::SeqCst) && !timed_out {
        // Shutting down mid-job: put it back for the next start.
        let _ = store.requeue_one(&job.id);
        return;
    }
    if matches!(store.job_state(&job.id), Ok(Some(s)) if s == "cancelled") {
        return;
    }
    // Streamed into the text (no JSON value of the whole result: a 10^6-step
    // result is 82 MB of text, several times that as a value tree).
    let mut text = Vec::new();
    if let Err(e) = write_result(&mut text, &mission, &options, &solution, elapsed_ms) {
        let _ = store.finish_job(
            &job.id,
            "failed",
            None,
            Some(&format!("writing the result: {e}")),
            now_ms(),
        );
        return;
    }
    drop(solution);
    let text = String::from_utf8(text).expect("serde_json writes UTF-8");
    let error = timed_out.then(|| {
        format!(
            "time limit of {} s reached (partial, sound result kept)",
            job.time_limit_s
        )
    });
    if let Err(e) = store.finish_job(&job.id, "done", Some(&text), error.as_deref(), now_ms()) {
        tracing::error!("storing the result of job {}: {e}", job.id);
    }
}
