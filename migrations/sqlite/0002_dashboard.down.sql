DROP INDEX stage_runs_open_idx;
DROP INDEX stage_runs_tenant_open_idx;
DROP INDEX jobs_tenant_state_idx;
DROP TABLE batch_items;
