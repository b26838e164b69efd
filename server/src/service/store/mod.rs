//! Storage of missions and jobs behind one trait, with two real
//! implementations: SQLite (a database file, the default) and PostgreSQL
//! (several `nvector serve` processes sharing one queue). Migrations are
//! applied on open.
//!
//! Jobs form the queue. A job is queued with one statement that also
//! checks the queue limit (on PostgreSQL under a transaction-scoped
//! advisory lock, so concurrent submissions of every process never
//! overshoot it), with its cost (the mission's steps × detections) and its
//! place in the queue (`queue_order`: the submission time, plus the long-job
//! delay for a job above the short-job cost: see [`QueuePolicy`]). A worker
//! claims the first queued job in that order with one atomic statement
//! (`UPDATE ... RETURNING`; on PostgreSQL with `FOR UPDATE SKIP LOCKED`),
//! so a job runs once however many workers and processes there are. A running job carries the id of the process that
//! runs it and a heartbeat that process refreshes; a job whose heartbeat is
//! older than the lease (its process died) goes back to the queue. Writes
//! about a running job (progress, result, re-queue) only apply while this
//! process still holds it, so a process that lost its lease cannot clobber
//! the job's next run.

mod postgres;
mod sqlite;
mod types;

pub use self::postgres::PostgresStore;
pub use self::sqlite::SqliteStore;
pub use self::types::{
    mission_row, JobError, JobErrorCode, JobRow, JobState, MissionRow, QueuePolicy, Queued, Store,
    StoreError, StoreResult,
};
