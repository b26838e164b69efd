//! `nvector serve`: the HTTP service and the web UI.

use crate::service::{self, Config, PoolConfig};
use crate::CliError;
use std::path::{Path, PathBuf};

/// Arguments of `nvector serve`.
#[derive(clap::Args)]
pub struct Args {
    /// Address to listen on.
    #[arg(long, default_value = "127.0.0.1:8080")]
    addr: std::net::SocketAddr,
    /// Storage: sqlite://PATH (created on first run) or
    /// `postgres://USER[:PASSWORD]@HOST:PORT/DB` (shared by several processes).
    #[arg(long, default_value = "sqlite://data/nvector.db")]
    database: String,
    /// Job workers, each running one job at a time in a worker process of
    /// its own (default: the number of cores; several services on one
    /// host: share the cores, see docs/deploy.md).
    #[arg(long)]
    workers: Option<usize>,
    /// Workers that run only short jobs, in addition to --workers.
    #[arg(long, default_value_t = 1)]
    short_lane_workers: usize,
    /// Jobs whose mission has at most this many steps × detections are
    /// short: they go ahead of long jobs and the short lane runs them.
    #[arg(long, default_value_t = service::config::DEFAULT_SHORT_JOB_COST)]
    short_job_cost: i64,
    /// A long job is queued as if submitted this many seconds later (short
    /// jobs submitted meanwhile go first; none waits longer behind them).
    #[arg(long, default_value_t = 60.0)]
    long_job_delay: f64,
    /// Memory limit of each worker process (e.g. 512MiB, 2GiB; `none`: no
    /// limit). Default: 7/8 of the machine's memory shared by the worker
    /// processes (--workers + --short-lane-workers).
    #[arg(long)]
    job_memory_limit: Option<String>,
    /// A job whose worker process dies (abort, killed) this many times
    /// fails (`worker_crashed`); a job over the memory limit fails at once.
    #[arg(long, default_value_t = 2)]
    job_attempts: u32,
    /// Directory of the page (default: the first of ./web/www, the
    /// repository's web/www beside the binary's target/ directory, www/ or
    /// ../share/nvector/www beside the binary, that holds index.html; the
    /// one chosen is logged at start).
    #[arg(long)]
    static_dir: Option<PathBuf>,
    /// File with one API key per line (enables authentication).
    #[arg(long)]
    api_key_file: Option<PathBuf>,
    /// Allowed CORS origin (repeat; CORS is off without it).
    #[arg(long = "cors-origin")]
    cors_origins: Vec<String>,
    /// Largest request body in bytes.
    #[arg(long, default_value_t = 64 << 20)]
    max_body: usize,
    /// Most steps in a mission.
    #[arg(long, default_value_t = 2_000_000)]
    max_steps: usize,
    /// Most detections in a mission.
    #[arg(long, default_value_t = 100_000)]
    max_detections: usize,
    /// Most queued jobs (then 429 with Retry-After).
    #[arg(long, default_value_t = 1000)]
    max_queue: i64,
    /// Job time limit in seconds (default and largest allowed).
    #[arg(long, default_value_t = 300.0)]
    job_time_limit: f64,
    /// Seconds a running job may go without its process's heartbeat before
    /// another process (or the next start) re-queues it.
    #[arg(long, default_value_t = 10.0)]
    job_lease: f64,
    /// Time limit in seconds of one POST /api/v1/contract (the exact
    /// contractor is stopped there: 422 work_limit).
    #[arg(long, default_value_t = 10.0)]
    contract_time_limit: f64,
}

/// Where the page may be, in order: `./web/www` (started from the
/// repository), the repository's `web/www` seen from the binary
/// (`REPO/target/PROFILE/nvector`), then `www/` and `../share/nvector/www`
/// beside the binary (an installed copy).
pub fn page_candidates(exe: Option<&Path>) -> Vec<PathBuf> {
    let mut dirs = vec![PathBuf::from("web/www")];
    if let Some(bin_dir) = exe.and_then(Path::parent) {
        for up in [2, 3] {
            // target/debug/nvector -> REPO; target/x86_64-.../release/nvector -> REPO.
            if let Some(repo) = bin_dir.ancestors().nth(up) {
                dirs.push(repo.join("web/www"));
            }
        }
        dirs.push(bin_dir.join("www"));
        dirs.push(bin_dir.join("../share/nvector/www"));
    }
    dirs
}

/// The page's directory: the one given, else the first candidate holding
/// `index.html`; `Err` lists where it looked (the service then answers `/`
/// with a short page saying how to build it).
pub fn resolve_static_dir(given: Option<PathBuf>) -> Result<PathBuf, (PathBuf, Vec<PathBuf>)> {
    if let Some(dir) = given {
        return if dir.join("index.html").is_file() {
            Ok(dir)
        } else {
            Err((dir.clone(), vec![dir]))
        };
    }
    let exe = std::env::current_exe()
        .ok()
        .and_then(|p| p.canonicalize().ok());
    let candidates = page_candidates(exe.as_deref());
    match candidates.iter().find(|d| d.join("index.html").is_file()) {
        Some(d) => Ok(d.canonicalize().unwrap_or_else(|_| d.clone())),
        None => Err((candidates[0].clone(), candidates)),
    }
}

/// The API keys of `--api-key-file` (one a line; blank lines and `#`
/// comments skipped), none without it.
fn api_keys(a: &Args) -> Result<Vec<String>, CliError> {
    let Some(p) = &a.api_key_file else {
        return Ok(Vec::new());
    };
    Ok(std::fs::read_to_string(p)
        .map_err(|e| CliError(format!("reading {}: {e}", p.display())))?
        .lines()
        .map(str::trim)
        .filter(|l| !l.is_empty() && !l.starts_with('#'))
        .map(str::to_string)
        .collect())
}

/// Refuses the job limits out of their ranges, naming the flag.
fn check_limits(a: &Args) -> Result<(), CliError> {
    if a.job_time_limit.is_nan() || a.job_time_limit <= 0.0 {
        return Err(CliError("--job-time-limit must be > 0".into()));
    }
    if a.job_lease.is_nan() || a.job_lease < 0.1 || a.job_lease > 86_400.0 {
        return Err(CliError(
            "--job-lease must be between 0.1 and 86400 s".into(),
        ));
    }
    if !(a.contract_time_limit > 0.0 && a.contract_time_limit <= 86_400.0) {
        return Err(CliError(
            "--contract-time-limit must be in (0, 86400] s".into(),
        ));
    }
    if !(a.long_job_delay >= 0.0 && a.long_job_delay <= 86_400.0) {
        return Err(CliError(
            "--long-job-delay must be between 0 and 86400 s".into(),
        ));
    }
    if a.short_job_cost < 0 {
        return Err(CliError("--short-job-cost must be >= 0".into()));
    }
    if !(1..=100).contains(&a.job_attempts) {
        return Err(CliError("--job-attempts must be between 1 and 100".into()));
    }
    Ok(())
}

/// The worker pool: worker counts, the job memory limit (never above an
/// address-space limit the service was started under: `ulimit -v`), the
/// attempts and the short lane's cost.
fn pool_config(a: &Args) -> Result<PoolConfig, CliError> {
    let workers = a
        .workers
        .unwrap_or_else(|| std::thread::available_parallelism().map_or(2, |n| n.get()));
    let memory_limit = match a.job_memory_limit.as_deref() {
        None => service::default_job_memory(workers + a.short_lane_workers),
        Some("none" | "unlimited") => None,
        Some(text) => {
            let bytes = service::parse_size(text)
                .map_err(|e| CliError(format!("--job-memory-limit: {e}")))?;
            if bytes < service::MIN_JOB_MEMORY {
                return Err(CliError(format!(
                    "--job-memory-limit must be at least {}",
                    service::format_size(service::MIN_JOB_MEMORY)
                )));
            }
            Some(bytes)
        }
    };
    let memory_limit = match (memory_limit, service::job_runner::inherited_memory_limit()) {
        (Some(l), Some(h)) => Some(l.min(h)),
        (None, h) => h,
        (l, None) => l,
    };
    Ok(PoolConfig {
        workers,
        short_lane_workers: a.short_lane_workers,
        memory_limit,
        attempts: a.job_attempts,
        short_cost: a.short_job_cost,
    })
}

/// The page's directory, logged; when missing, a warning naming where it
/// was looked for (the API and its reference are served all the same).
fn page_dir(given: Option<PathBuf>) -> PathBuf {
    match resolve_static_dir(given) {
        Ok(dir) => {
            tracing::info!(
                "serving the page from {} (the API reference at /api/docs)",
                dir.display()
            );
            dir
        }
        Err((dir, looked)) => {
            let looked: Vec<String> = looked.iter().map(|d| d.display().to_string()).collect();
            tracing::warn!(
                "the page is missing: no index.html in {}; build it with `make run` (or \
                 scripts/web.sh build) or pass --static-dir; / answers with a note, the API \
                 and /api/docs are served",
                looked.join(", ")
            );
            dir
        }
    }
}

/// Runs the subcommand.
pub fn run(a: Args) -> Result<(), CliError> {
    tracing_subscriber::fmt()
        .with_env_filter(
            tracing_subscriber::EnvFilter::try_from_default_env().unwrap_or_else(|_| "info".into()),
        )
        .with_writer(std::io::stderr)
        .init();
    let api_keys = api_keys(&a)?;
    check_limits(&a)?;
    let pool = pool_config(&a)?;
    let config = Config {
        max_body: a.max_body,
        max_steps: a.max_steps,
        max_detections: a.max_detections,
        max_queue: a.max_queue,
        job_time_limit_s: a.job_time_limit,
        static_dir: page_dir(a.static_dir),
        api_keys: api_keys.into_iter().collect(),
        cors_origins: a.cors_origins,
        job_lease: std::time::Duration::from_secs_f64(a.job_lease),
        contract_time_limit: std::time::Duration::from_secs_f64(a.contract_time_limit),
        short_job_cost: a.short_job_cost,
        long_job_delay: std::time::Duration::from_secs_f64(a.long_job_delay),
    };
    tracing::info!(
        "{} worker(s) and {} short-lane worker(s), job memory limit {}",
        pool.workers,
        pool.short_lane_workers,
        pool.memory_limit
            .map_or_else(|| "none".to_string(), service::format_size)
    );
    let store = service::open_store(&a.database, pool.workers + a.short_lane_workers + 4)
        .map_err(CliError)?;
    let rt = tokio::runtime::Builder::new_multi_thread()
        .enable_all()
        .build()
        .map_err(|e| CliError(format!("starting the runtime: {e}")))?;
    rt.block_on(service::serve(a.addr, store, config, pool))
        .map_err(CliError)
}
