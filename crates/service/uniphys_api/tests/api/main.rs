//! The API suite: each case runs against SQLite always and against PostgreSQL when
//! `UNIPHYS_TEST_DATABASE_URL` is set (with `CI` set, a missing Postgres fails instead of
//! skipping), each on its own database and artifact directory, through `router(state).oneshot`.

mod harness;

mod archives;
mod bad_input;
mod dashboard;
mod exports;
mod listener;
mod ops;
mod status;
mod submit;

/// Declares each case once per backend: `sqlite::name` and `postgres::name`.
macro_rules! cases {
    ($($module:ident :: $case:ident),* $(,)?) => {
        mod sqlite {
            $(
                #[tokio::test(flavor = "multi_thread", worker_threads = 2)]
                async fn $case() {
                    crate::$module::$case(uniphys_queue::Backend::Sqlite).await;
                }
            )*
        }
        mod postgres {
            $(
                #[tokio::test(flavor = "multi_thread", worker_threads = 2)]
                async fn $case() {
                    crate::$module::$case(uniphys_queue::Backend::Postgres).await;
                }
            )*
        }
    };
}

cases!(
    submit::an_upload_creates_an_asset_and_the_same_bytes_return_the_same_ids,
    submit::an_object_in_the_store_is_submitted_by_key,
    submit::a_batch_is_validated_whole_before_anything_is_submitted,
    submit::a_partial_batch_submits_the_valid_items_and_refuses_each_bad_one,
    submit::a_full_backlog_answers_429_with_retry_after,
    submit::concurrent_uploads_never_take_the_tenant_over_its_cap_together,
    archives::an_archived_asset_folder_is_accepted_stored_whole_and_idempotent,
    archives::a_hostile_archive_is_422_with_its_reason_and_stores_nothing,
    archives::a_folder_in_the_store_is_submitted_by_its_prefix,
    bad_input::an_oversize_upload_is_413_and_stores_nothing,
    bad_input::a_malformed_manifest_is_400,
    bad_input::unknown_fields_are_400_naming_the_field,
    bad_input::a_wrong_key_is_401_and_another_tenants_rows_are_404,
    bad_input::invalid_ids_are_400,
    bad_input::bad_filenames_and_keys_are_422,
    bad_input::unsupported_types_and_empty_files_are_refused_at_submission,
    status::status_shows_each_stage_with_progress,
    status::listing_pages_newest_first_with_a_cursor,
    status::cancelling_a_finished_job_is_409,
    status::a_dead_lettered_job_is_retried_and_a_running_one_is_409,
    status::a_cancelled_job_is_offered_on_re_upload_and_retried,
    status::a_completed_stages_artifact_is_listed_and_downloaded,
    ops::the_openapi_document_lists_every_route,
    ops::health_readiness_and_metrics_answer,
    ops::statistics_count_each_stage,
    ops::a_stage_no_worker_takes_is_flagged_unserved,
    ops::an_unreachable_database_is_503_with_retry_after,
    dashboard::the_overview_counts_the_tenants_jobs_and_keeps_a_history,
    dashboard::the_overview_is_computed_once_per_refresh_for_every_viewer,
    dashboard::work_lists_open_stages_and_dead_letters_with_their_errors,
    dashboard::a_batch_counts_its_converted_assets,
    dashboard::the_dashboard_is_served_without_a_key,
    exports::a_batch_is_exported_into_the_store_and_again_adds_only_what_is_new,
);
