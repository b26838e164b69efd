//! The end-to-end harness: the real `nvector` binary (located, and built
//! when missing or stale, by [`nvector_bin`]), `nvector serve` on a free
//! loopback port with a fresh SQLite file or a database on a throw-away
//! PostgreSQL cluster ([`pg`]), and a minimal HTTP/1.1 client over a real
//! socket (raw, so that malformed requests can be sent too).

pub mod browser;
pub mod chromium;
pub mod pg;
pub mod schema;

use serde_json::Value;
use std::io::{BufRead, BufReader, Read, Write};
use std::net::TcpStream;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::sync::OnceLock;
use std::time::{Duration, Instant};

/// The repository root (the workspace).
pub fn repo_root() -> &'static Path {
    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/.."))
}

/// The `nvector` binary under test.
///
/// `NVECTOR_BIN`, when set, names it. Otherwise it is `nvector` in the
/// profile directory of this test executable (`target/debug/deps/x` ->
/// `target/debug/nvector`), first brought up to date by `cargo build
/// --workspace --bins --tests --profile test` (`cargo test --workspace`'s
/// selection and profile; for `target/release`, `cargo build -p
/// nvector-server --bin nvector --profile release`), once per test
/// process. The binary belongs to another package, so
/// `CARGO_BIN_EXE_nvector` does not exist here; building it from the test
/// keeps `cargo test --workspace` working from a fresh clone, and costs one
/// no-op cargo call when the Makefile built it first.
pub fn nvector_bin() -> &'static Path {
    static BIN: OnceLock<PathBuf> = OnceLock::new();
    BIN.get_or_init(|| {
        if let Some(p) = std::env::var_os("NVECTOR_BIN") {
            return PathBuf::from(p);
        }
        let exe = std::env::current_exe().expect("the test executable's path");
        let profile_dir = exe
            .parent()
            .and_then(Path::parent)
            .expect("a test executable under target/<profile>/deps")
            .to_path_buf();
        let dir_name = profile_dir
            .file_name()
            .and_then(|n| n.to_str())
            .unwrap_or("debug");
        let profile = match dir_name {
            "debug" => "test",
            other => other,
        };
        // In `target/debug`, the binary is built with the package
        // selection of `cargo test --workspace` (every member's tests: the
        // same features for every dependency), so that after it (CI, `make
        // test`) only the binary itself is compiled. With `-p
        // nvector-server` alone, cargo resolved other features (serde_json
        // without `alloc`, syn without `extra-traits` and `visit`: brought
        // by other members and their dev-dependencies) and compiled serde,
        // the proc macros, core and the server's dependencies a second time
        // while the tests ran: most of the browser test's cold 125 s in CI
        // (BENCHMARKS.md, "CI time").
        let select: &[&str] = if profile == "test" {
            &["--workspace", "--bins", "--tests"]
        } else {
            &["-p", "nvector-server", "--bin", "nvector"]
        };
        let cargo = std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into());
        let status = Command::new(cargo)
            .current_dir(repo_root())
            .args(["build", "--quiet"])
            .args(select)
            .args(["--profile", profile])
            .status()
            .expect("run cargo to build the nvector binary");
        assert!(status.success(), "cargo build of the nvector binary failed");
        let bin = profile_dir.join(format!("nvector{}", std::env::consts::EXE_SUFFIX));
        assert!(bin.exists(), "no nvector binary at {}", bin.display());
        bin
    })
}

/// `nvector ARGS...` as a command, ready to run.
pub fn nvector() -> Command {
    Command::new(nvector_bin())
}

/// A running service.
pub struct Server {
    pub child: Child,
    pub addr: String,
    pub dir: PathBuf,
    pub db: String,
}

/// Where a test server keeps its data.
pub enum Backend<'a> {
    /// A fresh SQLite file in the server's directory.
    Sqlite,
    /// A fresh database on the test PostgreSQL cluster.
    Postgres(&'a pg::PgCluster),
}

/// Declares `sqlite::NAME` and `postgres::NAME` tests for each scenario
/// `fn NAME(b: &Backend)`: the same test against both storages.
#[macro_export]
macro_rules! on_both_storages {
    ($($name:ident),* $(,)?) => {
        mod sqlite {
            $(
                #[test]
                fn $name() {
                    super::$name(&$crate::Backend::Sqlite)
                }
            )*
        }
        mod postgres {
            $(
                #[test]
                fn $name() {
                    $crate::pg::with_cluster(|c| {
                        super::$name(&$crate::Backend::Postgres(c))
                    });
                }
            )*
        }
    };
}

/// A fresh path named `name` in a new temporary directory: two calls never
/// share a file, so tests running in parallel cannot overwrite each
/// other's outputs.
pub fn temp_file(name: &str) -> PathBuf {
    temp_dir("file").join(name)
}

/// Runs the `nvector` binary with `args` to completion.
pub fn run(args: &[&str]) -> std::process::Output {
    nvector().args(args).output().expect("run nvector")
}

/// Asserts that a run succeeded and returns its standard error.
pub fn succeeded(out: &std::process::Output) -> String {
    let err = String::from_utf8_lossy(&out.stderr).to_string();
    assert!(out.status.success(), "{err}");
    err
}

/// The JSON document in the file at `p`.
pub fn read_json(p: &Path) -> Value {
    let text = std::fs::read_to_string(p).unwrap_or_else(|e| panic!("{}: {e}", p.display()));
    serde_json::from_str(&text).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

/// The planted detections of an imported mission (`truth.matching` null)
/// that are not false: a planted range is false when its interval misses,
/// for every landmark of `truth.landmarks`, the true distance from the
/// true position at its step by more than |`sensor_offset`| (where the
/// sensor may be). Returns `(index, why)` for each one that is not, and
/// the count of planted detections checked.
pub fn planted_ranges_not_false(m: &Value) -> (Vec<(usize, String)>, usize) {
    let point = |v: &Value| Some((v[0].as_f64()?, v[1].as_f64()?));
    let o = point(&m["sensor_offset"]).map_or(0.0, |(x, y)| f64::hypot(x, y));
    let landmarks: Vec<(f64, f64)> = m["truth"]["landmarks"]
        .as_array()
        .expect("truth.landmarks")
        .iter()
        .map(|l| point(l).expect("a true landmark"))
        .collect();
    let mut bad = Vec::new();
    let mut planted = 0;
    let matching = m["truth"]["matching"].as_array().expect("truth.matching");
    for (i, d) in m["detections"].as_array().unwrap().iter().enumerate() {
        if !matching[i].is_null() {
            continue;
        }
        planted += 1;
        let step = d["step"].as_u64().unwrap() as usize;
        let (lo, hi) = (
            d["range"][0].as_f64().unwrap(),
            d["range"][1].as_f64().unwrap(),
        );
        let Some((px, py)) = point(&m["truth"]["positions"][step]) else {
            bad.push((i, format!("no true position at step {step}")));
            continue;
        };
        for (l, &(lx, ly)) in landmarks.iter().enumerate() {
            let dist = f64::hypot(lx - px, ly - py);
            if dist + o >= lo && dist - o <= hi {
                bad.push((
                    i,
                    format!("range [{lo}, {hi}] at step {step} may see landmark {l} ({dist} m)"),
                ));
            }
        }
    }
    (bad, planted)
}

/// A new temporary directory.
pub fn temp_dir(what: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!(
        "nvector-{what}-{}-{}",
        std::process::id(),
        uuid_like()
    ));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

impl Server {
    /// Starts `nvector serve` with a fresh database of the given backend.
    pub fn start_on(b: &Backend, extra: &[&str]) -> Server {
        match b {
            Backend::Sqlite => Server::start(extra),
            Backend::Postgres(c) => Server::start_with(temp_dir("http"), c.create_db(), extra),
        }
    }

    /// Starts `nvector serve` on 127.0.0.1:0 with a new database in a new
    /// temporary directory, plus extra flags.
    pub fn start(extra: &[&str]) -> Server {
        let dir = std::env::temp_dir().join(format!(
            "nvector-http-{}-{}",
            std::process::id(),
            uuid_like()
        ));
        std::fs::create_dir_all(&dir).unwrap();
        let db = format!("sqlite://{}", dir.join("nvector.db").display());
        Server::start_with(dir, db, extra)
    }

    /// Starts on an existing directory and database (restart tests).
    pub fn start_with(dir: PathBuf, db: String, extra: &[&str]) -> Server {
        Server::start_from(nvector(), dir, db, extra)
    }

    /// [`Server::start_with`], the service started by `command` (the
    /// `nvector` binary, or a wrapper that runs it, e.g. under a limit).
    pub fn start_from(mut command: Command, dir: PathBuf, db: String, extra: &[&str]) -> Server {
        let mut child = command
            .args([
                "serve",
                "--addr",
                "127.0.0.1:0",
                "--database",
                &db,
                "--static-dir",
            ])
            .arg(dir.join("www"))
            .args(extra)
            .env("RUST_LOG", "warn")
            .stdout(Stdio::piped())
            .stderr(Stdio::inherit())
            .spawn()
            .expect("start nvector serve");
        let stdout = child.stdout.take().unwrap();
        let mut line = String::new();
        BufReader::new(stdout).read_line(&mut line).unwrap();
        let addr = line
            .trim()
            .strip_prefix("nvector serving on http://")
            .unwrap_or_else(|| panic!("unexpected first line: {line}"))
            .to_string();
        Server {
            child,
            addr,
            dir,
            db,
        }
    }

    /// One request; returns (status, headers, body).
    pub fn raw(&self, request: &[u8]) -> (u16, String, Vec<u8>) {
        let mut s = TcpStream::connect(&self.addr).unwrap();
        s.set_read_timeout(Some(Duration::from_secs(60))).unwrap();
        s.write_all(request).unwrap();
        let mut buf = Vec::new();
        let _ = s.read_to_end(&mut buf);
        parse_response(&buf)
    }

    /// A request with an optional body and content type.
    pub fn req(
        &self,
        method: &str,
        path: &str,
        body: Option<(&str, &[u8])>,
        headers: &[(&str, &str)],
    ) -> (u16, String, Vec<u8>) {
        let mut r = format!(
            "{method} {path} HTTP/1.1\r\nHost: {}\r\nConnection: close\r\n",
            self.addr
        );
        for (k, v) in headers {
            r.push_str(&format!("{k}: {v}\r\n"));
        }
        let mut bytes = Vec::new();
        match body {
            Some((ctype, b)) => {
                r.push_str(&format!(
                    "Content-Type: {ctype}\r\nContent-Length: {}\r\n\r\n",
                    b.len()
                ));
                bytes.extend_from_slice(r.as_bytes());
                bytes.extend_from_slice(b);
            }
            None => {
                r.push_str("\r\n");
                bytes.extend_from_slice(r.as_bytes());
            }
        }
        self.raw(&bytes)
    }

    pub fn get(&self, path: &str) -> (u16, Value) {
        let (st, _, b) = self.req("GET", path, None, &[]);
        (st, serde_json::from_slice(&b).unwrap_or(Value::Null))
    }

    pub fn post(&self, path: &str, v: &Value) -> (u16, Value) {
        let body = v.to_string();
        let (st, _, b) = self.req(
            "POST",
            path,
            Some(("application/json", body.as_bytes())),
            &[],
        );
        (st, serde_json::from_slice(&b).unwrap_or(Value::Null))
    }

    /// The live worker processes of this service (its child processes, read
    /// from /proc: Linux only), by process id.
    pub fn worker_pids(&self) -> Vec<u32> {
        children_of(self.child.id())
    }

    /// Waits until `id` runs in a worker process other than those in
    /// `not`, and returns the job and that process's id.
    pub fn wait_running_in_worker(&self, id: &str, not: &[u32], limit: Duration) -> (Value, u32) {
        let start = Instant::now();
        loop {
            let (_, j) = self.get(&format!("/api/v1/jobs/{id}"));
            assert!(
                !matches!(j["state"].as_str(), Some("done" | "failed" | "cancelled")),
                "the job ended before the test could stop it: {j}"
            );
            if j["state"] == "running" {
                if let Some(pid) = self.worker_pids().into_iter().find(|p| !not.contains(p)) {
                    return (j, pid);
                }
            }
            assert!(
                start.elapsed() < limit,
                "job {id} not running in a new worker: {j}"
            );
            std::thread::sleep(Duration::from_millis(5));
        }
    }

    /// Polls a job until it ends.
    pub fn wait_job(&self, id: &str, limit: Duration) -> Value {
        let start = Instant::now();
        loop {
            let (st, j) = self.get(&format!("/api/v1/jobs/{id}"));
            assert_eq!(st, 200, "{j}");
            if matches!(j["state"].as_str(), Some("done" | "failed" | "cancelled")) {
                return j;
            }
            assert!(
                start.elapsed() < limit,
                "job {id} did not end in {limit:?}: {j}"
            );
            std::thread::sleep(Duration::from_millis(50));
        }
    }
}

impl Drop for Server {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// The live (not zombie) child processes of `parent`, from /proc.
pub fn children_of(parent: u32) -> Vec<u32> {
    let Ok(dir) = std::fs::read_dir("/proc") else {
        return Vec::new();
    };
    dir.flatten()
        .filter_map(|e| e.file_name().to_str()?.parse::<u32>().ok())
        .filter(|&pid| {
            // `pid (comm) state ppid ...`: the comm may hold spaces and
            // parentheses, so read after its last ')'.
            std::fs::read_to_string(format!("/proc/{pid}/stat")).is_ok_and(|stat| {
                let rest = stat.rsplit_once(')').map_or("", |(_, r)| r);
                let mut f = rest.split_whitespace();
                let state = f.next();
                let ppid = f.next().and_then(|p| p.parse::<u32>().ok());
                state != Some("Z") && ppid == Some(parent)
            })
        })
        .collect()
}

/// Whether a process runs (not a zombie), from /proc.
pub fn process_alive(pid: u32) -> bool {
    std::fs::read_to_string(format!("/proc/{pid}/stat")).is_ok_and(|stat| {
        let state = stat
            .rsplit_once(')')
            .map_or("", |(_, r)| r)
            .split_whitespace()
            .next();
        state != Some("Z")
    })
}

/// Sends SIGKILL to a process.
pub fn kill9(pid: u32) {
    let ok = Command::new("kill")
        .args(["-KILL", &pid.to_string()])
        .status()
        .expect("run kill");
    assert!(ok.success(), "kill -KILL {pid}");
}

fn uuid_like() -> String {
    static N: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(0);
    format!(
        "{:x}-{}",
        std::time::SystemTime::now()
            .duration_since(std::time::UNIX_EPOCH)
            .unwrap()
            .as_nanos(),
        N.fetch_add(1, std::sync::atomic::Ordering::SeqCst)
    )
}

/// Parses an HTTP/1.1 response (content-length or chunked).
pub fn parse_response(buf: &[u8]) -> (u16, String, Vec<u8>) {
    let split = buf
        .windows(4)
        .position(|w| w == b"\r\n\r\n")
        .expect("a complete response head");
    let head = String::from_utf8_lossy(&buf[..split]).to_string();
    let status: u16 = head.split_whitespace().nth(1).unwrap().parse().unwrap();
    let rest = &buf[split + 4..];
    let chunked = head
        .to_ascii_lowercase()
        .contains("transfer-encoding: chunked");
    let body = if chunked {
        let mut out = Vec::new();
        let mut i = 0;
        while i < rest.len() {
            let Some(eol) = rest[i..].windows(2).position(|w| w == b"\r\n") else {
                break;
            };
            let size = usize::from_str_radix(String::from_utf8_lossy(&rest[i..i + eol]).trim(), 16)
                .unwrap_or(0);
            i += eol + 2;
            if size == 0 {
                break;
            }
            out.extend_from_slice(&rest[i..(i + size).min(rest.len())]);
            i += size + 2;
        }
        out
    } else {
        rest.to_vec()
    };
    (status, head, body)
}

/// A small simulated paper mission.
pub fn small_mission(seed: u64, steps: usize) -> Value {
    let mut o = nvector_core::slam::simulate::SimulateOptions::new(
        nvector_core::slam::simulate::Scenario::Paper,
        seed,
    );
    o.steps = Some(steps);
    nvector_core::slam::simulate::simulate(&o)
}

/// The worst case of `exact`'s work limit: 40 overlapping boxes in 8-D
/// with integer bounds, n = 6 (minutes of search without a work budget),
/// as a contraction request, with `contractor` when given.
pub fn worst_case_contract(contractor: Option<&str>) -> Value {
    let mut state: u64 = 12;
    let mut unit = || {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    let boxes: Vec<Vec<[f64; 2]>> = (0..40)
        .map(|_| {
            (0..8)
                .map(|_| {
                    let c = (unit() * 10.0).round();
                    let a = (4.0 + unit() * 4.0).round();
                    let b = (4.0 + unit() * 4.0).round();
                    [c - a, c + b]
                })
                .collect()
        })
        .collect();
    let mut v = serde_json::json!({"format": "nvector-contract/1", "n": 6, "boxes": boxes});
    if let Some(c) = contractor {
        v["contractor"] = c.into();
    }
    v
}
