//! A throw-away PostgreSQL cluster for the tests: `initdb` into a temporary
//! directory, the server started with `pg_ctl` on a free loopback port
//! (as the `postgres` user when the tests run as root, since PostgreSQL
//! refuses to run as root), one fresh database per test server, and the
//! cluster stopped and deleted when the test process exits.
//!
//! Under CI (`CI=true`) a cluster that cannot start fails the test; elsewhere
//! the PostgreSQL tests are skipped with a loud message.

use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::OnceLock;

/// A running cluster.
pub struct PgCluster {
    pub dir: PathBuf,
    pub port: u16,
    bin: PathBuf,
    as_postgres: bool,
    next_db: AtomicUsize,
}

static CLUSTER: OnceLock<Result<PgCluster, String>> = OnceLock::new();

/// Runs `f` with the shared cluster, starting it on first use. Returns
/// false (after saying so on stderr) when PostgreSQL is unavailable outside
/// CI; panics under CI.
pub fn with_cluster(f: impl FnOnce(&PgCluster)) -> bool {
    match CLUSTER.get_or_init(start) {
        Ok(c) => {
            f(c);
            true
        }
        Err(e) => {
            if std::env::var("CI").is_ok_and(|v| v == "true") {
                panic!("PostgreSQL test cluster could not start under CI: {e}");
            }
            eprintln!(
                "\n!!!!! SKIPPED: PostgreSQL test cluster could not start: {e}\n\
                 !!!!! (install Debian's postgresql package; under CI=true this fails)\n"
            );
            false
        }
    }
}

fn is_root() -> bool {
    Command::new("id")
        .arg("-u")
        .output()
        .is_ok_and(|o| String::from_utf8_lossy(&o.stdout).trim() == "0")
}

/// The directory of `initdb`, `pg_ctl` and `psql`: the newest
/// /usr/lib/postgresql/*/bin, else whatever is on PATH.
fn bindir() -> Option<PathBuf> {
    let mut versions: Vec<(u32, PathBuf)> = std::fs::read_dir("/usr/lib/postgresql")
        .ok()?
        .filter_map(|e| e.ok())
        .filter_map(|e| {
            let v = e.file_name().to_string_lossy().parse().ok()?;
            let bin = e.path().join("bin");
            bin.join("initdb").exists().then_some((v, bin))
        })
        .collect();
    versions.sort();
    versions.pop().map(|(_, b)| b)
}

fn pg_command(bin: &Path, tool: &str, as_postgres: bool) -> Command {
    let exe = if bin.as_os_str().is_empty() {
        PathBuf::from(tool)
    } else {
        bin.join(tool)
    };
    if as_postgres {
        let mut c = Command::new("runuser");
        c.args(["-u", "postgres", "--"]).arg(exe);
        c
    } else {
        Command::new(exe)
    }
}

fn free_port() -> u16 {
    std::net::TcpListener::bind("127.0.0.1:0")
        .and_then(|l| l.local_addr())
        .map(|a| a.port())
        .unwrap_or(54329)
}

fn run(mut c: Command, what: &str) -> Result<(), String> {
    let out = c.output().map_err(|e| format!("{what}: {e}"))?;
    if out.status.success() {
        Ok(())
    } else {
        Err(format!(
            "{what} failed ({}): {}{}",
            out.status,
            String::from_utf8_lossy(&out.stdout),
            String::from_utf8_lossy(&out.stderr)
        ))
    }
}

fn start() -> Result<PgCluster, String> {
    let bin = bindir().unwrap_or_default();
    let as_postgres = is_root();
    let dir =
        std::env::temp_dir().join(format!("nvector-pg-{}-{}", std::process::id(), free_port()));
    std::fs::create_dir_all(&dir).map_err(|e| e.to_string())?;
    if as_postgres {
        run(
            {
                let mut c = Command::new("chown");
                c.arg("postgres:postgres").arg(&dir);
                c
            },
            "chown of the cluster directory to postgres",
        )?;
    }
    let data = dir.join("data");
    let mut c = pg_command(&bin, "initdb", as_postgres);
    c.args([
        "-A",
        "trust",
        "-U",
        "postgres",
        "-E",
        "UTF8",
        "--no-sync",
        "-D",
    ])
    .arg(&data);
    run(c, "initdb")?;
    let port = free_port();
    let mut c = pg_command(&bin, "pg_ctl", as_postgres);
    c.args(["start", "-w", "-t", "60", "-D"])
        .arg(&data)
        .arg("-l")
        .arg(dir.join("log"))
        .arg("-o")
        .arg(format!(
            "-p {port} -k {} -c listen_addresses=127.0.0.1 -c fsync=off \
             -c synchronous_commit=off -c max_connections=300",
            dir.display()
        ));
    if let Err(e) = run(c, "pg_ctl start") {
        let log = std::fs::read_to_string(dir.join("log")).unwrap_or_default();
        return Err(format!("{e}\nserver log:\n{log}"));
    }
    // A watchdog shell stops and deletes the cluster once this test
    // process has exited, however it exits (even on abort).
    let pg_ctl = if bin.as_os_str().is_empty() {
        PathBuf::from("pg_ctl")
    } else {
        bin.join("pg_ctl")
    };
    let stop = format!(
        "{} '{}' stop -m immediate -w -D '{}' >/dev/null 2>&1",
        if as_postgres {
            "runuser -u postgres --"
        } else {
            ""
        },
        pg_ctl.display(),
        data.display()
    );
    let script = format!(
        "while kill -0 {pid} 2>/dev/null; do sleep 0.5; done; {stop}; rm -rf '{dir}'",
        pid = std::process::id(),
        dir = dir.display()
    );
    Command::new("sh")
        .args(["-c", &script])
        .stdin(std::process::Stdio::null())
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .spawn()
        .map_err(|e| format!("starting the cluster watchdog: {e}"))?;
    Ok(PgCluster {
        dir,
        port,
        bin,
        as_postgres,
        next_db: AtomicUsize::new(0),
    })
}

impl PgCluster {
    /// The URL of a database of this cluster.
    pub fn url(&self, db: &str) -> String {
        format!("postgres://postgres@127.0.0.1:{}/{db}", self.port)
    }

    /// Runs SQL as the superuser on database `postgres`.
    pub fn psql(&self, sql: &str) -> Result<String, String> {
        let out = pg_command(&self.bin, "psql", false)
            .args([
                "-X",
                "-q",
                "-t",
                "-A",
                "-v",
                "ON_ERROR_STOP=1",
                "-h",
                "127.0.0.1",
            ])
            .args([
                "-p",
                &self.port.to_string(),
                "-U",
                "postgres",
                "-d",
                "postgres",
                "-c",
                sql,
            ])
            .output()
            .map_err(|e| format!("psql: {e}"))?;
        if out.status.success() {
            Ok(String::from_utf8_lossy(&out.stdout).to_string())
        } else {
            Err(String::from_utf8_lossy(&out.stderr).to_string())
        }
    }

    /// A new empty database; returns its URL.
    pub fn create_db(&self) -> String {
        let name = format!("t{}", self.next_db.fetch_add(1, Ordering::SeqCst));
        self.psql(&format!("CREATE DATABASE {name}"))
            .unwrap_or_else(|e| panic!("CREATE DATABASE {name}: {e}"));
        self.url(&name)
    }

    /// Whether the cluster runs as the `postgres` user.
    pub fn as_postgres(&self) -> bool {
        self.as_postgres
    }
}
