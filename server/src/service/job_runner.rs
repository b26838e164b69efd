//! Inside a worker process (`nvector worker`, started by `nvector serve`,
//! never by hand): runs SLAM jobs one at a time, under a memory limit, and
//! talks to the service over its standard input and output.
//!
//! Protocol (one job at a time; the worker owns no storage):
//! - in: a [`JobOrder`] as one JSON line, then exactly `mission_bytes`
//!   bytes of mission JSON;
//! - out: [`Report::Progress`] lines while it runs (at most ten a second),
//!   then one [`Report::Done`] line followed by exactly `result_bytes` bytes
//!   of result JSON, or one [`Report::Failed`] line.
//!
//! The worker exits when its input ends (the service closed it or died).
//! Cancellation is the service killing the process; the job's own time
//! limit is kept here (the propagation stops at the deadline and the
//! partial, sound result is reported with `timed_out`), and the service
//! kills a worker that overruns it by more than a grace period.
//!
//! The memory limit is `setrlimit(RLIMIT_AS)` on the worker itself, set
//! before it reads anything: an allocation over it fails, the Rust runtime
//! prints `memory allocation of N bytes failed` and aborts, and the service
//! reads that on the worker's standard error as `memory_limit`.

use super::store::JobErrorCode;
use nvector_core::slam::mission::Mission;
use nvector_core::slam::result::write_result;
use nvector_core::slam::solve::solve_model;
use nvector_core::slam::types::{Association, Progress, Solution, SolveOptions};
use serde::{Deserialize, Serialize};
use std::io::{BufRead, BufWriter, Read, Write};
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

/// A job sent to a worker process (one JSON line, then the mission).
#[derive(Debug, Serialize, Deserialize)]
pub struct JobOrder {
    /// The job's id (for the logs).
    pub id: String,
    /// Its association mode.
    pub contractor: String,
    /// Its round cap.
    pub max_rounds: u32,
    /// Its time limit (s).
    pub time_limit_s: f64,
    /// The length of the mission JSON that follows the line.
    pub mission_bytes: usize,
    /// What the job solves (absent: a SLAM mission).
    #[serde(default)]
    pub kind: JobKind,
}

/// What a job solves: a SLAM mission (`POST /jobs`) or a TDOA problem
/// (`POST /tdoa`, `nvector-tdoa/1`; the result is `nvector-tdoa-result/1`).
#[derive(Debug, Default, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum JobKind {
    /// `slam::solve_model` on a mission.
    #[default]
    Slam,
    /// `tdoa::solve_tdoa` on a TDOA problem.
    Tdoa,
}

impl JobKind {
    /// The kind of the job on a stored document: TDOA problems have ids
    /// `t-...` (`POST /tdoa`), missions `m-...`.
    pub fn of(document_id: &str) -> JobKind {
        if document_id.starts_with("t-") {
            JobKind::Tdoa
        } else {
            JobKind::Slam
        }
    }
}

/// What a worker process reports (one JSON line each).
#[derive(Debug, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Report {
    /// The job's progress.
    Progress {
        /// Rounds so far.
        round: u64,
        /// The largest trajectory box diameter (None when unbounded).
        diameter: Option<f64>,
        /// Fraction of the work done.
        fraction: f64,
    },
    /// The job ended with a result: `result_bytes` bytes of JSON follow.
    Done {
        /// The length of the result that follows the line.
        result_bytes: usize,
        /// Whether the time limit stopped the propagation (the result is
        /// partial, and sound).
        timed_out: bool,
    },
    /// The job failed for a reason of its own (bad mission, ...).
    Failed {
        /// A word a client can test.
        code: String,
        /// What is wrong, for a person.
        message: String,
    },
}

/// The address-space limit this process inherited (`ulimit -v`), if any:
/// the hard limit, which no worker can raise.
pub fn inherited_memory_limit() -> Option<u64> {
    #[cfg(unix)]
    {
        rustix::process::getrlimit(rustix::process::Resource::As).maximum
    }
    #[cfg(not(unix))]
    {
        None
    }
}

/// Runs the worker process until its input ends: limits its memory to
/// `memory_limit` bytes (when given) and asks to be killed with its parent,
/// then runs the jobs it reads.
pub fn run(memory_limit: Option<u64>) -> Result<(), String> {
    #[cfg(unix)]
    if let Some(limit) = memory_limit {
        use rustix::process::{setrlimit, Resource, Rlimit};
        // Never above the limit this process inherited (raising a hard
        // limit is refused, and the worker would die at every job).
        let limit = inherited_memory_limit().map_or(limit, |h| limit.min(h));
        setrlimit(
            Resource::As,
            Rlimit {
                current: Some(limit),
                maximum: Some(limit),
            },
        )
        .map_err(|e| format!("setting the memory limit: {e}"))?;
    }
    #[cfg(not(unix))]
    let _ = memory_limit;
    // Killed with the service's worker thread that started it (a service
    // killed with -9 leaves no worker running on). Elsewhere than Linux a
    // worker ends at its next write to the service, or when idle.
    #[cfg(target_os = "linux")]
    rustix::process::set_parent_process_death_signal(Some(rustix::process::Signal::KILL))
        .map_err(|e| format!("setting the parent-death signal: {e}"))?;
    let mut input = std::io::stdin().lock();
    let mut output = std::io::stdout().lock();
    let mut line = String::new();
    loop {
        line.clear();
        if input
            .read_line(&mut line)
            .map_err(|e| format!("reading a job: {e}"))?
            == 0
        {
            return Ok(());
        }
        let order: JobOrder =
            serde_json::from_str(&line).map_err(|e| format!("reading a job order: {e}"))?;
        let mut mission = vec![0u8; order.mission_bytes];
        input
            .read_exact(&mut mission)
            .map_err(|e| format!("reading the mission of job {}: {e}", order.id))?;
        let Ok(mission) = String::from_utf8(mission) else {
            send(
                &mut output,
                &Report::Failed {
                    code: JobErrorCode::InvalidMission.as_str().into(),
                    message: "the mission is not UTF-8".into(),
                },
            )?;
            continue;
        };
        run_job(&order, mission, &mut output)?;
    }
}

fn send(out: &mut impl Write, report: &Report) -> Result<(), String> {
    let mut text = serde_json::to_string(report).map_err(|e| e.to_string())?;
    text.push('\n');
    out.write_all(text.as_bytes())
        .and_then(|()| out.flush())
        .map_err(|e| format!("writing to the service: {e}"))
}

/// Runs one job and reports its end (its progress on the way).
fn run_job(order: &JobOrder, mission: String, out: &mut impl Write) -> Result<(), String> {
    if order.kind == JobKind::Tdoa {
        return run_tdoa(order, &mission, out);
    }
    let mission = match Mission::from_json(&mission) {
        Ok(m) => {
            drop(mission);
            m
        }
        Err(e) => {
            return send(
                out,
                &Report::Failed {
                    code: JobErrorCode::InvalidMission.as_str().into(),
                    message: e.to_string(),
                },
            )
        }
    };
    let options = SolveOptions {
        association: Association::parse(&order.contractor).unwrap_or(Association::None),
        max_rounds: order.max_rounds.max(1),
        tolerance: 1e-9,
        // One thread a job: the service already runs its jobs side by side
        // (`--workers`), so the cores go to the jobs; measured under load,
        // a job's own threads lengthened its wall time.
        threads: 1,
    };
    let cancel = AtomicBool::new(false);
    let start = Instant::now();
    let limit = Duration::from_secs_f64(order.time_limit_s.clamp(0.001, 1e9));
    let mut last_sent: Option<Instant> = None;
    let mut timed_out = false;
    let mut broken: Option<String> = None;
    let mut progress = |p: &Progress| {
        if start.elapsed() > limit {
            timed_out = true;
            cancel.store(true, Ordering::SeqCst);
        }
        if last_sent.is_none_or(|t| t.elapsed() >= Duration::from_millis(100)) {
            last_sent = Some(Instant::now());
            let report = Report::Progress {
                round: u64::from(p.round),
                diameter: p
                    .max_trajectory_diameter
                    .is_finite()
                    .then_some(p.max_trajectory_diameter),
                fraction: p.fraction,
            };
            if let Err(e) = send(out, &report) {
                // The service is gone: stop, and say why on the way out.
                broken = Some(e);
                cancel.store(true, Ordering::SeqCst);
            }
        }
    };
    let deadline = AtomicBool::new(false);
    let solution = with_deadline(start, limit, &cancel, &deadline, || {
        solve_model(&mission, &options, &mut progress, &cancel)
    });
    let timed_out = timed_out || deadline.load(Ordering::SeqCst);
    if let Some(e) = broken {
        return Err(e);
    }
    let elapsed_ms = start.elapsed().as_secs_f64() * 1e3;
    let run = Finished {
        options,
        solution,
        elapsed_ms,
        timed_out,
    };
    send_result(out, mission, run)
}

/// Runs `f` while a watchdog thread sets `cancel` (and `hit`) once `limit`
/// has passed since `start`. The progress callback also checks the clock,
/// but only where the solver reports progress: the robust propagation's
/// sub-propagations (`max_outliers` > 0: consensus, conflict packing)
/// report none, so a job with false detections ran on past its limit, the
/// service killed its worker after the grace period, and the job failed
/// with no result instead of being `done` with its sound partial boxes.
fn with_deadline<T>(
    start: Instant,
    limit: Duration,
    cancel: &AtomicBool,
    hit: &AtomicBool,
    f: impl FnOnce() -> T,
) -> T {
    let done = AtomicBool::new(false);
    std::thread::scope(|scope| {
        let watchdog = scope.spawn(|| {
            while !done.load(Ordering::SeqCst) {
                let left = limit.saturating_sub(start.elapsed());
                if left.is_zero() {
                    hit.store(true, Ordering::SeqCst);
                    cancel.store(true, Ordering::SeqCst);
                    return;
                }
                std::thread::park_timeout(left);
            }
        });
        let out = f();
        done.store(true, Ordering::SeqCst);
        watchdog.thread().unpark();
        out
    })
}

/// A job's run, to be reported.
struct Finished {
    options: SolveOptions,
    solution: Solution,
    elapsed_ms: f64,
    timed_out: bool,
}

/// Reports a job's end: `Done` with the result's length, then the result
/// (or `Failed` if it cannot be written). The mission and the solution are
/// freed before the result is sent.
fn send_result(out: &mut impl Write, mission: Mission, run: Finished) -> Result<(), String> {
    let Finished {
        options,
        solution,
        elapsed_ms,
        timed_out,
    } = run;
    // The final figures as the last progress (the progress lines are sent
    // at most ten a second, so the last round's may not have gone out):
    // a finished job's progress agrees with its result.
    let diameter = solution.model.trajectory_diameters().0;
    send(
        out,
        &Report::Progress {
            round: u64::from(solution.rounds),
            diameter: diameter.is_finite().then_some(diameter),
            fraction: 1.0,
        },
    )?;
    // The whole result first: its length goes before it.
    let mut text = Vec::new();
    if let Err(e) = write_result(&mut text, &mission, &options, &solution, elapsed_ms) {
        return send(
            out,
            &Report::Failed {
                code: JobErrorCode::Internal.as_str().into(),
                message: format!("writing the result: {e}"),
            },
        );
    }
    drop(solution);
    drop(mission);
    send(
        out,
        &Report::Done {
            result_bytes: text.len(),
            timed_out,
        },
    )?;
    let mut w = BufWriter::with_capacity(1 << 16, out);
    w.write_all(&text)
        .and_then(|()| w.flush())
        .map_err(|e| format!("writing the result to the service: {e}"))
}

/// Runs one TDOA job: the problem solved by core's `tdoa::solve_tdoa_with`
/// with the job's contractor (`none` or an atmost_nvector contractor) and
/// round cap, reported as `nvector-tdoa-result/1`. Progress goes out after
/// each round; at the time limit the rounds stop and the (sound, wider)
/// result is reported with `timed_out`.
fn run_tdoa(order: &JobOrder, text: &str, out: &mut impl Write) -> Result<(), String> {
    use nvector_core::nvector::Contractor;
    use nvector_core::tdoa::{solve_tdoa_with, tdoa_result_json, TdoaOptions, TdoaProblem};
    let problem = match TdoaProblem::from_json_str(text) {
        Ok(p) => p,
        Err(e) => {
            return send(
                out,
                &Report::Failed {
                    code: JobErrorCode::InvalidMission.as_str().into(),
                    message: e.to_string(),
                },
            )
        }
    };
    let options = TdoaOptions {
        mode: Contractor::parse(&order.contractor),
        max_rounds: (order.max_rounds as usize).clamp(1, MAX_TDOA_ROUNDS),
        ..TdoaOptions::default()
    };
    let start = Instant::now();
    let limit = Duration::from_secs_f64(order.time_limit_s.clamp(0.001, 1e9));
    let mut timed_out = false;
    let mut broken: Option<String> = None;
    let rounds = options.max_rounds as f64;
    let mut go_on = |done: usize| {
        let report = Report::Progress {
            round: done as u64,
            diameter: None,
            fraction: (done as f64 / rounds).min(1.0),
        };
        if let Err(e) = send(out, &report) {
            broken = Some(e);
            return false;
        }
        timed_out = start.elapsed() > limit;
        !timed_out
    };
    let solution = solve_tdoa_with(&problem, &options, &mut go_on);
    if let Some(e) = broken {
        return Err(e);
    }
    let elapsed_ms = start.elapsed().as_secs_f64() * 1e3;
    let text = tdoa_result_json(&problem, &options, &solution, elapsed_ms).to_string();
    send(
        out,
        &Report::Done {
            result_bytes: text.len(),
            timed_out,
        },
    )?;
    out.write_all(text.as_bytes())
        .and_then(|()| out.flush())
        .map_err(|e| format!("writing the result to the service: {e}"))
}

/// Most rounds of a TDOA job (as `nvector tdoa`'s `--max-rounds` cap).
pub const MAX_TDOA_ROUNDS: usize = 1000;
