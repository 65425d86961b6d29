-- Claim order: priority, then the run's age (its id: a job's runs are made when it is
-- submitted), no longer when it became due. A run put back after its worker died, or retried
-- after its backoff, is claimed before work submitted after it instead of behind the whole
-- backlog. Runs still in their backoff stay in the index and are skipped by the claim's filter.
DROP INDEX stage_runs_claim_idx;
CREATE INDEX stage_runs_claim_idx ON stage_runs (stage_name, priority DESC, id)
    WHERE state = 'ready';
