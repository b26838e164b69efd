//! The service's handle on one worker process: starts `nvector worker` (this
//! same binary) with the job memory limit, sends it jobs, reads its reports
//! on a thread of its own, keeps the end of its standard error (logged as
//! it comes), and when it dies says why, as a job error: `memory_limit`
//! (an allocation over the limit: the runtime's `memory allocation of N
//! bytes failed` before the abort) or `worker_crashed` (any other death:
//! abort, panic, a signal such as SIGKILL).

use super::config::format_size;
use super::job_runner::{JobOrder, Report};
use super::store::JobError;
use super::store::JobErrorCode;
use std::collections::VecDeque;
use std::io::{BufRead, BufReader, Read, Write};
use std::process::{Child, ChildStdin, Command, ExitStatus, Stdio};
use std::sync::mpsc::{self, Receiver, RecvTimeoutError};
use std::sync::{Arc, Mutex};
use std::time::Duration;

/// What the reader thread passes on from a worker process.
#[derive(Debug)]
pub enum Message {
    /// Progress of the running job.
    Progress {
        /// Rounds so far.
        round: u64,
        /// The largest trajectory box diameter (None when unbounded).
        diameter: Option<f64>,
        /// Fraction of the work done.
        fraction: f64,
    },
    /// The job ended with this result text.
    Done {
        /// The result JSON.
        result: String,
        /// Whether the time limit cut the propagation short.
        timed_out: bool,
    },
    /// The job failed for a reason of its own.
    Failed(JobError),
}

/// The lines of standard error kept to explain a death.
const STDERR_LINES: usize = 20;

/// One worker process and the threads that read it.
pub struct WorkerProcess {
    child: Child,
    stdin: ChildStdin,
    reports: Receiver<Message>,
    stderr: Arc<Mutex<VecDeque<String>>>,
    stderr_reader: Option<std::thread::JoinHandle<()>>,
    memory_limit: Option<u64>,
}

/// The program to start as a worker: this binary (on Linux its
/// `/proc/self/exe`, which stays valid when the file is replaced by an
/// upgrade while the service runs).
fn program() -> std::io::Result<std::path::PathBuf> {
    let proc_exe = std::path::Path::new("/proc/self/exe");
    if proc_exe.exists() {
        return Ok(proc_exe.to_path_buf());
    }
    std::env::current_exe()
}

impl WorkerProcess {
    /// Starts a worker process with this memory limit (bytes; None: no
    /// limit). It must be called from a thread that lives as long as the
    /// process: on Linux the worker is killed when that thread ends.
    pub fn start(memory_limit: Option<u64>) -> std::io::Result<WorkerProcess> {
        let mut cmd = Command::new(program()?);
        cmd.arg("worker");
        if let Some(limit) = memory_limit {
            cmd.args(["--memory-limit", &limit.to_string()]);
        }
        let mut child = cmd
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .env_remove("RUST_BACKTRACE")
            .spawn()?;
        let pid = child.id();
        let (stdin, stdout, stderr) =
            match (child.stdin.take(), child.stdout.take(), child.stderr.take()) {
                (Some(i), Some(o), Some(e)) => (i, o, e),
                _ => {
                    let _ = child.kill();
                    let _ = child.wait();
                    return Err(std::io::Error::other("the worker's pipes were not opened"));
                }
            };
        let (tx, reports) = mpsc::channel();
        std::thread::Builder::new()
            .name(format!("nvector-worker-out-{pid}"))
            .spawn(move || read_reports(BufReader::with_capacity(1 << 16, stdout), &tx))?;
        let tail = Arc::new(Mutex::new(VecDeque::new()));
        let kept = tail.clone();
        let stderr_reader = std::thread::Builder::new()
            .name(format!("nvector-worker-err-{pid}"))
            .spawn(move || {
                // The runtime's allocation-failure line is kept whatever
                // follows it (a backtrace can be longer than the tail).
                let mut allocation = None;
                for line in BufReader::new(stderr).lines() {
                    let Ok(line) = line else { break };
                    tracing::warn!("worker process {pid}: {line}");
                    if line.starts_with("memory allocation of ") {
                        allocation = Some(line.clone());
                    }
                    if let Ok(mut t) = kept.lock() {
                        if t.len() == STDERR_LINES {
                            t.pop_front();
                        }
                        t.push_back(line);
                    }
                }
                if let (Some(line), Ok(mut t)) = (allocation, kept.lock()) {
                    t.push_back(line);
                }
            })?;
        Ok(WorkerProcess {
            child,
            stdin,
            reports,
            stderr: tail,
            stderr_reader: Some(stderr_reader),
            memory_limit,
        })
    }

    /// Whether the worker process is still running.
    pub fn is_alive(&mut self) -> bool {
        matches!(self.child.try_wait(), Ok(None))
    }

    /// Sends a job: its order line, then the mission. An error means the
    /// worker is gone (it died while idle: not this job's fault).
    pub fn send(&mut self, order: &JobOrder, mission: &str) -> std::io::Result<()> {
        let mut line = serde_json::to_string(order).map_err(std::io::Error::other)?;
        line.push('\n');
        self.stdin.write_all(line.as_bytes())?;
        self.stdin.write_all(mission.as_bytes())?;
        self.stdin.flush()
    }

    /// The next report, waiting at most `timeout`: Ok(None) on timeout,
    /// Err(()) when the worker closed its output (it died, or broke the
    /// protocol: then it was killed).
    pub fn next(&mut self, timeout: Duration) -> Result<Option<Message>, ()> {
        match self.reports.recv_timeout(timeout) {
            Ok(m) => Ok(Some(m)),
            Err(RecvTimeoutError::Timeout) => Ok(None),
            Err(RecvTimeoutError::Disconnected) => Err(()),
        }
    }

    /// Kills the worker (SIGKILL) and reaps it.
    pub fn kill(mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }

    /// Waits for a worker whose output closed to exit, and says why it
    /// died as a job error (the worker process itself is gone after this).
    pub fn death(mut self) -> JobError {
        // A worker that closed its output without dying broke the protocol.
        let status = match self.child.try_wait() {
            Ok(Some(s)) => Ok(s),
            _ => {
                std::thread::sleep(Duration::from_millis(100));
                match self.child.try_wait() {
                    Ok(Some(s)) => Ok(s),
                    _ => {
                        let _ = self.child.kill();
                        self.child.wait().map_err(|_| ())
                    }
                }
            }
        };
        // Its standard error ends with it: read to the end.
        if let Some(h) = self.stderr_reader.take() {
            let _ = h.join();
        }
        let tail: Vec<String> = self
            .stderr
            .lock()
            .map(|t| t.iter().cloned().collect())
            .unwrap_or_default();
        explain_death(status.ok(), &tail, self.memory_limit)
    }
}

impl Drop for WorkerProcess {
    fn drop(&mut self) {
        // Never leave a worker behind (a no-op once it was reaped).
        if let Ok(None) = self.child.try_wait() {
            let _ = self.child.kill();
            let _ = self.child.wait();
        }
    }
}

/// Reads the worker's reports until its output closes (or breaks the
/// protocol), passing each on.
fn read_reports(mut out: impl BufRead, tx: &mpsc::Sender<Message>) {
    let mut line = String::new();
    loop {
        line.clear();
        match out.read_line(&mut line) {
            Ok(0) | Err(_) => return,
            Ok(_) => {}
        }
        let message = match serde_json::from_str::<Report>(&line) {
            Ok(Report::Progress {
                round,
                diameter,
                fraction,
            }) => Message::Progress {
                round,
                diameter,
                fraction,
            },
            Ok(Report::Done {
                result_bytes,
                timed_out,
            }) => {
                let mut bytes = Vec::new();
                if (&mut out)
                    .take(result_bytes as u64)
                    .read_to_end(&mut bytes)
                    .is_err()
                    || bytes.len() != result_bytes
                {
                    return;
                }
                let Ok(result) = String::from_utf8(bytes) else {
                    return;
                };
                Message::Done { result, timed_out }
            }
            Ok(Report::Failed { code, message }) => Message::Failed(JobError {
                code: known_code(&code),
                message,
            }),
            Err(e) => {
                tracing::error!("a worker process broke the protocol: {e}");
                return;
            }
        };
        if tx.send(message).is_err() {
            return;
        }
    }
}

/// The job error codes a worker may report, as static words (anything else
/// reads as `internal`).
fn known_code(code: &str) -> &'static str {
    match code {
        "invalid_mission" => JobErrorCode::InvalidMission.as_str(),
        _ => JobErrorCode::Internal.as_str(),
    }
}

/// Why a worker process died, from its exit status and the end of its
/// standard error: `memory_limit` when an allocation failed, else
/// `worker_crashed` naming the signal or the exit status.
pub fn explain_death(
    status: Option<ExitStatus>,
    stderr_tail: &[String],
    memory_limit: Option<u64>,
) -> JobError {
    let allocation = stderr_tail.iter().rev().find_map(|l| {
        l.strip_prefix("memory allocation of ")
            .and_then(|rest| rest.strip_suffix(" bytes failed"))
    });
    if let Some(bytes) = allocation {
        let limit = memory_limit.map_or_else(
            || "the machine could give (no --job-memory-limit)".to_string(),
            |l| {
                format!(
                    "this service's limit of {} per job (--job-memory-limit)",
                    format_size(l)
                )
            },
        );
        return JobError {
            code: JobErrorCode::MemoryLimit.as_str(),
            message: format!(
                "the job needs more memory than {limit}: an allocation of {bytes} bytes failed \
                 and its worker process stopped"
            ),
        };
    }
    let how = match status {
        None => "stopped, status unknown".to_string(),
        Some(s) => describe_status(s),
    };
    JobError {
        code: JobErrorCode::WorkerCrashed.as_str(),
        message: format!("the worker process running the job died: {how}"),
    }
}

#[cfg(unix)]
fn describe_status(s: ExitStatus) -> String {
    use std::os::unix::process::ExitStatusExt;
    match (s.signal(), s.code()) {
        (Some(9), _) => {
            "killed (SIGKILL: from outside, or by the system when out of memory)".into()
        }
        (Some(6), _) => "aborted (SIGABRT)".into(),
        (Some(11), _) => "segmentation fault (SIGSEGV)".into(),
        (Some(sig), _) => format!("killed by signal {sig}"),
        (None, Some(101)) => "a panic (a bug: the service's log has its message)".into(),
        (None, Some(c)) => format!("exit status {c}"),
        (None, None) => "stopped, status unknown".into(),
    }
}

#[cfg(not(unix))]
fn describe_status(s: ExitStatus) -> String {
    match s.code() {
        Some(101) => "a panic (a bug: the service's log has its message)".into(),
        Some(c) => format!("exit status {c}"),
        None => "stopped, status unknown".into(),
    }
}

#[cfg(all(test, unix))]
mod tests {
    use super::*;
    use std::os::unix::process::ExitStatusExt;

    #[test]
    fn an_allocation_failure_reads_as_the_memory_limit() {
        let tail = vec![
            "something else".to_string(),
            "memory allocation of 34359738368 bytes failed".to_string(),
        ];
        let e = explain_death(Some(ExitStatus::from_raw(6)), &tail, Some(64 << 20));
        assert_eq!(e.code, "memory_limit");
        assert!(e.message.contains("64 MiB"), "{}", e.message);
        assert!(e.message.contains("34359738368 bytes"), "{}", e.message);
    }

    #[test]
    fn other_deaths_read_as_crashes_naming_the_cause() {
        let killed = explain_death(Some(ExitStatus::from_raw(9)), &[], Some(1 << 30));
        assert_eq!(killed.code, "worker_crashed");
        assert!(killed.message.contains("SIGKILL"), "{}", killed.message);
        let aborted = explain_death(
            Some(ExitStatus::from_raw(6)),
            &["thread 'main' panicked at x.rs".to_string()],
            None,
        );
        assert_eq!(aborted.code, "worker_crashed");
        assert!(aborted.message.contains("SIGABRT"), "{}", aborted.message);
        let panicked = explain_death(Some(ExitStatus::from_raw(101 << 8)), &[], None);
        assert!(panicked.message.contains("panic"), "{}", panicked.message);
    }
}
