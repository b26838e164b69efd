//! Storage of missions and jobs behind one trait, with two real
//! implementations: SQLite (a database file, the default) and PostgreSQL
//! (several `nvector serve` processes sharing one queue). Migrations are
//! applied on open.
//!
//! Jobs form the queue. A worker claims the oldest queued job with one
//! atomic statement (`UPDATE ... RETURNING`; on PostgreSQL with
//! `FOR UPDATE SKIP LOCKED`), so a job runs once however many workers and
//! processes there are. A running job carries the id of the process that
//! runs it and a heartbeat that process refreshes; a job whose heartbeat is
//! older than the lease (its process died) goes back to the queue. Writes
//! about a running job (progress, result, re-queue) only apply while this
//! process still holds it, so a process that lost its lease cannot clobber
//! the job's next run.

mod postgres;
mod sqlite;

pub use self::postgres::PostgresStore;
pub use self::sqlite::SqliteStore;

/// A stored mission's summary.
#[derive(Debug, Clone)]
pub struct MissionRow {
    /// Id.
    pub id: String,
    /// Name from the mission.
    pub name: String,
    /// N.
    pub steps: i64,
    /// Number of detections.
    pub detections: i64,
    /// Creation time (ms since epoch).
    pub created: i64,
}

/// A job.
#[derive(Debug, Clone)]
pub struct JobRow {
    /// Id.
    pub id: String,
    /// Mission id.
    pub mission: String,
    /// queued, running, done, failed, cancelled.
    pub state: String,
    /// Contractor name.
    pub contractor: String,
    /// Most rounds.
    pub max_rounds: i64,
    /// Time limit (s).
    pub time_limit_s: f64,
    /// Progress: round.
    pub round: i64,
    /// Progress: max trajectory diameter.
    pub diameter: Option<f64>,
    /// Progress: fraction.
    pub fraction: f64,
    /// Error message when failed.
    pub error: Option<String>,
    /// How many times a worker claimed it (1 unless re-queued).
    pub attempts: i64,
    /// The process that runs or ran it.
    pub runner: Option<String>,
    /// Creation, start and end times (ms since epoch).
    pub created: i64,
    /// Start time.
    pub started: Option<i64>,
    /// End time.
    pub finished: Option<i64>,
}

/// Storage errors (the service answers 503/500 with no internals).
#[derive(Debug, thiserror::Error)]
#[error("storage: {0}")]
pub struct StoreError(pub String);

impl From<rusqlite::Error> for StoreError {
    fn from(e: rusqlite::Error) -> Self {
        StoreError(e.to_string())
    }
}

impl From<::postgres::Error> for StoreError {
    fn from(e: ::postgres::Error) -> Self {
        StoreError(e.to_string())
    }
}

/// A new process id for the jobs' `runner` column.
pub fn new_instance_id() -> String {
    uuid::Uuid::new_v4().simple().to_string()
}

/// The columns read into a [`JobRow`], in order.
pub const JOB_COLUMNS: &str = "id, mission, state, contractor, max_rounds, time_limit_s, round, \
     diameter, fraction, error, created, started, finished, attempts, runner";

/// Result alias.
pub type StoreResult<T> = Result<T, StoreError>;

/// Missions and jobs.
pub trait Store: Send + Sync {
    /// Whether the database answers.
    fn ping(&self) -> StoreResult<()>;
    /// Stores a mission (body = its JSON text).
    fn insert_mission(&self, owner: &str, row: &MissionRow, body: &str) -> StoreResult<()>;
    /// Missions of an owner, by creation, after an id, at most `limit`.
    fn list_missions(
        &self,
        owner: &str,
        after: Option<&str>,
        limit: i64,
    ) -> StoreResult<Vec<MissionRow>>;
    /// A mission's JSON text.
    fn mission_body(&self, owner: &str, id: &str) -> StoreResult<Option<String>>;
    /// A mission's JSON text, whoever owns it (for workers).
    fn mission_body_any(&self, id: &str) -> StoreResult<Option<String>>;
    /// Puts one job this process runs back in the queue (shutdown mid-job).
    fn requeue_one(&self, id: &str) -> StoreResult<()>;
    /// Deletes a mission and its jobs; false when absent.
    fn delete_mission(&self, owner: &str, id: &str) -> StoreResult<bool>;
    /// Queues a job.
    fn insert_job(&self, owner: &str, job: &JobRow) -> StoreResult<()>;
    /// A job.
    fn job(&self, owner: &str, id: &str) -> StoreResult<Option<JobRow>>;
    /// Number of queued jobs.
    fn queued_count(&self) -> StoreResult<i64>;
    /// Claims the oldest queued job for this process (state -> running),
    /// if any.
    fn claim_job(&self, now: i64) -> StoreResult<Option<JobRow>>;
    /// Refreshes the heartbeat of the jobs this process runs.
    fn heartbeat(&self, now: i64) -> StoreResult<()>;
    /// Puts back in the queue the running jobs whose heartbeat is older
    /// than `lease_ms` (their process died); returns how many.
    fn requeue_stale(&self, now: i64, lease_ms: i64) -> StoreResult<usize>;
    /// Records progress of a job this process runs.
    fn progress(&self, id: &str, round: i64, diameter: f64, fraction: f64) -> StoreResult<()>;
    /// Ends a job this process runs: state done/failed/cancelled, with its result or error.
    fn finish_job(
        &self,
        id: &str,
        state: &str,
        result: Option<&str>,
        error: Option<&str>,
        now: i64,
    ) -> StoreResult<()>;
    /// Marks a queued or running job cancelled; false when absent or ended.
    fn cancel_job(&self, owner: &str, id: &str, now: i64) -> StoreResult<Option<String>>;
    /// The state of a job (any owner), for workers checking cancellation.
    fn job_state(&self, id: &str) -> StoreResult<Option<String>>;
    /// A job's result JSON text.
    fn result(&self, owner: &str, id: &str) -> StoreResult<Option<String>>;
    /// This process's id, as stored in the jobs it runs.
    fn instance(&self) -> &str;
    /// Job counts by state.
    fn counts(&self) -> StoreResult<Vec<(String, i64)>>;
}

/// A summary of a mission value for listing.
pub fn mission_row(
    id: String,
    m: &nvector_core::slam::mission::Mission,
    created: i64,
) -> MissionRow {
    MissionRow {
        id,
        name: m.name.clone(),
        steps: m.steps as i64,
        detections: m.detections.len() as i64,
        created,
    }
}
