-- Job-queue state (uniphys_queue owns this schema; nothing else writes SQL).
-- SQLite flavour of migrations/postgres (same tables, columns and indexes; JSON stored as TEXT).
-- Times are INTEGER milliseconds since the Unix epoch, taken from the database clock.
-- Ids are database identities; the API shows them with a prefix (tenant_1, asset_1, job_1, run_1).

CREATE TABLE tenants (
    id            INTEGER PRIMARY KEY AUTOINCREMENT,
    name          TEXT   NOT NULL UNIQUE,
    created_at_ms BIGINT NOT NULL
);

-- API keys are stored as SHA-256 digests only; the plaintext is shown once, at creation.
CREATE TABLE api_keys (
    id            INTEGER PRIMARY KEY AUTOINCREMENT,
    tenant_id     BIGINT NOT NULL REFERENCES tenants (id) ON DELETE CASCADE,
    key_sha256    BLOB   NOT NULL UNIQUE,
    label         TEXT   NOT NULL,
    created_at_ms BIGINT NOT NULL,
    revoked_at_ms BIGINT
);

-- One row per distinct content per tenant: re-submitting the same bytes finds this row.
CREATE TABLE assets (
    id             INTEGER PRIMARY KEY AUTOINCREMENT,
    tenant_id      BIGINT NOT NULL REFERENCES tenants (id) ON DELETE CASCADE,
    content_digest TEXT   NOT NULL,
    source_uri     TEXT   NOT NULL,
    size_bytes     BIGINT NOT NULL,
    created_at_ms  BIGINT NOT NULL,
    UNIQUE (tenant_id, content_digest)
);

-- One row per run of the pipeline on an asset; `dag` is the submitted stage graph.
CREATE TABLE jobs (
    id             INTEGER PRIMARY KEY AUTOINCREMENT,
    tenant_id      BIGINT NOT NULL REFERENCES tenants (id) ON DELETE CASCADE,
    asset_id       BIGINT NOT NULL REFERENCES assets (id) ON DELETE CASCADE,
    state          TEXT   NOT NULL CHECK (state IN ('running', 'succeeded', 'dead', 'cancelled')),
    priority       BIGINT NOT NULL,
    dag            TEXT   NOT NULL,
    created_at_ms  BIGINT NOT NULL,
    finished_at_ms BIGINT
);
CREATE INDEX jobs_asset_idx ON jobs (asset_id, id);
CREATE INDEX jobs_tenant_idx ON jobs (tenant_id, id);
CREATE INDEX jobs_finished_idx ON jobs (finished_at_ms) WHERE finished_at_ms IS NOT NULL;

-- The hot table: one row per stage of a job. `attempt` is the fencing token (bumped at claim,
-- never reset); `blocking_deps` counts unfinished upstream stages.
CREATE TABLE stage_runs (
    id                  INTEGER PRIMARY KEY AUTOINCREMENT,
    job_id              BIGINT NOT NULL REFERENCES jobs (id) ON DELETE CASCADE,
    tenant_id           BIGINT NOT NULL,
    asset_id            BIGINT NOT NULL,
    stage_name          TEXT   NOT NULL,
    state               TEXT   NOT NULL
        CHECK (state IN ('blocked', 'ready', 'running', 'succeeded', 'dead', 'cancelled')),
    blocking_deps       BIGINT NOT NULL,
    attempt             BIGINT NOT NULL DEFAULT 0,
    max_attempts        BIGINT NOT NULL,
    attempts_per_retry  BIGINT NOT NULL,
    priority            BIGINT NOT NULL,
    run_after_ms        BIGINT NOT NULL,
    lease_expires_at_ms BIGINT,
    worker_id           TEXT,
    errors              TEXT   NOT NULL DEFAULT '[]',
    output_manifest     TEXT,
    cost                TEXT,
    created_at_ms       BIGINT NOT NULL,
    started_at_ms       BIGINT,
    finished_at_ms      BIGINT,
    UNIQUE (job_id, stage_name)
);
-- Claim order: priority, then age; partial so the index holds only claimable rows.
CREATE INDEX stage_runs_claim_idx ON stage_runs (stage_name, priority DESC, run_after_ms, id)
    WHERE state = 'ready';
CREATE INDEX stage_runs_lease_idx ON stage_runs (lease_expires_at_ms) WHERE state = 'running';
CREATE INDEX stage_runs_finished_idx ON stage_runs (finished_at_ms, stage_name)
    WHERE finished_at_ms IS NOT NULL;

-- Edges of the stage DAG: `stage_run_id` waits for `depends_on_id`.
CREATE TABLE stage_deps (
    depends_on_id BIGINT NOT NULL REFERENCES stage_runs (id) ON DELETE CASCADE,
    stage_run_id  BIGINT NOT NULL REFERENCES stage_runs (id) ON DELETE CASCADE,
    PRIMARY KEY (depends_on_id, stage_run_id)
);
-- Deleting a run (retention) finds the edges that point at it through this index.
CREATE INDEX stage_deps_run_idx ON stage_deps (stage_run_id);

-- Stage names whose runs are not claimed while listed here.
CREATE TABLE paused_stages (
    stage_name   TEXT   PRIMARY KEY,
    paused_at_ms BIGINT NOT NULL
);

-- Append-only history of transitions, purged with its job.
CREATE TABLE events (
    id           INTEGER PRIMARY KEY AUTOINCREMENT,
    job_id       BIGINT NOT NULL REFERENCES jobs (id) ON DELETE CASCADE,
    stage_run_id BIGINT,
    stage_name   TEXT,
    kind         TEXT   NOT NULL,
    attempt      BIGINT,
    detail       TEXT,
    at_ms        BIGINT NOT NULL
);
CREATE INDEX events_job_idx ON events (job_id, id);
CREATE INDEX events_at_idx ON events (at_ms);
