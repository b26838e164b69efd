//! The stored types (missions, jobs, their states and error codes) and the
//! [`Store`] trait the two backends implement; the backends import this,
//! never the facade, so that `store` has no import circle.

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
    /// Size of the stored mission JSON in bytes (when listed: the stored
    /// body's length).
    pub bytes: i64,
}

// As stored (the `state` column holds `JobState::as_str`: the same strings
// as before the type existed, so existing databases open) and as the API
// writes it.
/// The state of a job.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, utoipa::ToSchema)]
#[serde(rename_all = "lowercase")]
pub enum JobState {
    /// Waiting for a worker.
    Queued,
    /// Running.
    Running,
    /// Finished: the result is there (`error` says if a time limit cut it).
    Done,
    /// Failed (`error` says why).
    Failed,
    /// Cancelled.
    Cancelled,
}

impl JobState {
    /// Every state, in the order of the metrics.
    pub const ALL: [JobState; 5] = [
        JobState::Queued,
        JobState::Running,
        JobState::Done,
        JobState::Failed,
        JobState::Cancelled,
    ];

    /// The stored (and API) spelling.
    pub fn as_str(self) -> &'static str {
        match self {
            JobState::Queued => "queued",
            JobState::Running => "running",
            JobState::Done => "done",
            JobState::Failed => "failed",
            JobState::Cancelled => "cancelled",
        }
    }

    /// The state a stored string names.
    pub fn parse(s: &str) -> Option<JobState> {
        JobState::ALL.into_iter().find(|x| x.as_str() == s)
    }

    /// Whether the job has ended (done, failed or cancelled).
    pub fn is_terminal(self) -> bool {
        matches!(
            self,
            JobState::Done | JobState::Failed | JobState::Cancelled
        )
    }

    /// Whether the job may still be cancelled (queued or running).
    pub fn is_active(self) -> bool {
        !self.is_terminal()
    }
}

impl std::fmt::Display for JobState {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.as_str())
    }
}

/// A stored state that is none of [`JobState`]'s.
#[derive(Debug, thiserror::Error)]
#[error("unknown job state {0:?} in the database")]
pub struct UnknownState(pub String);

impl rusqlite::types::FromSql for JobState {
    fn column_result(v: rusqlite::types::ValueRef<'_>) -> rusqlite::types::FromSqlResult<Self> {
        let s = v.as_str()?;
        JobState::parse(s)
            .ok_or_else(|| rusqlite::types::FromSqlError::Other(Box::new(UnknownState(s.into()))))
    }
}

impl rusqlite::ToSql for JobState {
    fn to_sql(&self) -> rusqlite::Result<rusqlite::types::ToSqlOutput<'_>> {
        Ok(self.as_str().into())
    }
}

impl<'a> ::postgres::types::FromSql<'a> for JobState {
    fn from_sql(
        ty: &::postgres::types::Type,
        raw: &'a [u8],
    ) -> Result<Self, Box<dyn std::error::Error + Sync + Send>> {
        let s = <&str as ::postgres::types::FromSql>::from_sql(ty, raw)?;
        JobState::parse(s).ok_or_else(|| UnknownState(s.into()).into())
    }

    fn accepts(ty: &::postgres::types::Type) -> bool {
        <&str as ::postgres::types::FromSql>::accepts(ty)
    }
}

/// A job.
#[derive(Debug, Clone)]
pub struct JobRow {
    /// Id.
    pub id: String,
    /// Mission id.
    pub mission: String,
    /// Its state.
    pub state: JobState,
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
    /// A word a client can test when failed or cut short (`time_limit`,
    /// `memory_limit`, `worker_crashed`, `invalid_mission`, ...).
    pub error_code: Option<String>,
    /// How many times a worker claimed it (1 unless re-queued).
    pub attempts: i64,
    /// How many times the worker process running it died (abort, out of
    /// memory, killed): at `--job-attempts` it fails.
    pub crashes: i64,
    /// The cost estimate: the mission's steps × detections (at least 1).
    pub cost: i64,
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
     diameter, fraction, error, created, started, finished, attempts, runner, error_code, \
     crashes, cost";

/// Why a job failed or was cut short: a word a client can test and a
/// message a person can act on (the job's `error_code` and `error`).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct JobError {
    /// `time_limit`, `memory_limit`, `worker_crashed`, `invalid_mission`,
    /// `mission_deleted`, `internal`.
    pub code: &'static str,
    /// What happened, for a person.
    pub message: String,
}

/// How jobs enter the queue and in which order they leave it.
#[derive(Debug, Clone, Copy)]
pub struct QueuePolicy {
    /// Most queued jobs (of every process sharing the database).
    pub max_queue: i64,
    /// Jobs whose cost (steps × detections) is at most this are short.
    pub short_cost: i64,
    /// A long job is ordered as if submitted this much later (ms): short
    /// jobs submitted within that delay run first, and no long job waits
    /// behind short ones submitted after the delay.
    pub long_delay_ms: i64,
}

/// What queueing a job did.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Queued {
    /// The job is queued.
    Yes,
    /// The queue is full (nothing stored).
    Full,
    /// No such mission for this owner (nothing stored).
    NoMission,
}

/// The cost of a job on a mission: steps × detections (each at least 1),
/// as SQL over the `missions` row `m` (SQLite and PostgreSQL alike).
pub(crate) const COST_SQL: &str = "(CASE WHEN m.steps > 1 THEN m.steps ELSE 1 END) \
     * (CASE WHEN m.detections > 1 THEN m.detections ELSE 1 END)";

/// Result alias.
pub type StoreResult<T> = Result<T, StoreError>;

/// Missions and jobs.
pub trait Store: Send + Sync {
    /// Whether the database answers.
    fn ping(&self) -> StoreResult<()>;
    /// Stores a mission (body = its JSON text).
    fn insert_mission(&self, owner: &str, row: &MissionRow, body: &str) -> StoreResult<()>;
    /// Missions of an owner, by creation, after an id, at most `limit`.
    /// The id may be of a mission deleted since (its place is kept: a
    /// client paging through the list loses nothing when the last mission
    /// of its page is deleted); None when the owner never had it.
    fn list_missions(
        &self,
        owner: &str,
        after: Option<&str>,
        limit: i64,
    ) -> StoreResult<Option<Vec<MissionRow>>>;
    /// A mission's JSON text.
    fn mission_body(&self, owner: &str, id: &str) -> StoreResult<Option<String>>;
    /// A mission's JSON text, whoever owns it (for workers).
    fn mission_body_any(&self, id: &str) -> StoreResult<Option<String>>;
    /// Puts one job this process runs back in the queue (shutdown mid-job).
    fn requeue_one(&self, id: &str) -> StoreResult<()>;
    /// Records that the worker process running this job died: the job goes
    /// back to the queue, or fails with `error` once it has crashed
    /// `max_crashes` times. Returns its new state (None when this process
    /// no longer holds it).
    fn record_crash(
        &self,
        id: &str,
        error: &JobError,
        max_crashes: i64,
        now: i64,
    ) -> StoreResult<Option<JobState>>;
    /// Deletes a mission and its jobs; false when absent.
    fn delete_mission(&self, owner: &str, id: &str) -> StoreResult<bool>;
    /// Queues a job on a mission of `owner`, unless the queue holds
    /// `policy.max_queue` jobs already: one atomic step, whatever the
    /// number of concurrent submissions and processes.
    fn insert_job(&self, owner: &str, job: &JobRow, policy: &QueuePolicy) -> StoreResult<Queued>;
    /// A job.
    fn job(&self, owner: &str, id: &str) -> StoreResult<Option<JobRow>>;
    /// Claims the first queued job (by `queue_order`, then submission) of
    /// cost at most `max_cost` for this process (state -> running), if any.
    fn claim_job(&self, now: i64, max_cost: i64) -> StoreResult<Option<JobRow>>;
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
        state: JobState,
        result: Option<&str>,
        error: Option<&JobError>,
        now: i64,
    ) -> StoreResult<()>;
    /// Marks a queued or running job cancelled; false when absent or ended.
    fn cancel_job(&self, owner: &str, id: &str, now: i64) -> StoreResult<Option<JobState>>;
    /// The state of a job (any owner), for workers checking cancellation.
    fn job_state(&self, id: &str) -> StoreResult<Option<JobState>>;
    /// A job's result JSON text.
    fn result(&self, owner: &str, id: &str) -> StoreResult<Option<String>>;
    /// This process's id, as stored in the jobs it runs.
    fn instance(&self) -> &str;
    /// Job counts by state.
    fn counts(&self) -> StoreResult<Vec<(JobState, i64)>>;
}

/// A summary of a mission value for listing.
pub fn mission_row(
    id: String,
    m: &nvector_core::slam::mission::Mission,
    created: i64,
    bytes: usize,
) -> MissionRow {
    MissionRow {
        id,
        name: m.name.clone(),
        steps: m.steps as i64,
        detections: m.detections.len() as i64,
        created,
        bytes: bytes as i64,
    }
}

/// Why a job failed or was cut short, as a word: the workers store
/// [`JobErrorCode::as_str`], and a job's `error_code` is read back into it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, utoipa::ToSchema)]
#[serde(rename_all = "snake_case")]
pub enum JobErrorCode {
    /// The time limit stopped it: `done` with the partial, sound result, or
    /// `failed` when it did not stop within the grace period.
    TimeLimit,
    /// It needs more memory than the service's limit per job (the message
    /// names the limit); not retried.
    MemoryLimit,
    /// Its worker process died (abort, signal) as many times as the
    /// service's `--job-attempts`.
    WorkerCrashed,
    /// The stored mission could not be read.
    InvalidMission,
    /// The mission was deleted before the job ran.
    MissionDeleted,
    /// The service's own failure (storage, a bug).
    Internal,
}

impl JobErrorCode {
    /// Every code.
    pub const ALL: [JobErrorCode; 6] = [
        JobErrorCode::TimeLimit,
        JobErrorCode::MemoryLimit,
        JobErrorCode::WorkerCrashed,
        JobErrorCode::InvalidMission,
        JobErrorCode::MissionDeleted,
        JobErrorCode::Internal,
    ];

    /// The stored word.
    pub const fn as_str(self) -> &'static str {
        match self {
            JobErrorCode::TimeLimit => "time_limit",
            JobErrorCode::MemoryLimit => "memory_limit",
            JobErrorCode::WorkerCrashed => "worker_crashed",
            JobErrorCode::InvalidMission => "invalid_mission",
            JobErrorCode::MissionDeleted => "mission_deleted",
            JobErrorCode::Internal => "internal",
        }
    }

    /// The code of a stored word (`None` for a word no version wrote).
    pub fn parse(word: &str) -> Option<JobErrorCode> {
        JobErrorCode::ALL.into_iter().find(|c| c.as_str() == word)
    }
}
