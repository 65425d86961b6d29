DROP TABLE events;
DROP TABLE paused_stages;
DROP TABLE stage_deps;
DROP TABLE stage_runs;
DROP TABLE jobs;
DROP TABLE assets;
DROP TABLE api_keys;
DROP TABLE tenants;
