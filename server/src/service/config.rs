//! Configuration of the service: the flags of `nvector serve` and their
//! defaults (docs/api.md, "Limits"), and the sizes they are written in.

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
    /// Jobs whose mission has at most this many steps × detections are
    /// short: they go ahead of long jobs, and the short lane's workers run
    /// only them.
    pub short_job_cost: i64,
    /// A long job is queued as if submitted this much later.
    pub long_job_delay: std::time::Duration,
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
            short_job_cost: DEFAULT_SHORT_JOB_COST,
            long_job_delay: std::time::Duration::from_secs(60),
        }
    }
}

/// The default short-job cost (steps × detections): simulated paper
/// missions up to 10,000 steps (44 detections, 4.4·10^5) and the AUV
/// survey (60,000 steps, 14 detections, 8.4·10^5) are short; a
/// 100,000-step paper mission (4.5·10^7) and CMU Plaza (9657 steps, 3529
/// ranges, 3.4·10^7; 8 s with `best`) are long.
pub const DEFAULT_SHORT_JOB_COST: i64 = 1_000_000;

/// The smallest job memory limit accepted: below it a worker process could
/// not even read a small mission.
pub const MIN_JOB_MEMORY: u64 = 16 << 20;

/// Reads a size: a number of bytes with an optional unit, `B`, `KiB`,
/// `MiB`, `GiB`, `TiB` (powers of 1024; `K`, `M`, `G`, `T` alone mean the
/// same) or `kB`, `MB`, `GB`, `TB` (powers of 1000), case-insensitive, with
/// an optional fraction (`1.5GiB`). Errors name the text.
pub fn parse_size(text: &str) -> Result<u64, String> {
    let t = text.trim();
    let split = t
        .find(|c: char| !(c.is_ascii_digit() || c == '.'))
        .unwrap_or(t.len());
    let (number, unit) = (&t[..split], t[split..].trim());
    let factor: f64 = match unit.to_ascii_lowercase().as_str() {
        "" | "b" => 1.0,
        "k" | "kib" => 1024.0,
        "m" | "mib" => 1024.0 * 1024.0,
        "g" | "gib" => 1024.0 * 1024.0 * 1024.0,
        "t" | "tib" => 1024.0 * 1024.0 * 1024.0 * 1024.0,
        "kb" => 1e3,
        "mb" => 1e6,
        "gb" => 1e9,
        "tb" => 1e12,
        _ => {
            return Err(format!(
                "unknown unit '{unit}' in size '{text}' (expected B, KiB, MiB, GiB, TiB, kB, MB, GB or TB)"
            ))
        }
    };
    let value: f64 = number
        .parse()
        .map_err(|_| format!("expected a size such as 512MiB or 2GiB, found '{text}'"))?;
    let bytes = (value * factor).floor();
    if !(bytes.is_finite() && bytes < u64::MAX as f64) {
        return Err(format!("size '{text}' is too large"));
    }
    Ok(bytes as u64)
}

/// A size for a person: whole GiB, MiB or KiB when exact, else bytes.
pub fn format_size(bytes: u64) -> String {
    for (unit, size) in [
        ("TiB", 1u64 << 40),
        ("GiB", 1 << 30),
        ("MiB", 1 << 20),
        ("KiB", 1 << 10),
    ] {
        // The sizes are powers of two: a multiple has no lower bits set.
        if bytes >= size && bytes & (size - 1) == 0 {
            return format!("{} {unit}", bytes / size);
        }
    }
    if bytes >= 1 << 20 {
        return format!("{:.1} MiB", bytes as f64 / (1u64 << 20) as f64);
    }
    format!("{bytes} bytes")
}

/// The machine's memory (bytes), from `/proc/meminfo` (`MemTotal`); None
/// where that file is not there.
pub fn total_memory() -> Option<u64> {
    let text = std::fs::read_to_string("/proc/meminfo").ok()?;
    let line = text.lines().find(|l| l.starts_with("MemTotal:"))?;
    let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    kib.checked_mul(1024)
}

/// The default job memory limit: the machine's memory shared by the
/// worker processes, less an eighth kept for the HTTP process and the
/// system, rounded down to a MiB; None (no limit) where the memory is
/// unknown.
pub fn default_job_memory(worker_processes: usize) -> Option<u64> {
    let total = total_memory()?;
    let share = total / 8 * 7 / worker_processes.max(1) as u64;
    Some((share >> 20 << 20).max(MIN_JOB_MEMORY))
}

/// The threads a solve may use when none is asked for: the machine's
/// available parallelism (1 when it cannot be read). Core reads nothing
/// of the machine; its `SolveOptions::threads` comes from here (`nvector
/// run`, `bench`, the service's jobs).
pub fn machine_threads() -> usize {
    std::thread::available_parallelism().map_or(1, |n| n.get())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes_read_with_their_units() {
        assert_eq!(parse_size("512MiB"), Ok(512 << 20));
        assert_eq!(parse_size("2GiB"), Ok(2 << 30));
        assert_eq!(parse_size("2 gib"), Ok(2 << 30));
        assert_eq!(parse_size("64M"), Ok(64 << 20));
        assert_eq!(parse_size("1.5GiB"), Ok(3 << 29));
        assert_eq!(parse_size("1GB"), Ok(1_000_000_000));
        assert_eq!(parse_size("4096"), Ok(4096));
        assert!(parse_size("12 parsecs")
            .unwrap_err()
            .contains("unknown unit"));
        assert!(parse_size("MiB").unwrap_err().contains("expected a size"));
        assert!(parse_size("1e300GiB").is_err());
        assert!(parse_size("-1GiB").is_err());
    }

    #[test]
    fn sizes_print_in_the_largest_exact_unit() {
        assert_eq!(format_size(64 << 20), "64 MiB");
        assert_eq!(format_size(3 << 30), "3 GiB");
        assert_eq!(format_size(3 << 29), "1536 MiB");
        assert_eq!(format_size(1000), "1000 bytes");
        assert_eq!(format_size((1 << 20) + 1), "1.0 MiB");
    }
}
