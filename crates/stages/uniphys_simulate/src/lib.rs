//! Dynamic check of an articulated asset in a physics engine (rapier, reduced-coordinate
//! multibody): does the asset at rest stay at rest, and does each joint driven to its limits
//! reach them without exploding? Verdict and metrics per movable joint, for `report.json`.
//!
//! Frames and units: everything comes in the object frame (Z up, metres, radians), as the
//! [`uniphys_types::AssetRecord`] holds it; joint coordinates are 0 at the exported rest pose.
//! The engine runs in `f32`; the analysis around it is `f64`. A step in which the engine itself
//! fails (an assert on a state that is no longer finite) counts as non-finite states, not as a
//! crash (`engine_guard.rs`).
//!
//! Collision-filter policy: contacts are ignored between the parent and child of every joint,
//! between parts welded by fixed joints, and between the caller's excluded pairs (the touching
//! pairs the exporter writes as MJCF `<contact><exclude>`); every other pair collides, as in
//! the exported MJCF.
//!
//! The criteria and their thresholds are documented where they are applied: the at-rest test
//! in `rest.rs`, the drive test in `drive.rs`, the defaults in [`DynamicParams`]. In short: at
//! rest a joint passes if it drifts less than 2 % of its range; drift that gravity explains
//! (load above the joint's friction, in the direction of the load, without swinging) is a
//! warning; any other drift, a swing, a rest pose outside the limits or an explosion fails. The
//! drive passes if a bounded velocity servo reaches both limits in time, nothing moves faster
//! than 10 object diagonals per second, no other joint is kicked beyond 5 % of its range, and
//! mechanical energy does not grow after release.
//!
//! Scope: one world for the at-rest test, one fresh world per movable joint for its drive.
//! Continuous joints are driven to -pi/2 and +pi/2. `Joint::coupled_parts` is not read: parts
//! that move together are already joined by fixed joints in the record's tree. Contacts use the
//! parts' Coulomb friction coefficients; there is no floor (the root is fixed).

mod check;
mod drive;
mod engine_guard;
mod error;
mod filter;
mod model;
mod params;
mod report;
mod rest;
mod scene;
mod trace;

pub use check::check_dynamics;
pub use error::{SimulateError, SimulateResult};
pub use params::DynamicParams;
pub use report::{DriveMetrics, DynamicReport, JointDynamics, RestMetrics, SECTION_NAME, Verdict};
