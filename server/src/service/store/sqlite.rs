//! SQLite storage: a database file, created on first run.

use super::types::{
    JobError, JobRow, JobState, MissionRow, QueuePolicy, Queued, Store, StoreError, StoreResult,
    COST_SQL, JOB_COLUMNS,
};
use rusqlite::{params, Connection, OptionalExtension};
use std::sync::Mutex;

/// SQLite storage: one connection behind a mutex (SQLite serialises
/// writers anyway), WAL journal.
pub struct SqliteStore {
    conn: Mutex<Connection>,
    instance: String,
}

const MIGRATIONS: &[&str] = &[
    "CREATE TABLE IF NOT EXISTS missions (
        id TEXT PRIMARY KEY, owner TEXT NOT NULL, name TEXT NOT NULL,
        steps INTEGER NOT NULL, detections INTEGER NOT NULL,
        body TEXT NOT NULL, created INTEGER NOT NULL, seq INTEGER NOT NULL)",
    "CREATE TABLE IF NOT EXISTS jobs (
        id TEXT PRIMARY KEY, owner TEXT NOT NULL, mission TEXT NOT NULL,
        state TEXT NOT NULL, contractor TEXT NOT NULL, max_rounds INTEGER NOT NULL,
        time_limit_s REAL NOT NULL, round INTEGER NOT NULL DEFAULT 0,
        diameter REAL, fraction REAL NOT NULL DEFAULT 0, error TEXT, result TEXT,
        created INTEGER NOT NULL, started INTEGER, finished INTEGER, seq INTEGER NOT NULL)",
    "CREATE INDEX IF NOT EXISTS jobs_state ON jobs (state, seq)",
    "CREATE INDEX IF NOT EXISTS missions_owner ON missions (owner, seq)",
    "ALTER TABLE jobs ADD COLUMN runner TEXT;
     ALTER TABLE jobs ADD COLUMN heartbeat INTEGER;
     ALTER TABLE jobs ADD COLUMN attempts INTEGER NOT NULL DEFAULT 0",
    // Worker processes: why a job failed as a word, how often
    // its worker died, its cost and its place in the queue.
    "ALTER TABLE jobs ADD COLUMN error_code TEXT;
     ALTER TABLE jobs ADD COLUMN crashes INTEGER NOT NULL DEFAULT 0;
     ALTER TABLE jobs ADD COLUMN cost INTEGER NOT NULL DEFAULT 1;
     ALTER TABLE jobs ADD COLUMN queue_order INTEGER NOT NULL DEFAULT 0;
     UPDATE jobs SET queue_order = created, cost = COALESCE((SELECT
         (CASE WHEN m.steps > 1 THEN m.steps ELSE 1 END)
         * (CASE WHEN m.detections > 1 THEN m.detections ELSE 1 END)
         FROM missions m WHERE m.id = jobs.mission), 1);
     CREATE INDEX IF NOT EXISTS jobs_queue ON jobs (state, queue_order, seq)",
    // The places of deleted missions, for paging cursors (`list_missions`).
    "CREATE TABLE IF NOT EXISTS deleted_missions (
        id TEXT PRIMARY KEY, owner TEXT NOT NULL, seq INTEGER NOT NULL)",
];

impl SqliteStore {
    /// Opens (creating) the database file and applies the migrations.
    pub fn open(path: &str) -> StoreResult<SqliteStore> {
        if let Some(dir) = std::path::Path::new(path).parent() {
            if !dir.as_os_str().is_empty() {
                std::fs::create_dir_all(dir)
                    .map_err(|e| StoreError(format!("creating {}: {e}", dir.display())))?;
            }
        }
        let conn = Connection::open(path)?;
        conn.busy_timeout(std::time::Duration::from_secs(5))?;
        conn.pragma_update(None, "journal_mode", "WAL")?;
        conn.pragma_update(None, "synchronous", "NORMAL")?;
        let version: i64 = conn.pragma_query_value(None, "user_version", |r| r.get(0))?;
        // Each migration and its version number in one transaction: a
        // process killed half-way leaves the previous version whole.
        for (i, m) in MIGRATIONS.iter().enumerate() {
            if (i as i64) >= version {
                conn.execute_batch(&format!(
                    "BEGIN IMMEDIATE; {m}; PRAGMA user_version = {}; COMMIT;",
                    i + 1
                ))?;
            }
        }
        Ok(SqliteStore {
            conn: Mutex::new(conn),
            instance: super::types::new_instance_id(),
        })
    }

    fn with<T>(&self, f: impl FnOnce(&Connection) -> rusqlite::Result<T>) -> StoreResult<T> {
        let c = self
            .conn
            .lock()
            .map_err(|_| StoreError("poisoned connection".into()))?;
        Ok(f(&c)?)
    }
}

fn job_from_row(r: &rusqlite::Row<'_>) -> rusqlite::Result<JobRow> {
    Ok(JobRow {
        id: r.get(0)?,
        mission: r.get(1)?,
        state: r.get(2)?,
        contractor: r.get(3)?,
        max_rounds: r.get(4)?,
        time_limit_s: r.get(5)?,
        round: r.get(6)?,
        diameter: r.get(7)?,
        fraction: r.get(8)?,
        error: r.get(9)?,
        created: r.get(10)?,
        started: r.get(11)?,
        finished: r.get(12)?,
        attempts: r.get(13)?,
        runner: r.get(14)?,
        error_code: r.get(15)?,
        crashes: r.get(16)?,
        cost: r.get(17)?,
    })
}

impl Store for SqliteStore {
    fn ping(&self) -> StoreResult<()> {
        self.with(|c| c.query_row("SELECT 1", [], |_| Ok(())))
    }

    fn insert_mission(&self, owner: &str, m: &MissionRow, body: &str) -> StoreResult<()> {
        self.with(|c| {
            c.execute(
                "INSERT INTO missions (id, owner, name, steps, detections, body, created, seq)
                 VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, (SELECT COALESCE(MAX(seq), 0) + 1 FROM missions))",
                params![m.id, owner, m.name, m.steps, m.detections, body, m.created],
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
                Some(a) => {
                    let seq: Option<i64> = c
                        .query_row(
                            "SELECT seq FROM missions WHERE id = ?1 AND owner = ?2
                             UNION ALL
                             SELECT seq FROM deleted_missions WHERE id = ?1 AND owner = ?2",
                            params![a, owner],
                            |r| r.get(0),
                        )
                        .optional()?;
                    match seq {
                        Some(s) => s,
                        None => return Ok(None),
                    }
                }
                None => 0,
            };
            let mut st = c.prepare(
                "SELECT id, name, steps, detections, created, length(CAST(body AS BLOB)) FROM missions
                 WHERE owner = ?1 AND seq > ?2 AND id NOT LIKE 't-%' ORDER BY seq LIMIT ?3",
            )?;
            let rows = st.query_map(params![owner, after_seq, limit], |r| {
                Ok(MissionRow {
                    id: r.get(0)?,
                    name: r.get(1)?,
                    steps: r.get(2)?,
                    detections: r.get(3)?,
                    created: r.get(4)?,
                    bytes: r.get(5)?,
                })
            })?;
            rows.collect::<rusqlite::Result<Vec<_>>>().map(Some)
        })
    }

    fn mission_body(&self, owner: &str, id: &str) -> StoreResult<Option<String>> {
        self.with(|c| {
            c.query_row(
                "SELECT body FROM missions WHERE id = ?1 AND owner = ?2",
                params![id, owner],
                |r| r.get(0),
            )
            .optional()
        })
    }

    fn mission_body_any(&self, id: &str) -> StoreResult<Option<String>> {
        self.with(|c| {
            c.query_row(
                "SELECT body FROM missions WHERE id = ?1",
                params![id],
                |r| r.get(0),
            )
            .optional()
        })
    }

    fn requeue_one(&self, id: &str) -> StoreResult<()> {
        self.with(|c| {
            c.execute(
                "UPDATE jobs SET state = 'queued', started = NULL, runner = NULL
                 WHERE id = ?1 AND state = 'running' AND runner = ?2",
                params![id, self.instance],
            )
            .map(|_| ())
        })
    }

    fn delete_mission(&self, owner: &str, id: &str) -> StoreResult<bool> {
        self.with(|c| {
            c.execute(
                "INSERT OR IGNORE INTO deleted_missions (id, owner, seq)
                 SELECT id, owner, seq FROM missions WHERE id = ?1 AND owner = ?2",
                params![id, owner],
            )?;
            let n = c.execute("DELETE FROM missions WHERE id = ?1 AND owner = ?2", params![id, owner])?;
            if n > 0 {
                c.execute("UPDATE jobs SET state = 'cancelled' WHERE mission = ?1 AND state IN ('queued', 'running')", params![id])?;
                c.execute("DELETE FROM jobs WHERE mission = ?1", params![id])?;
            }
            Ok(n > 0)
        })
    }

    fn insert_job(&self, owner: &str, j: &JobRow, policy: &QueuePolicy) -> StoreResult<Queued> {
        // One statement under the connection's lock: the count and the
        // insert cannot interleave with another submission.
        self.with(|c| {
            let n = c.execute(
                &format!(
                    "INSERT INTO jobs (id, owner, mission, state, contractor, max_rounds,
                        time_limit_s, created, seq, cost, queue_order)
                     SELECT ?1, ?2, m.id, 'queued', ?4, ?5, ?6, ?7,
                        (SELECT COALESCE(MAX(seq), 0) + 1 FROM jobs), {COST_SQL},
                        ?7 + CASE WHEN {COST_SQL} > ?9 THEN ?10 ELSE 0 END
                     FROM missions m
                     WHERE m.id = ?3 AND m.owner = ?2
                       AND (SELECT COUNT(*) FROM jobs WHERE state = 'queued') < ?8"
                ),
                params![
                    j.id,
                    owner,
                    j.mission,
                    j.contractor,
                    j.max_rounds,
                    j.time_limit_s,
                    j.created,
                    policy.max_queue,
                    policy.short_cost,
                    policy.long_delay_ms
                ],
            )?;
            if n > 0 {
                return Ok(Queued::Yes);
            }
            let mission: Option<i64> = c
                .query_row(
                    "SELECT 1 FROM missions WHERE id = ?1 AND owner = ?2",
                    params![j.mission, owner],
                    |r| r.get(0),
                )
                .optional()?;
            Ok(if mission.is_some() {
                Queued::Full
            } else {
                Queued::NoMission
            })
        })
    }

    fn job(&self, owner: &str, id: &str) -> StoreResult<Option<JobRow>> {
        self.with(|c| {
            c.query_row(
                &format!("SELECT {JOB_COLUMNS} FROM jobs WHERE id = ?1 AND owner = ?2"),
                params![id, owner],
                job_from_row,
            )
            .optional()
        })
    }

    fn claim_job(&self, now: i64, max_cost: i64) -> StoreResult<Option<JobRow>> {
        self.with(|c| {
            c.query_row(
                &format!(
                    "UPDATE jobs SET state = 'running', started = ?1, heartbeat = ?1,
                     runner = ?2, attempts = attempts + 1
                     WHERE id = (SELECT id FROM jobs WHERE state = 'queued' AND cost <= ?3
                                 ORDER BY queue_order, seq LIMIT 1)
                     RETURNING {JOB_COLUMNS}"
                ),
                params![now, self.instance, max_cost],
                job_from_row,
            )
            .optional()
        })
    }

    fn progress(&self, id: &str, round: i64, diameter: f64, fraction: f64) -> StoreResult<()> {
        let d = if diameter.is_finite() {
            Some(diameter)
        } else {
            None
        };
        self.with(|c| {
            c.execute(
                "UPDATE jobs SET round = ?2, diameter = ?3, fraction = ?4
                 WHERE id = ?1 AND state = 'running' AND runner = ?5",
                params![id, round, d, fraction, self.instance],
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
                "UPDATE jobs SET state = ?2, result = ?3, error = ?4, error_code = ?7, finished = ?5,
                 fraction = CASE WHEN ?2 = 'done' THEN 1 ELSE fraction END
                 WHERE id = ?1 AND state = 'running' AND runner = ?6",
                params![id, state, result, message, now, self.instance, code],
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
            c.query_row(
                "UPDATE jobs SET crashes = crashes + 1,
                   state = CASE WHEN crashes + 1 >= ?3 THEN 'failed' ELSE 'queued' END,
                   error = CASE WHEN crashes + 1 >= ?3 THEN ?4 ELSE NULL END,
                   error_code = CASE WHEN crashes + 1 >= ?3 THEN ?5 ELSE NULL END,
                   finished = CASE WHEN crashes + 1 >= ?3 THEN ?6 ELSE NULL END,
                   started = CASE WHEN crashes + 1 >= ?3 THEN started ELSE NULL END,
                   runner = CASE WHEN crashes + 1 >= ?3 THEN runner ELSE NULL END
                 WHERE id = ?1 AND state = 'running' AND runner = ?2
                 RETURNING state",
                params![
                    id,
                    self.instance,
                    max_crashes,
                    error.message,
                    error.code,
                    now
                ],
                |r| r.get(0),
            )
            .optional()
        })
    }

    fn cancel_job(&self, owner: &str, id: &str, now: i64) -> StoreResult<Option<JobState>> {
        self.with(|c| {
            let state: Option<JobState> = c
                .query_row("SELECT state FROM jobs WHERE id = ?1 AND owner = ?2", params![id, owner], |r| r.get(0))
                .optional()?;
            if let Some(s) = state {
                if s.is_active() {
                    c.execute(
                        "UPDATE jobs SET state = 'cancelled', finished = ?2 WHERE id = ?1 AND state IN ('queued', 'running')",
                        params![id, now],
                    )?;
                }
            }
            Ok(state)
        })
    }

    fn job_state(&self, id: &str) -> StoreResult<Option<JobState>> {
        self.with(|c| {
            c.query_row("SELECT state FROM jobs WHERE id = ?1", params![id], |r| {
                r.get(0)
            })
            .optional()
        })
    }

    fn result(&self, owner: &str, id: &str) -> StoreResult<Option<String>> {
        self.with(|c| {
            c.query_row(
                "SELECT result FROM jobs WHERE id = ?1 AND owner = ?2",
                params![id, owner],
                |r| r.get(0),
            )
            .optional()
            .map(Option::flatten)
        })
    }

    fn heartbeat(&self, now: i64) -> StoreResult<()> {
        self.with(|c| {
            c.execute(
                "UPDATE jobs SET heartbeat = ?1 WHERE state = 'running' AND runner = ?2",
                params![now, self.instance],
            )
            .map(|_| ())
        })
    }

    fn requeue_stale(&self, now: i64, lease_ms: i64) -> StoreResult<usize> {
        self.with(|c| {
            c.execute(
                "UPDATE jobs SET state = 'queued', started = NULL, runner = NULL
                 WHERE state = 'running' AND (heartbeat IS NULL OR heartbeat < ?1)",
                params![now.saturating_sub(lease_ms)],
            )
        })
    }

    fn instance(&self) -> &str {
        &self.instance
    }

    fn counts(&self) -> StoreResult<Vec<(JobState, i64)>> {
        self.with(|c| {
            let mut st =
                c.prepare("SELECT state, COUNT(*) FROM jobs GROUP BY state ORDER BY state")?;
            let rows = st.query_map([], |r| Ok((r.get(0)?, r.get(1)?)))?;
            rows.collect()
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The stored strings are those the column held before `JobState`
    /// (existing databases open), and a string that is none of them is a
    /// storage error, not a panic.
    #[test]
    fn job_states_are_the_stored_strings() {
        let c = Connection::open_in_memory().unwrap();
        for s in JobState::ALL {
            let back: String = c.query_row("SELECT ?1", params![s], |r| r.get(0)).unwrap();
            assert_eq!(back, s.as_str());
            let read: JobState = c
                .query_row("SELECT ?1", params![s.as_str()], |r| r.get(0))
                .unwrap();
            assert_eq!(read, s);
        }
        assert_eq!(
            ["queued", "running", "done", "failed", "cancelled"],
            JobState::ALL.map(JobState::as_str)
        );
        let bad = c.query_row("SELECT 'paused'", [], |r| r.get::<_, JobState>(0));
        assert!(bad.unwrap_err().to_string().contains("paused"));
    }

    fn open() -> (SqliteStore, std::path::PathBuf) {
        let dir = std::env::temp_dir().join(format!(
            "nvector-store-{}",
            super::super::types::new_instance_id()
        ));
        let store = SqliteStore::open(dir.join("db").to_str().unwrap()).unwrap();
        (store, dir)
    }

    fn mission(st: &SqliteStore, id: &str, steps: i64, detections: i64) {
        let row = MissionRow {
            id: id.into(),
            name: id.into(),
            steps,
            detections,
            created: 0,
            bytes: 2,
        };
        st.insert_mission("", &row, "{}").unwrap();
    }

    fn job(id: &str, mission: &str, created: i64) -> JobRow {
        JobRow {
            id: id.into(),
            mission: mission.into(),
            state: JobState::Queued,
            contractor: "none".into(),
            max_rounds: 1,
            time_limit_s: 1.0,
            round: 0,
            diameter: None,
            fraction: 0.0,
            error: None,
            error_code: None,
            attempts: 0,
            crashes: 0,
            cost: 0,
            runner: None,
            created,
            started: None,
            finished: None,
        }
    }

    const POLICY: QueuePolicy = QueuePolicy {
        max_queue: 3,
        short_cost: 100,
        long_delay_ms: 1000,
    };

    #[test]
    fn the_queue_limit_cost_and_order() {
        let (st, dir) = open();
        mission(&st, "long", 50, 3); // cost 150: long
        mission(&st, "short", 10, 0); // cost 10 × 1: short
        let q = |id: &str, m: &str, t: i64| st.insert_job("", &job(id, m, t), &POLICY).unwrap();
        assert_eq!(q("a", "long", 0), Queued::Yes);
        assert_eq!(q("b", "long", 10), Queued::Yes);
        // Queued after both long jobs, within the long-job delay: first.
        assert_eq!(q("c", "short", 500), Queued::Yes);
        assert_eq!(q("d", "short", 600), Queued::Full);
        assert_eq!(q("e", "gone", 600), Queued::NoMission);
        // The short lane sees only the short job; the costs are stored.
        assert!(st
            .claim_job(1, 100)
            .unwrap()
            .is_some_and(|j| j.id == "c" && j.cost == 10));
        assert!(st.claim_job(1, 100).unwrap().is_none());
        let order: Vec<(String, i64)> = std::iter::from_fn(|| st.claim_job(1, i64::MAX).unwrap())
            .map(|j| (j.id, j.cost))
            .collect();
        assert_eq!(order, [("a".into(), 150), ("b".into(), 150)]);
        let _ = std::fs::remove_dir_all(dir);
    }

    #[test]
    fn a_crash_requeues_until_the_last_attempt() {
        let (st, dir) = open();
        mission(&st, "m", 1, 1);
        st.insert_job("", &job("j", "m", 0), &POLICY).unwrap();
        let e = JobError {
            code: "worker_crashed",
            message: "killed".into(),
        };
        st.claim_job(1, i64::MAX).unwrap().unwrap();
        assert_eq!(
            st.record_crash("j", &e, 2, 5).unwrap(),
            Some(JobState::Queued)
        );
        let j = st.job("", "j").unwrap().unwrap();
        assert_eq!(
            (j.crashes, j.error_code, j.runner, j.started),
            (1, None, None, None)
        );
        let j = st.claim_job(6, i64::MAX).unwrap().unwrap();
        assert_eq!((j.attempts, j.crashes), (2, 1));
        assert_eq!(
            st.record_crash("j", &e, 2, 9).unwrap(),
            Some(JobState::Failed)
        );
        let j = st.job("", "j").unwrap().unwrap();
        assert_eq!(
            (
                j.state.as_str(),
                j.crashes,
                j.error_code.as_deref(),
                j.error.as_deref(),
                j.finished
            ),
            ("failed", 2, Some("worker_crashed"), Some("killed"), Some(9))
        );
        // Nothing claims it again, and a crash of a job no longer held is
        // not recorded.
        assert!(st.claim_job(10, i64::MAX).unwrap().is_none());
        assert_eq!(st.record_crash("j", &e, 2, 11).unwrap(), None);
        let _ = std::fs::remove_dir_all(dir);
    }
}
