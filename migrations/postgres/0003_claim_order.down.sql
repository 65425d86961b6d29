DROP INDEX stage_runs_claim_idx;
CREATE INDEX stage_runs_claim_idx ON stage_runs (stage_name, priority DESC, run_after_ms, id)
    WHERE state = 'ready';
