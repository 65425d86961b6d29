-- Batches and the dashboard's lists.

-- A batch is a tenant's label on a set of jobs (a dataset build), for its statistics. A job can be
-- in several batches: re-submitting known content into a new batch adds the existing job to it.
CREATE TABLE batch_items (
    tenant_id   BIGINT NOT NULL REFERENCES tenants (id) ON DELETE CASCADE,
    batch       TEXT   NOT NULL,
    job_id      BIGINT NOT NULL REFERENCES jobs (id) ON DELETE CASCADE,
    added_at_ms BIGINT NOT NULL,
    PRIMARY KEY (tenant_id, batch, job_id)
);
-- Retention deletes jobs; the cascade finds their batch rows through this index.
CREATE INDEX batch_items_job_idx ON batch_items (job_id);

-- A tenant's jobs in one state, newest first, and its counts by state, without a scan of all its
-- jobs (the dashboard's running and dead-letter lists at 100,000 assets).
CREATE INDEX jobs_tenant_state_idx ON jobs (tenant_id, state, id);

-- Counts that every upload (the tenant's backlog cap) and the statistics (every stage's open and
-- dead runs) take, read from these partial indexes instead of a scan of every run ever made.
CREATE INDEX stage_runs_tenant_open_idx ON stage_runs (tenant_id, state)
    WHERE state IN ('blocked', 'ready', 'running');
CREATE INDEX stage_runs_open_idx ON stage_runs (stage_name, state, run_after_ms)
    WHERE state IN ('blocked', 'ready', 'running', 'dead');
