//! Each tenant's backlog (unfinished stage runs) as this API process knows it: counted at most
//! [`FRESH`] ago, plus the runs this process has submitted since. Counting is proportional to
//! the backlog, so counting it exactly for every upload made submissions slow down as a large
//! manifest filled the queue (0.39x the upload rate at 40,000 queued jobs against 1,000).
//!
//! Every submission's runs are held as in flight until it has finished ([`Admission`]). Far
//! from the cap, a submission goes on the estimate; near it, its own transaction counts exactly
//! under the tenant's lock, against the cap less what else this process has in flight. So this
//! process never takes a tenant over its cap, however many of its requests race. What other API processes accept within [`FRESH`] is not in the estimate:
//! with several, the cap may be passed by what the others accept in that second.

use std::collections::HashMap;
use std::sync::{Arc, Mutex, PoisonError};
use std::time::{Duration, Instant};

use uniphys_queue::TenantId;

use crate::error::ApiResult;
use crate::state::ApiState;

/// How old a count may be before it is taken again.
pub(crate) const FRESH: Duration = Duration::from_secs(1);

/// What this process knows of one tenant.
#[derive(Clone, Copy, Debug, Default)]
struct Gauge {
    /// The last count (with what was in flight when it began), and when it began.
    count: u64,
    counted: Option<Instant>,
    /// Runs submitted by this process since that count began.
    added_since: u64,
    /// Runs admitted whose submissions have not finished.
    in_flight: u64,
    /// Every run this process has submitted or admitted, ever (to tell what a count missed).
    added_total: u64,
}

impl Gauge {
    fn fresh(&self) -> bool {
        self.counted.is_some_and(|at| at.elapsed() < FRESH)
    }
}

/// How a submission of new runs may go; its runs count as in flight until it is dropped (once
/// the submission has finished).
#[derive(Debug)]
pub(crate) struct Admission {
    /// `None`: on the estimate, no count in the transaction. `Some(cap)`: near the cap, the
    /// transaction counts, against this cap (the tenant's, less what else this process has in
    /// flight).
    pub(crate) exact_cap: Option<u64>,
    _in_flight: InFlight,
}

/// Runs admitted and not yet submitted; dropping it ends their time in flight.
#[derive(Debug)]
pub(crate) struct InFlight {
    gauge: Arc<BacklogGauge>,
    tenant: TenantId,
    runs: u64,
}

impl Drop for InFlight {
    fn drop(&mut self) {
        let mut tenants = self.gauge.lock();
        if let Some(g) = tenants.get_mut(&self.tenant) {
            g.in_flight = g.in_flight.saturating_sub(self.runs);
        }
    }
}

/// Backlog estimates by tenant.
#[derive(Debug, Default)]
pub(crate) struct BacklogGauge {
    tenants: Mutex<HashMap<TenantId, Gauge>>,
}

impl BacklogGauge {
    fn lock(&self) -> std::sync::MutexGuard<'_, HashMap<TenantId, Gauge>> {
        self.tenants.lock().unwrap_or_else(PoisonError::into_inner)
    }

    /// Counts `tenant`'s backlog now and keeps it; returns the estimate. Runs in flight when
    /// the count begins, and runs added while it runs, are added to it (some may be counted
    /// twice, which only errs towards the exact check).
    pub(crate) async fn recount(&self, state: &ApiState, tenant: TenantId) -> ApiResult<u64> {
        let began = Instant::now();
        let (in_flight, added_before) = {
            let tenants = self.lock();
            let g = tenants.get(&tenant).copied().unwrap_or_default();
            (g.in_flight, g.added_total)
        };
        let counted = state.store.tenant_backlog(tenant).await?;
        let mut tenants = self.lock();
        let g = tenants.entry(tenant).or_default();
        g.count = counted + in_flight;
        g.counted = Some(began);
        g.added_since = g.added_total - added_before;
        Ok(g.count + g.added_since)
    }

    /// The tenant's backlog: the estimate if its count is fresh, else a new count.
    pub(crate) async fn backlog(&self, state: &ApiState, tenant: TenantId) -> ApiResult<u64> {
        if let Some(g) = self.lock().get(&tenant).filter(|g| g.fresh()) {
            return Ok(g.count + g.added_since);
        }
        self.recount(state, tenant).await
    }

    /// How a submission adding `runs` goes under `cap`. Its runs join the estimate at once
    /// (refused ones too, until the next count), so requests racing it see them.
    pub(crate) async fn admit(
        self: &Arc<Self>,
        state: &ApiState,
        tenant: TenantId,
        runs: u64,
        cap: u64,
    ) -> ApiResult<Admission> {
        if !self.lock().get(&tenant).is_some_and(Gauge::fresh) {
            self.recount(state, tenant).await?;
        }
        let mut tenants = self.lock();
        let g = tenants.entry(tenant).or_default();
        let fits = g.count + g.added_since + runs <= cap;
        let exact_cap = (!fits).then(|| cap.saturating_sub(g.in_flight));
        g.in_flight += runs;
        g.added_since += runs;
        g.added_total += runs;
        Ok(Admission {
            exact_cap,
            _in_flight: InFlight {
                gauge: self.clone(),
                tenant,
                runs,
            },
        })
    }
}
