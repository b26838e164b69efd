//! Configuration of the service: the flags of `nvector serve` and their
//! defaults (spec/api.md, "Limits").

use std::collections::HashSet;

/// Service configuration (flags of `nvector serve`).
#[derive(Debug, Clone)]
pub struct Config {
    /// Largest request body (bytes).
    pub max_body: usize,
    /// Most steps in a mission.
    pub max_steps: usize,
    /// Most detections in a mission.
    pub max_detections: usize,
    /// Most queued jobs (then 429).
    pub max_queue: i64,
    /// Default and largest job time limit (s).
    pub job_time_limit_s: f64,
    /// Directory of the page.
    pub static_dir: std::path::PathBuf,
    /// API keys (empty: no authentication).
    pub api_keys: HashSet<String>,
    /// Allowed CORS origins (empty: CORS off).
    pub cors_origins: Vec<String>,
    /// How long a running job may go without its process's heartbeat
    /// before it is re-queued.
    pub job_lease: std::time::Duration,
    /// Time limit of one `POST /api/v1/contract`: the exact contractor is
    /// cancelled at this deadline and the request answered 422
    /// (`work_limit`).
    pub contract_time_limit: std::time::Duration,
}

impl Default for Config {
    fn default() -> Self {
        Config {
            max_body: 64 << 20,
            max_steps: 2_000_000,
            max_detections: 100_000,
            max_queue: 1000,
            job_time_limit_s: 300.0,
            static_dir: "web/www".into(),
            api_keys: HashSet::new(),
            cors_origins: Vec::new(),
            job_lease: std::time::Duration::from_secs(10),
            contract_time_limit: std::time::Duration::from_secs(10),
        }
    }
}
