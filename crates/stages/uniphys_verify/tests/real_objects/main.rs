//! The verifier on real objects of the shared PartNet-Mobility set
//! (`../shared/data/partnet-mobility/` beside the repository): true joints handed over as a
//! grounder's (swept and correctable) pass unchanged, and deliberately broken ones are caught
//! and put back. `scripts/bench` (verify-bench) measures the whole set.

mod hinges;
mod ranges;
mod slides;
mod support;
mod true_joints;
