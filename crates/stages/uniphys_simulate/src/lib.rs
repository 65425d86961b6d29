//! Dynamic check of an articulated asset in a physics engine (rapier, reduced-coordinate
//! multibody): does the asset at rest stay at rest, and does each joint driven to its limits
//! reach them without exploding? Verdict and metrics per movable joint, for `report.json`.
//!
//! Frames and units: everything comes in the object frame (Z up, metres, radians), as the
//! [`uniphys_types::AssetRecord`] holds it; joint coordinates are 0 at the exported rest pose.
//! The engine runs in `f32`; the analysis around it is `f64`.
//!
//! Collision-filter policy: contacts are ignored between the parent and child of every joint,
//! between parts welded by fixed joints, and between the caller's excluded pairs (the touching
//! pairs the exporter writes as MJCF `<contact><exclude>`); every other pair collides, as in
//! the exported MJCF.
//!
//! The criteria and their thresholds are documented where they are applied: the at-rest test
//! in `rest.rs`, the drive test in `drive.rs`, the defaults in [`DynamicParams`].

mod check;
mod drive;
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
