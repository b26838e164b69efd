//! PostgreSQL storage: several `nvector serve` processes on one database
//! share the missions and the job queue. A job is claimed with
//! `FOR UPDATE SKIP LOCKED`, so concurrent workers of every process each
//! take a different queued job and never wait for each other.
//!
//! Connections come from a small fixed pool (one per worker plus a few for
//! the HTTP handlers); a broken connection is dropped and reopened on the
//! next use. The schema is created on open, under an advisory lock so that
//! processes starting together do not race.

use super::types::{
    JobError, JobRow, JobState, MissionRow, QueuePolicy, Queued, Store, StoreError, StoreResult,
    COST_SQL, JOB_COLUMNS,
};
use postgres::{Client, NoTls, Row};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;

/// Schema versions, applied in order; `schema_version` holds how many ran.
const MIGRATIONS: &[&str] = &[
    "CREATE TABLE missions (
        seq BIGSERIAL UNIQUE, id TEXT PRIMARY KEY, owner TEXT NOT NULL, name TEXT NOT NULL,
        steps BIGINT NOT NULL, detections BIGINT NOT NULL, body TEXT NOT NULL,
        created BIGINT NOT NULL);
     CREATE INDEX missions_owner ON missions (owner, seq);
     CREATE TABLE jobs (
        seq BIGSERIAL UNIQUE, id TEXT PRIMARY KEY, owner TEXT NOT NULL, mission TEXT NOT NULL,
        state TEXT NOT NULL, contractor TEXT NOT NULL, max_rounds BIGINT NOT NULL,
        time_limit_s DOUBLE PRECISION NOT NULL, round BIGINT NOT NULL DEFAULT 0,
        diameter DOUBLE PRECISION, fraction DOUBLE PRECISION NOT NULL DEFAULT 0,
        error TEXT, result TEXT, created BIGINT NOT NULL, started BIGINT, finished BIGINT,
        runner TEXT, heartbeat BIGINT, attempts BIGINT NOT NULL DEFAULT 0);
     CREATE INDEX jobs_state ON jobs (state, seq);
     CREATE INDEX jobs_mission ON jobs (mission);",
    // Missions and results are large JSON texts: lz4 compresses them several
    // times faster than PostgreSQL's default pglz. Servers built without lz4
    // keep the default.
    "DO $$ BEGIN
        ALTER TABLE missions ALTER COLUMN body SET COMPRESSION lz4;
        ALTER TABLE jobs ALTER COLUMN result SET COMPRESSION lz4;
     EXCEPTION WHEN OTHERS THEN NULL;
     END $$;",
    // Worker processes: why a job failed as a word, how often
    // its worker died, its cost and its place in the queue.
    "ALTER TABLE jobs ADD COLUMN error_code TEXT,
        ADD COLUMN crashes BIGINT NOT NULL DEFAULT 0,
        ADD COLUMN cost BIGINT NOT NULL DEFAULT 1,
        ADD COLUMN queue_order BIGINT NOT NULL DEFAULT 0;
     UPDATE jobs SET queue_order = created, cost = COALESCE((SELECT
         (CASE WHEN m.steps > 1 THEN m.steps ELSE 1 END)
         * (CASE WHEN m.detections > 1 THEN m.detections ELSE 1 END)
         FROM missions m WHERE m.id = jobs.mission), 1);
     CREATE INDEX jobs_queue ON jobs (state, queue_order, seq);",
    // The places of deleted missions, for paging cursors (`list_missions`).
    "CREATE TABLE deleted_missions (
        id TEXT PRIMARY KEY, owner TEXT NOT NULL, seq BIGINT NOT NULL);",
];

/// An arbitrary key for `pg_advisory_xact_lock` around migrations.
const MIGRATION_LOCK: i64 = 0x006e_7665_6374_6f72;

/// The key of `pg_advisory_xact_lock` around queueing a job: the queue
/// limit's count and the insert happen under it, so submissions of every
/// process are serialised there (a short transaction: one count on the
/// `jobs_state` index, one insert).
const QUEUE_LOCK: i64 = 0x006e_7665_6371_7565;

/// PostgreSQL storage.
pub struct PostgresStore {
    url: String,
    pool: Vec<Mutex<Option<Client>>>,
    next: AtomicUsize,
    instance: String,
}

impl PostgresStore {
    /// Connects (`postgres://user@host:port/db`), creates or upgrades the
    /// schema, and keeps up to `pool_size` connections.
    pub fn open(url: &str, pool_size: usize) -> StoreResult<PostgresStore> {
        let mut client = Client::connect(url, NoTls)
            .map_err(|e| StoreError(format!("connecting to PostgreSQL: {e}")))?;
        {
            let mut tx = client.transaction()?;
            tx.execute("SELECT pg_advisory_xact_lock($1)", &[&MIGRATION_LOCK])?;
            tx.batch_execute(
                "CREATE TABLE IF NOT EXISTS schema_version (version BIGINT NOT NULL)",
            )?;
            let version: i64 = match tx.query_opt("SELECT version FROM schema_version", &[])? {
                Some(r) => r.get(0),
                None => {
                    tx.execute("INSERT INTO schema_version VALUES (0)", &[])?;
                    0
                }
            };
            for m in MIGRATIONS.iter().skip(version.max(0) as usize) {
                tx.batch_execute(m)?;
            }
            tx.execute(
                "UPDATE schema_version SET version = $1",
                &[&(MIGRATIONS.len() as i64)],
            )?;
            tx.commit()?;
        }
        let pool: Vec<Mutex<Option<Client>>> =
            (0..pool_size.max(1)).map(|_| Mutex::new(None)).collect();
        if let Ok(mut first) = pool[0].lock() {
            *first = Some(client);
        }
        Ok(PostgresStore {
            url: url.to_string(),
            pool,
            next: AtomicUsize::new(0),
            instance: super::types::new_instance_id(),
        })
    }

    /// Runs `f` on a pooled connection: a free one if any, else waits for
    /// one in turn. A connection that broke is reopened.
    fn with<T>(&self, f: impl FnOnce(&mut Client) -> Result<T, postgres::Error>) -> StoreResult<T> {
        let n = self.pool.len();
        let start = self.next.fetch_add(1, Ordering::Relaxed) % n;
        let mut guard = (0..n)
            .find_map(|i| self.pool[(start + i) % n].try_lock().ok())
            .map_or_else(|| self.pool[start].lock(), Ok)
            .map_err(|_| StoreError("poisoned connection".into()))?;
        if guard.as_ref().is_none_or(Client::is_closed) {
            *guard = Some(
                Client::connect(&self.url, NoTls)
                    .map_err(|e| StoreError(format!("connecting to PostgreSQL: {e}")))?,
            );
        }
        let client = guard.as_mut().expect("connection just opened");
        let out = f(client);
        if out.is_err() && client.is_closed() {
            *guard = None;
        }
        Ok(out?)
    }
}

fn job_from_row(r: &Row) -> JobRow {
    JobRow {
        id: r.get(0),
        mission: r.get(1),
        state: r.get(2),
        contractor: r.get(3),
        max_rounds: r.get(4),
        time_limit_s: r.get(5),
        round: r.get(6),
        diameter: r.get(7),
        fraction: r.get(8),
        error: r.get(9),
        created: r.get(10),
        started: r.get(11),
        finished: r.get(12),
        attempts: r.get(13),
        runner: r.get(14),
        error_code: r.get(15),
        crashes: r.get(16),
        cost: r.get(17),
    }
}

impl Store for PostgresStore {
    fn ping(&self) -> StoreResult<()> {
        self.with(|c| c.simple_query("SELECT 1").map(|_| ()))
    }

    fn insert_mission(&self, owner: &str, m: &MissionRow, body: &str) -> StoreResult<()> {
        self.with(|c| {
            c.execute(
                "INSERT INTO missions (id, owner, name, steps, detections, body, created)
                 VALUES ($1, $2, $3, $4, $5, $6, $7)",
                &[
                    &m.id,
                    &owner,
                    &m.name,
                    &m.steps,
                    &m.detections,
                    &body,
                    &m.created,
                ],
            )
            .map(|_| ())
        })
    }

    fn list_missions(
        &self,
        owner: &str,
        after: Option<&str>,
        limit: i64,
    ) -> StoreResult<Option<Vec<MissionRow>>> {
        self.with(|c| {
            let after_seq: i64 = match after {
                Some(a) => match c.query_opt(
                    "SELECT seq FROM missions WHERE id = $1 AND owner = $2
                     UNION ALL
                     SELECT seq FROM deleted_missions WHERE id = $1 AND owner = $2",
                    &[&a, &owner],
                )? {
                    Some(r) => r.get(0),
                    None => return Ok(None),
                },
                None => 0,
            };
            let rows = c.query(
                "SELECT id, name, steps, detections, created, octet_length(body)::BIGINT FROM missions
                 WHERE owner = $1 AND seq > $2 AND id NOT LIKE 't-%' ORDER BY seq LIMIT $3",
                &[&owner, &after_seq, &limit],
            )?;
            Ok(Some(
                rows.iter()
                    .map(|r| MissionRow {
                        id: r.get(0),
                        name: r.get(1),
                        steps: r.get(2),
                        detections: r.get(3),
                        created: r.get(4),
                        bytes: r.get(5),
                    })
                    .collect(),
            ))
        })
    }

    fn mission_body(&self, owner: &str, id: &str) -> StoreResult<Option<String>> {
        self.with(|c| {
            Ok(c.query_opt(
                "SELECT body FROM missions WHERE id = $1 AND owner = $2",
                &[&id, &owner],
            )?
            .map(|r| r.get(0)))
        })
    }

    fn mission_body_any(&self, id: &str) -> StoreResult<Option<String>> {
        self.with(|c| {
            Ok(
                c.query_opt("SELECT body FROM missions WHERE id = $1", &[&id])?
                    .map(|r| r.get(0)),
            )
        })
    }

    fn requeue_one(&self, id: &str) -> StoreResult<()> {
        self.with(|c| {
            c.execute(
                "UPDATE jobs SET state = 'queued', started = NULL, runner = NULL
                 WHERE id = $1 AND state = 'running' AND runner = $2",
                &[&id, &self.instance],
            )
            .map(|_| ())
        })
    }

    fn delete_mission(&self, owner: &str, id: &str) -> StoreResult<bool> {
        self.with(|c| {
            let mut tx = c.transaction()?;
            tx.execute(
                "INSERT INTO deleted_missions (id, owner, seq)
                 SELECT id, owner, seq FROM missions WHERE id = $1 AND owner = $2
                 ON CONFLICT (id) DO NOTHING",
                &[&id, &owner],
            )?;
            let n = tx.execute(
                "DELETE FROM missions WHERE id = $1 AND owner = $2",
                &[&id, &owner],
            )?;
            if n > 0 {
                tx.execute("DELETE FROM jobs WHERE mission = $1", &[&id])?;
            }
            tx.commit()?;
            Ok(n > 0)
        })
    }

    fn insert_job(&self, owner: &str, j: &JobRow, policy: &QueuePolicy) -> StoreResult<Queued> {
        self.with(|c| {
            let mut tx = c.transaction()?;
            // Held to the commit: the next submission's count (a new
            // snapshot, taken after it gets the lock) sees this insert.
            tx.execute("SELECT pg_advisory_xact_lock($1)", &[&QUEUE_LOCK])?;
            let n = tx.execute(
                &format!(
                    "INSERT INTO jobs (id, owner, mission, state, contractor, max_rounds,
                        time_limit_s, created, cost, queue_order)
                     SELECT $1::TEXT, $2::TEXT, m.id, 'queued', $4::TEXT, $5::BIGINT,
                        $6::DOUBLE PRECISION, $7::BIGINT, {COST_SQL},
                        $7::BIGINT + CASE WHEN {COST_SQL} > $9::BIGINT THEN $10::BIGINT ELSE 0 END
                     FROM missions m
                     WHERE m.id = $3::TEXT AND m.owner = $2::TEXT
                       AND (SELECT COUNT(*) FROM jobs WHERE state = 'queued') < $8::BIGINT"
                ),
                &[
                    &j.id,
                    &owner,
                    &j.mission,
                    &j.contractor,
                    &j.max_rounds,
                    &j.time_limit_s,
                    &j.created,
                    &policy.max_queue,
                    &policy.short_cost,
                    &policy.long_delay_ms,
                ],
            )?;
            let outcome = if n > 0 {
                Queued::Yes
            } else if tx
                .query_opt(
                    "SELECT 1 FROM missions WHERE id = $1 AND owner = $2",
                    &[&j.mission, &owner],
                )?
                .is_some()
            {
                Queued::Full
            } else {
                Queued::NoMission
            };
            tx.commit()?;
            Ok(outcome)
        })
    }

    fn job(&self, owner: &str, id: &str) -> StoreResult<Option<JobRow>> {
        self.with(|c| {
            Ok(c.query_opt(
                &format!("SELECT {JOB_COLUMNS} FROM jobs WHERE id = $1 AND owner = $2"),
                &[&id, &owner],
            )?
            .map(|r| job_from_row(&r)))
        })
    }

    fn claim_job(&self, now: i64, max_cost: i64) -> StoreResult<Option<JobRow>> {
        self.with(|c| {
            Ok(c.query_opt(
                &format!(
                    "UPDATE jobs SET state = 'running', started = $1, heartbeat = $1,
                     runner = $2, attempts = attempts + 1
                     WHERE id = (SELECT id FROM jobs WHERE state = 'queued' AND cost <= $3::BIGINT
                                 ORDER BY queue_order, seq
                                 LIMIT 1 FOR UPDATE SKIP LOCKED)
                       AND state = 'queued'
                     RETURNING {JOB_COLUMNS}"
                ),
                &[&now, &self.instance, &max_cost],
            )?
            .map(|r| job_from_row(&r)))
        })
    }

    fn heartbeat(&self, now: i64) -> StoreResult<()> {
        self.with(|c| {
            c.execute(
                "UPDATE jobs SET heartbeat = $1 WHERE state = 'running' AND runner = $2",
                &[&now, &self.instance],
            )
            .map(|_| ())
        })
    }

    fn requeue_stale(&self, now: i64, lease_ms: i64) -> StoreResult<usize> {
        self.with(|c| {
            c.execute(
                "UPDATE jobs SET state = 'queued', started = NULL, runner = NULL
                 WHERE state = 'running' AND (heartbeat IS NULL OR heartbeat < $1)",
                &[&now.saturating_sub(lease_ms)],
            )
            .map(|n| n as usize)
        })
    }

    fn progress(&self, id: &str, round: i64, diameter: f64, fraction: f64) -> StoreResult<()> {
        let d = diameter.is_finite().then_some(diameter);
        self.with(|c| {
            c.execute(
                "UPDATE jobs SET round = $2, diameter = $3, fraction = $4
                 WHERE id = $1 AND state = 'running' AND runner = $5",
                &[&id, &round, &d, &fraction, &self.instance],
            )
            .map(|_| ())
        })
    }

    fn finish_job(
        &self,
        id: &str,
        state: JobState,
        result: Option<&str>,
        error: Option<&JobError>,
        now: i64,
    ) -> StoreResult<()> {
        let (code, message) = (error.map(|e| e.code), error.map(|e| e.message.as_str()));
        self.with(|c| {
            c.execute(
                "UPDATE jobs SET state = $2, result = $3, error = $4, error_code = $7::TEXT, finished = $5,
                 fraction = CASE WHEN $2 = 'done' THEN 1 ELSE fraction END
                 WHERE id = $1 AND state = 'running' AND runner = $6",
                &[&id, &state.as_str(), &result, &message, &now, &self.instance, &code],
            )
            .map(|_| ())
        })
    }

    fn record_crash(
        &self,
        id: &str,
        error: &JobError,
        max_crashes: i64,
        now: i64,
    ) -> StoreResult<Option<JobState>> {
        // The right-hand sides all read the row before the update.
        self.with(|c| {
            Ok(c.query_opt(
                "UPDATE jobs SET crashes = crashes + 1,
                   state = CASE WHEN crashes + 1 >= $3::BIGINT THEN 'failed' ELSE 'queued' END,
                   error = CASE WHEN crashes + 1 >= $3::BIGINT THEN $4::TEXT ELSE NULL END,
                   error_code = CASE WHEN crashes + 1 >= $3::BIGINT THEN $5::TEXT ELSE NULL END,
                   finished = CASE WHEN crashes + 1 >= $3::BIGINT THEN $6::BIGINT ELSE NULL END,
                   started = CASE WHEN crashes + 1 >= $3::BIGINT THEN started ELSE NULL END,
                   runner = CASE WHEN crashes + 1 >= $3::BIGINT THEN runner ELSE NULL END
                 WHERE id = $1 AND state = 'running' AND runner = $2
                 RETURNING state",
                &[
                    &id,
                    &self.instance,
                    &max_crashes,
                    &error.message,
                    &error.code,
                    &now,
                ],
            )?
            .map(|r| r.get(0)))
        })
    }

    fn cancel_job(&self, owner: &str, id: &str, now: i64) -> StoreResult<Option<JobState>> {
        self.with(|c| {
            let mut tx = c.transaction()?;
            let state: Option<JobState> = tx
                .query_opt(
                    "SELECT state FROM jobs WHERE id = $1 AND owner = $2 FOR UPDATE",
                    &[&id, &owner],
                )?
                .map(|r| r.get(0));
            if state.is_some_and(JobState::is_active) {
                tx.execute(
                    "UPDATE jobs SET state = 'cancelled', finished = $2 WHERE id = $1",
                    &[&id, &now],
                )?;
            }
            tx.commit()?;
            Ok(state)
        })
    }

    fn job_state(&self, id: &str) -> StoreResult<Option<JobState>> {
        self.with(|c| {
            Ok(c.query_opt("SELECT state FROM jobs WHERE id = $1", &[&id])?
                .map(|r| r.get(0)))
        })
    }

    fn result(&self, owner: &str, id: &str) -> StoreResult<Option<String>> {
        self.with(|c| {
            Ok(c.query_opt(
                "SELECT result FROM jobs WHERE id = $1 AND owner = $2",
                &[&id, &owner],
            )?
            .and_then(|r| r.get(0)))
        })
    }

    fn counts(&self) -> StoreResult<Vec<(JobState, i64)>> {
        self.with(|c| {
            Ok(c.query(
                "SELECT state, COUNT(*) FROM jobs GROUP BY state ORDER BY state",
                &[],
            )?
            .iter()
            .map(|r| (r.get(0), r.get(1)))
            .collect())
        })
    }

    fn instance(&self) -> &str {
        &self.instance
    }
}
