//! The conformance suite: one set of cases, run against SQLite always and against PostgreSQL
//! when `UNIPHYS_TEST_DATABASE_URL` is set (with `CI` set, a missing or unreachable Postgres
//! fails the Postgres cases instead of skipping them). Each case gets its own database (a temp
//! SQLite file, or a fresh Postgres schema), so cases run in parallel.

mod harness;

mod batch_complete;
mod claim;
mod control;
mod dag;
mod fencing;
mod listing;
mod retention;
mod retry;
mod schema;
mod stats;
mod submit;
mod worker_reads;

/// Declares each case once per backend: `sqlite::name` and `postgres::name`.
macro_rules! conformance {
    ($($module:ident :: $case:ident),* $(,)?) => {
        mod sqlite {
            $(
                #[tokio::test(flavor = "multi_thread", worker_threads = 4)]
                async fn $case() {
                    crate::$module::$case(uniphys_queue::Backend::Sqlite).await;
                }
            )*
        }
        mod postgres {
            $(
                #[tokio::test(flavor = "multi_thread", worker_threads = 4)]
                async fn $case() {
                    crate::$module::$case(uniphys_queue::Backend::Postgres).await;
                }
            )*
        }
    };
}

conformance!(
    submit::resubmitting_the_same_content_returns_the_same_asset_and_job,
    submit::concurrent_resubmits_create_one_asset_and_one_job,
    submit::concurrent_capped_submissions_stop_at_the_backlog_cap,
    submit::invalid_or_foreign_submissions_store_nothing,
    submit::api_keys_are_stored_hashed_and_resolve_to_their_tenant,
    submit::tenant_names_are_validated,
    claim::concurrent_claimers_get_each_run_exactly_once,
    claim::claim_counts_the_attempt_and_sets_the_lease,
    claim::claims_follow_priority_then_age,
    claim::claims_only_take_the_named_stages,
    claim::a_recovered_run_is_claimed_before_newer_work,
    batch_complete::a_batch_completes_each_run_and_fences_the_stale_one,
    batch_complete::a_job_whose_last_runs_share_a_batch_succeeds_once,
    batch_complete::the_completer_answers_every_concurrent_completion,
    fencing::a_reclaimed_run_rejects_the_stale_worker,
    fencing::heartbeat_keeps_the_lease_alive,
    fencing::completing_twice_is_refused,
    fencing::expired_leases_are_recovered_with_an_error_record,
    fencing::a_crash_loop_is_dead_lettered_after_max_attempts,
    retry::transient_failures_wait_for_their_backoff,
    retry::exhausted_attempts_dead_letter_with_the_error_history,
    retry::permanent_failures_dead_letter_at_once,
    retry::retrying_a_dead_job_grants_a_fresh_budget_and_keeps_history,
    dag::completion_unblocks_dependents_in_dag_order,
    dag::concurrent_last_completions_finish_the_job_once,
    dag::fan_in_waits_for_every_parent_under_concurrency,
    control::cancel_stops_unfinished_runs_and_fences_the_worker,
    control::a_cancelled_job_is_retried_and_its_old_worker_stays_fenced,
    control::pause_holds_claims_until_resume,
    stats::stats_count_each_state_and_the_throughput,
    listing::listing_filters_and_pages_a_tenants_jobs,
    listing::table_health_reports_the_hot_table,
    retention::purge_removes_only_jobs_finished_before_the_retention,
    schema::migrations_revert_and_reapply,
    worker_reads::assets_and_backlog_are_per_tenant,
    worker_reads::run_context_carries_the_asset_trace_and_upstream,
    worker_reads::a_released_run_is_claimable_at_once_without_using_an_attempt,
);
