//! `nvector bench --service`: the load run of BENCHMARKS.md ("Service").
//! Starts a real `nvector serve` (this binary) on a free loopback port with
//! a fresh database, then `clients` threads at once each upload a small
//! simulated mission, queue a job on it and follow the job's Server-Sent
//! Events to the end. Prints one JSON line: errors, submit-to-done p50/p99,
//! throughput, and the peak resident memory of the service's HTTP process
//! and, summed, of its worker processes (the jobs run there).

use crate::CliError;
use nvector_core::slam::simulate::{simulate, Scenario, SimulateOptions};
use serde_json::{json, Value};
use std::io::{BufRead, BufReader, Read, Write};
use std::net::TcpStream;
use std::process::{Child, Command, Stdio};
use std::sync::{Arc, Barrier};
use std::time::{Duration, Instant};

/// Options of the load run.
pub struct Options {
    /// Clients at once.
    pub clients: usize,
    /// Steps of each client's mission.
    pub steps: usize,
    /// Storage URL (default: a fresh SQLite file in a temporary directory).
    pub database: Option<String>,
    /// Worker threads of the service (default: its own default, the cores).
    pub workers: Option<usize>,
}

struct Service {
    child: Child,
    addr: String,
    dir: std::path::PathBuf,
}

impl Drop for Service {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
        let _ = std::fs::remove_dir_all(&self.dir);
    }
}

fn start_service(o: &Options) -> Result<Service, CliError> {
    let dir = std::env::temp_dir().join(format!("nvector-load-{}", std::process::id()));
    std::fs::create_dir_all(&dir)?;
    let db = o
        .database
        .clone()
        .unwrap_or_else(|| format!("sqlite://{}", dir.join("load.db").display()));
    let exe = std::env::current_exe()?;
    let mut cmd = Command::new(exe);
    cmd.args(["serve", "--addr", "127.0.0.1:0", "--database", &db])
        .arg("--static-dir")
        .arg(dir.join("www"))
        .args(["--max-queue", &(o.clients * 2 + 10).to_string()])
        .env("RUST_LOG", "warn")
        .stdout(Stdio::piped())
        .stderr(Stdio::inherit());
    if let Some(w) = o.workers {
        cmd.args(["--workers", &w.to_string()]);
    }
    let mut child = cmd.spawn()?;
    let mut line = String::new();
    if let Some(out) = child.stdout.take() {
        BufReader::new(out).read_line(&mut line)?;
    }
    let addr = line
        .trim()
        .strip_prefix("nvector serving on http://")
        .map(str::to_string);
    match addr {
        Some(addr) => Ok(Service { child, addr, dir }),
        None => {
            let _ = child.kill();
            Err(CliError(format!("the service did not start: {line}")))
        }
    }
}

/// One HTTP/1.1 request over a new connection; returns (status, body).
fn request(addr: &str, method: &str, path: &str, body: &str) -> Result<(u16, String), String> {
    let mut s = TcpStream::connect(addr).map_err(|e| format!("connect: {e}"))?;
    s.set_read_timeout(Some(Duration::from_secs(120)))
        .map_err(|e| e.to_string())?;
    let req = format!(
        "{method} {path} HTTP/1.1\r\nHost: {addr}\r\nConnection: close\r\nContent-Type: application/json\r\nContent-Length: {}\r\n\r\n{body}",
        body.len()
    );
    s.write_all(req.as_bytes())
        .map_err(|e| format!("write: {e}"))?;
    let mut buf = Vec::new();
    s.read_to_end(&mut buf).map_err(|e| format!("read: {e}"))?;
    let text = String::from_utf8_lossy(&buf).to_string();
    let (head, rest) = text
        .split_once("\r\n\r\n")
        .ok_or("a response with no head")?;
    let status = head
        .split_whitespace()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .ok_or("a response with no status")?;
    Ok((status, rest.to_string()))
}

/// Follows a job's event stream until its `end` event; returns the job.
fn follow(addr: &str, job: &str) -> Result<Value, String> {
    let mut s = TcpStream::connect(addr).map_err(|e| format!("connect: {e}"))?;
    s.set_read_timeout(Some(Duration::from_secs(300)))
        .map_err(|e| e.to_string())?;
    let req = format!(
        "GET /api/v1/jobs/{job}/events HTTP/1.1\r\nHost: {addr}\r\nAccept: text/event-stream\r\n\r\n"
    );
    s.write_all(req.as_bytes())
        .map_err(|e| format!("write: {e}"))?;
    let mut reader = BufReader::new(s);
    let mut line = String::new();
    let mut ended = false;
    loop {
        line.clear();
        if reader.read_line(&mut line).map_err(|e| e.to_string())? == 0 {
            return Err("the event stream closed before the end event".into());
        }
        if line.starts_with("event: end") {
            ended = true;
        } else if ended {
            if let Some(data) = line.strip_prefix("data: ") {
                return serde_json::from_str(data.trim()).map_err(|e| e.to_string());
            }
        }
    }
}

/// One client: upload, queue, follow. Returns submit-to-done seconds.
fn client(addr: &str, mission: &str) -> Result<f64, String> {
    let t = Instant::now();
    let (st, body) = request(addr, "POST", "/api/v1/missions", mission)?;
    if st != 201 {
        return Err(format!("upload: {st} {body}"));
    }
    let id = serde_json::from_str::<Value>(&body).map_err(|e| e.to_string())?["id"]
        .as_str()
        .ok_or("upload: no id")?
        .to_string();
    let job = json!({"mission": id, "contractor": "best"}).to_string();
    let (st, body) = request(addr, "POST", "/api/v1/jobs", &job)?;
    if st != 202 {
        return Err(format!("job: {st} {body}"));
    }
    let jid = serde_json::from_str::<Value>(&body).map_err(|e| e.to_string())?["id"]
        .as_str()
        .ok_or("job: no id")?
        .to_string();
    let end = follow(addr, &jid)?;
    if end["state"] != "done" {
        return Err(format!("job ended {}", end["state"]));
    }
    Ok(t.elapsed().as_secs_f64())
}

/// The child processes of `parent` (its worker processes), from /proc
/// (Linux; empty elsewhere).
fn worker_pids(parent: u32) -> Vec<u32> {
    let Ok(dir) = std::fs::read_dir("/proc") else {
        return Vec::new();
    };
    dir.flatten()
        .filter_map(|e| e.file_name().to_str()?.parse::<u32>().ok())
        .filter(|pid| {
            std::fs::read_to_string(format!("/proc/{pid}/stat")).is_ok_and(|stat| {
                // `pid (comm) state ppid ...`: read after the comm.
                let rest = stat.rsplit_once(')').map_or("", |(_, r)| r);
                rest.split_whitespace().nth(1) == Some(&parent.to_string())
            })
        })
        .collect()
}

/// Peak resident memory (VmHWM) of a process, in MiB (Linux).
fn peak_rss_mib(pid: u32) -> Option<f64> {
    let s = std::fs::read_to_string(format!("/proc/{pid}/status")).ok()?;
    let kb: f64 = s
        .lines()
        .find(|l| l.starts_with("VmHWM:"))?
        .split_whitespace()
        .nth(1)?
        .parse()
        .ok()?;
    Some(kb / 1024.0)
}

fn percentile(sorted: &[f64], p: f64) -> f64 {
    if sorted.is_empty() {
        return f64::NAN;
    }
    let i = ((sorted.len() as f64 * p).ceil() as usize).clamp(1, sorted.len()) - 1;
    sorted[i]
}

/// Runs the load and returns its JSON line.
pub fn run(o: &Options) -> Result<Value, CliError> {
    if o.clients == 0 {
        return Err(CliError("--clients must be at least 1".into()));
    }
    let service = start_service(o)?;
    // Each client its own mission (different seeds), made before the clock.
    let missions: Vec<String> = (0..o.clients)
        .map(|i| {
            let mut so = SimulateOptions::new(Scenario::Paper, 1000 + i as u64);
            so.steps = Some(o.steps);
            simulate(&so).to_string()
        })
        .collect();
    let barrier = Arc::new(Barrier::new(o.clients));
    let start = Instant::now();
    let handles: Vec<_> = missions
        .into_iter()
        .map(|m| {
            let addr = service.addr.clone();
            let barrier = barrier.clone();
            std::thread::Builder::new()
                .stack_size(256 << 10)
                .spawn(move || {
                    barrier.wait();
                    client(&addr, &m)
                })
        })
        .collect::<Result<_, _>>()?;
    let mut times = Vec::new();
    let mut errors = Vec::new();
    for h in handles {
        match h.join() {
            Ok(Ok(t)) => times.push(t),
            Ok(Err(e)) => errors.push(e),
            Err(_) => errors.push("client thread panicked".into()),
        }
    }
    let wall = start.elapsed().as_secs_f64();
    let rss = peak_rss_mib(service.child.id());
    let workers_rss: f64 = worker_pids(service.child.id())
        .into_iter()
        .filter_map(peak_rss_mib)
        .sum();
    times.sort_by(f64::total_cmp);
    let mut v = json!({
        "name": "service_load",
        "ms": (percentile(&times, 0.99) * 1e6).round() / 1e3,
        "clients": o.clients,
        "steps": o.steps,
        "errors": errors.len(),
        "p50_ms": (percentile(&times, 0.5) * 1e6).round() / 1e3,
        "p99_ms": (percentile(&times, 0.99) * 1e6).round() / 1e3,
        "max_ms": (times.last().copied().unwrap_or(f64::NAN) * 1e6).round() / 1e3,
        "wall_ms": (wall * 1e6).round() / 1e3,
        "jobs_per_s": ((times.len() as f64 / wall) * 1e3).round() / 1e3,
        "peak_rss_mib": rss.map(|r| (r * 10.0).round() / 10.0),
        "workers_peak_rss_mib": (workers_rss * 10.0).round() / 10.0,
        "goal_p99_ms": 2000,
    });
    if let Some(e) = errors.first() {
        v["first_error"] = json!(e);
    }
    Ok(v)
}
