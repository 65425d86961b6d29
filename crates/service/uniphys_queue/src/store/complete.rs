//! Completing stage runs: their output manifests, their cost, the stages they unblock and, for
//! a job's last stage, the job, all in one transaction. Many runs complete in one transaction
//! with one statement per step ([`QueueStore::complete_many`]); one run is a batch of one.

use std::collections::{BTreeMap, BTreeSet, HashMap, HashSet};

use serde::{Deserialize, Serialize};
use serde_json::{Value, json};

use super::{QueueStore, RunRef, fencing};
use crate::db::{Session, Sql, args};
use crate::{JobId, Lease, QueueError, QueueResult, StageRunId};

/// Largest output manifest accepted, in bytes of JSON: manifests name artifacts (object keys and
/// digests), they never carry them.
pub const MAX_MANIFEST_BYTES: usize = 64 * 1024;

/// What a stage run consumed, summed by the worker. Wall time is `finished - started`.
#[derive(Clone, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct StageCost {
    /// GPU time, milliseconds.
    pub gpu_ms: u64,
    /// Requests to the LVLM.
    pub lvlm_requests: u64,
    /// Tokens in and out of the LVLM.
    pub lvlm_tokens: u64,
    /// Money spent on external services, millionths of a US dollar.
    pub usd_micros: u64,
}

/// One held run to mark succeeded.
#[derive(Clone, Debug, PartialEq)]
pub struct Completion {
    /// The fencing token of the attempt that finished.
    pub lease: Lease,
    /// What the run wrote (at most [`MAX_MANIFEST_BYTES`] of JSON).
    pub output_manifest: Value,
    /// What it consumed.
    pub cost: StageCost,
}

/// What completing a run changed.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct CompleteOutcome {
    /// Downstream runs that became claimable, by id (wake their stages' workers).
    pub unblocked: Vec<RunRef>,
    /// Whether this was the job's last stage and the job succeeded.
    pub job_succeeded: bool,
}

// Statements take each list as one parameter (an array on Postgres, JSON on SQLite), so a batch
// of any size is one statement per step, planned with its lengths known (index scans).

// The jobs of the runs, locked in id order (two batches never wait on each other in a cycle);
// SQLite has one writer.
static LOCK_JOBS: Sql = Sql::new(
    "SELECT id FROM jobs WHERE id IN (SELECT job_id FROM stage_runs WHERE id {in_list_1})
     ORDER BY id {for_update}",
);

// $1 run ids, $2 attempts, $3 and $4 the manifests and costs as JSON arrays in the same order.
static SUCCEED: Sql = Sql::per_dialect(
    "UPDATE stage_runs
     SET state = 'succeeded', output_manifest = $3 -> CAST(c.ord - 1 AS INT),
         cost = $4 -> CAST(c.ord - 1 AS INT), finished_at_ms = {now}, lease_expires_at_ms = NULL
     FROM unnest(CAST($1 AS BIGINT[]), CAST($2 AS BIGINT[]))
          WITH ORDINALITY AS c(run_id, run_attempt, ord)
     WHERE id = c.run_id AND attempt = c.run_attempt AND state = 'running'
     RETURNING id, job_id, stage_name, attempt",
    "UPDATE stage_runs
     SET state = 'succeeded', output_manifest = c.manifest, cost = c.cost,
         finished_at_ms = {now}, lease_expires_at_ms = NULL
     FROM (SELECT i.value AS run_id, a.value AS run_attempt,
                  $3 -> ('$[' || i.key || ']') AS manifest, $4 -> ('$[' || i.key || ']') AS cost
           FROM json_each($1) AS i JOIN json_each($2) AS a ON a.key = i.key) AS c
     WHERE id = c.run_id AND attempt = c.run_attempt AND state = 'running'
     RETURNING id, job_id, stage_name, attempt",
);

static DEPENDENTS: Sql =
    Sql::new("SELECT depends_on_id, stage_run_id FROM stage_deps WHERE depends_on_id {in_list_1}");

// A dependent becomes ready when its last blocking dependencies succeed (SET reads old values).
static UNBLOCK: Sql = Sql::new(
    "UPDATE stage_runs
     SET blocking_deps = blocking_deps - d.n,
         state = CASE WHEN blocking_deps = d.n AND state = 'blocked' THEN 'ready' ELSE state END,
         run_after_ms = CASE WHEN blocking_deps = d.n AND state = 'blocked' THEN {now}
                        ELSE run_after_ms END
     FROM (SELECT stage_run_id AS dependent, count(*) AS n FROM stage_deps
           WHERE depends_on_id {in_list_1} GROUP BY stage_run_id) AS d
     WHERE id = d.dependent
     RETURNING id, stage_name, state",
);

static FINISH_JOBS: Sql = Sql::new(
    "UPDATE jobs SET state = 'succeeded', finished_at_ms = {now}
     WHERE id {in_list_1} AND state = 'running'
       AND NOT EXISTS (SELECT 1 FROM stage_runs s WHERE s.job_id = jobs.id AND s.state <> 'succeeded')
     RETURNING id",
);

// In the order given: $1 job ids, $2 run ids, $3 stage names, $4 attempts, $5 details (JSON).
static STAGE_EVENTS: Sql = Sql::per_dialect(
    "INSERT INTO events (job_id, stage_run_id, stage_name, kind, attempt, detail, at_ms)
     SELECT e.job_id, e.run_id, e.stage_name, 'stage_succeeded', e.attempt,
            $5 -> CAST(e.ord - 1 AS INT), {now}
     FROM unnest(CAST($1 AS BIGINT[]), CAST($2 AS BIGINT[]), CAST($3 AS TEXT[]),
                 CAST($4 AS BIGINT[])) WITH ORDINALITY AS e(job_id, run_id, stage_name, attempt, ord)
     ORDER BY e.ord",
    "INSERT INTO events (job_id, stage_run_id, stage_name, kind, attempt, detail, at_ms)
     SELECT j.value, r.value, s.value, 'stage_succeeded', a.value, $5 -> ('$[' || j.key || ']'),
            {now}
     FROM json_each($1) AS j JOIN json_each($2) AS r ON r.key = j.key
          JOIN json_each($3) AS s ON s.key = j.key JOIN json_each($4) AS a ON a.key = j.key
     ORDER BY j.key",
);

// After the stage events, so a job's success follows its stages'.
static JOB_EVENTS: Sql = Sql::per_dialect(
    "INSERT INTO events (job_id, kind, at_ms)
     SELECT x.job_id, 'job_succeeded', {now}
     FROM unnest(CAST($1 AS BIGINT[])) WITH ORDINALITY AS x(job_id, ord) ORDER BY x.ord",
    "INSERT INTO events (job_id, kind, at_ms)
     SELECT value, 'job_succeeded', {now} FROM json_each($1) ORDER BY key",
);

/// The `stage_succeeded` events of a batch, column by column.
#[derive(Default)]
struct StageEvents {
    jobs: Vec<i64>,
    runs: Vec<i64>,
    stages: Vec<String>,
    attempts: Vec<i64>,
    details: Vec<Value>,
}

impl StageEvents {
    fn push(&mut self, done: &Succeeded, lease: Lease, unblocked: &[RunRef]) {
        self.jobs.push(done.job.0);
        self.runs.push(lease.run_id.0);
        self.stages.push(done.stage_name.clone());
        self.attempts.push(i64::from(lease.attempt));
        let names: Vec<&str> = unblocked.iter().map(|r| r.stage_name.as_str()).collect();
        self.details.push(json!({ "unblocked": names }));
    }
}

/// A run the batch marked succeeded.
struct Succeeded {
    job: JobId,
    stage_name: String,
    attempt: u32,
}

impl QueueStore {
    /// Marks the held run succeeded with its output manifest and cost, makes the stages that
    /// waited only for it claimable and, if it was the last, marks the job succeeded: one
    /// transaction, so a crash leaves either all of it or none. Fails with `LeaseLost` or
    /// `Cancelled` (changing nothing) if the lease is no longer current.
    pub async fn complete(
        &self,
        lease: &Lease,
        output_manifest: &Value,
        cost: &StageCost,
    ) -> QueueResult<CompleteOutcome> {
        let completion = Completion {
            lease: *lease,
            output_manifest: output_manifest.clone(),
            cost: cost.clone(),
        };
        let mut results = self
            .complete_many(std::slice::from_ref(&completion))
            .await?;
        results.pop().unwrap_or_else(|| {
            Err(QueueError::CorruptRow(
                "a completion gave no result".to_owned(),
            ))
        })
    }

    /// Completes many held runs in one transaction, with one statement per step for the whole
    /// batch (the runs, their dependents, their jobs, their events); each run as
    /// [`Self::complete`] would. Returns one result per completion, in order: a lease that is
    /// no longer current (`LeaseLost`, `Cancelled`) or an oversized manifest (`Invalid`) fails
    /// that completion alone. The outer error means the transaction failed and nothing was
    /// recorded. A job whose last runs complete in one batch is reported succeeded on the last
    /// of them.
    pub async fn complete_many(
        &self,
        completions: &[Completion],
    ) -> QueueResult<Vec<QueueResult<CompleteOutcome>>> {
        let mut results: Vec<Option<QueueResult<CompleteOutcome>>> = completions
            .iter()
            .map(|c| oversized(&c.output_manifest).map(Err))
            .collect();
        let batch: Vec<&Completion> = completions
            .iter()
            .zip(&results)
            .filter(|(_, r)| r.is_none())
            .map(|(c, _)| c)
            .collect();
        if batch.is_empty() {
            return Ok(results.into_iter().flatten().collect());
        }
        let mut tx = self.db.write_tx().await?;
        let run_ids: Vec<i64> = batch.iter().map(|c| c.lease.run_id.0).collect();
        tx.fetch_all(&LOCK_JOBS, args![run_ids.clone()]).await?;
        let attempts: Vec<i64> = batch.iter().map(|c| i64::from(c.lease.attempt)).collect();
        let manifests: Vec<Value> = batch.iter().map(|c| c.output_manifest.clone()).collect();
        let costs = batch
            .iter()
            .map(|c| serde_json::to_value(&c.cost).map_err(|e| QueueError::Invalid(e.to_string())))
            .collect::<QueueResult<Vec<Value>>>()?;
        let mut succeeded: HashMap<StageRunId, Succeeded> = HashMap::new();
        let updated = tx
            .fetch_all(
                &SUCCEED,
                args![
                    run_ids,
                    attempts,
                    Value::Array(manifests),
                    Value::Array(costs)
                ],
            )
            .await?;
        for row in updated {
            succeeded.insert(
                StageRunId(row.i64("id")?),
                Succeeded {
                    job: JobId(row.i64("job_id")?),
                    stage_name: row.text("stage_name")?,
                    attempt: row.u32("attempt")?,
                },
            );
        }
        let unblocked = unblock(&mut tx, &succeeded).await?;
        let jobs: BTreeSet<JobId> = succeeded.values().map(|s| s.job).collect();
        let finished: HashSet<JobId> = if jobs.is_empty() {
            HashSet::new()
        } else {
            let ids: Vec<i64> = jobs.iter().map(|j| j.0).collect();
            tx.fetch_all(&FINISH_JOBS, args![ids])
                .await?
                .iter()
                .map(|row| Ok(JobId(row.i64("id")?)))
                .collect::<QueueResult<_>>()?
        };

        // One result per completion in order: the one whose attempt the update matched succeeds (a
        // run listed twice succeeds once); the others are explained by their lease.
        let last_of_job: HashMap<JobId, usize> = batch
            .iter()
            .enumerate()
            .filter_map(|(i, c)| {
                succeeded
                    .get(&c.lease.run_id)
                    .filter(|s| s.attempt == c.lease.attempt)
                    .map(|s| (s.job, i))
            })
            .collect();
        let mut reported = HashSet::new();
        let mut events = StageEvents::default();
        let mut finished_jobs = Vec::new();
        let mut outcomes = Vec::with_capacity(batch.len());
        for (i, c) in batch.iter().enumerate() {
            let run = c.lease.run_id;
            let Some(done) = succeeded
                .get(&run)
                .filter(|s| s.attempt == c.lease.attempt && reported.insert(run))
            else {
                outcomes.push(Err(fencing::lease_error(&mut tx, &c.lease).await));
                continue;
            };
            let next = unblocked.get(&run).cloned().unwrap_or_default();
            let job_succeeded =
                finished.contains(&done.job) && last_of_job.get(&done.job) == Some(&i);
            events.push(done, c.lease, &next);
            if job_succeeded {
                finished_jobs.push(done.job.0);
            }
            outcomes.push(Ok(CompleteOutcome {
                unblocked: next,
                job_succeeded,
            }));
        }
        if !events.jobs.is_empty() {
            let StageEvents {
                jobs,
                runs,
                stages,
                attempts,
                details,
            } = events;
            tx.execute(
                &STAGE_EVENTS,
                args![jobs, runs, stages, attempts, Value::Array(details)],
            )
            .await?;
        }
        if !finished_jobs.is_empty() {
            tx.execute(&JOB_EVENTS, args![finished_jobs]).await?;
        }
        tx.commit().await?;
        let mut outcomes = outcomes.into_iter();
        results
            .iter_mut()
            .map(|r| r.take().or_else(|| outcomes.next()))
            .collect::<Option<Vec<_>>>()
            .ok_or_else(|| QueueError::CorruptRow("a completion lost its result".to_owned()))
    }
}

/// The size in bytes of `manifest` as JSON when it is over [`MAX_MANIFEST_BYTES`]: a completion
/// carrying it is refused.
#[must_use]
pub fn oversized_manifest_bytes(manifest: &Value) -> Option<usize> {
    let bytes = manifest.to_string().len();
    (bytes > MAX_MANIFEST_BYTES).then_some(bytes)
}

/// The error for a manifest over [`MAX_MANIFEST_BYTES`].
fn oversized(manifest: &Value) -> Option<QueueError> {
    oversized_manifest_bytes(manifest).map(|bytes| {
        QueueError::Invalid(format!(
            "output manifest of {bytes} bytes exceeds {MAX_MANIFEST_BYTES}: store artifacts, not data"
        ))
    })
}

/// Counts the succeeded runs off their dependents' blocking dependencies; returns, per succeeded
/// run, the dependents that became claimable (a dependent of several runs of the batch is listed
/// under each), sorted by id.
async fn unblock(
    tx: &mut Session,
    succeeded: &HashMap<StageRunId, Succeeded>,
) -> QueueResult<BTreeMap<StageRunId, Vec<RunRef>>> {
    let mut by_run: BTreeMap<StageRunId, Vec<RunRef>> = BTreeMap::new();
    if succeeded.is_empty() {
        return Ok(by_run);
    }
    let ids: Vec<i64> = succeeded.keys().map(|r| r.0).collect();
    let mut edges = Vec::new();
    for row in tx.fetch_all(&DEPENDENTS, args![ids.clone()]).await? {
        edges.push((
            StageRunId(row.i64("depends_on_id")?),
            StageRunId(row.i64("stage_run_id")?),
        ));
    }
    if edges.is_empty() {
        return Ok(by_run);
    }
    let mut ready = HashMap::new();
    for row in tx.fetch_all(&UNBLOCK, args![ids]).await? {
        if row.text("state")? == "ready" {
            let run_id = StageRunId(row.i64("id")?);
            ready.insert(
                run_id,
                RunRef {
                    run_id,
                    stage_name: row.text("stage_name")?,
                },
            );
        }
    }
    for (upstream, dependent) in edges {
        if let Some(r) = ready.get(&dependent) {
            by_run.entry(upstream).or_default().push(r.clone());
        }
    }
    for list in by_run.values_mut() {
        list.sort_by_key(|r| r.run_id);
    }
    Ok(by_run)
}
