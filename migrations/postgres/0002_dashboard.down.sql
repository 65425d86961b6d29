DROP INDEX jobs_tenant_state_idx;
DROP TABLE batch_items;
