//! Domain types of the UniPhys service: parts, materials, intrinsic physical properties, joints,
//! the provenance of every value, verification reports, and unit conversions. No IO.
//!
//! All quantities are SI inside the code (metres, kilograms, seconds, pascals, radians); the
//! conversions to the units of the LVLM contract and the UniPhys-40K dataset (g/cm^3, GPa, HV, cm,
//! degrees) live in [`units`] and are applied only at the edges.

mod asset;
mod category;
mod category_table;
mod error;
mod grounded;
mod ids;
mod joint;
mod material;
mod properties;
mod provenance;
mod report;
mod service_stage;
mod summary;
pub mod units;
mod verified;
pub mod words;

pub use asset::{
    AssetRecord, PartMass, PartRecord, SCHEMA_VERSION, SourceFormat, SourceInfo, UpAxis,
};
pub use category::{
    CATEGORY_PRIORS, CategoryPrior, HOLLOW, MASS_BAND_FACTOR, PACKED, SIZE_BAND_FACTOR, SOLID,
};
pub use error::{TypesError, TypesResult};
pub use grounded::{GROUNDED_VERSION, GroundedAsset, Hull};
pub use ids::PartId;
pub use joint::{Joint, JointKind, JointLimits};
pub use material::{Material, MaterialCategory, MaterialPrior, PriorRange};
pub use properties::{Descriptions, ObjectProperties, PartProperties};
pub use provenance::{Estimate, Provenance};
pub use report::{CheckOutcome, CheckResult, ReportSection, VerificationReport};
pub use service_stage::ServiceStage;
pub use summary::{
    ConvertSummary, DatasetFacts, DecomposeStageSummary, GroundSummary, InferSummary,
    IngestSummary, VerifySummary,
};
pub use verified::{VERIFIED_VERSION, VerifiedAsset};
