//! The built-in grounder: assigns materials, intrinsic properties, object properties and an
//! articulation without any model or network. Every value it produces names it
//! ([`BUILTIN_PROVIDER`]) in its provenance, or says it is a default.
//!
//! - materials from glTF/MTL material names, then part names, then the kind's body material
//!   ([`ground_part`]);
//! - properties from typical values of known subtypes or the centre of the material prior;
//! - the object's kind from what the input names ([`object_kind`]): its typical size, mass and
//!   body material (`uniphys_types::CategoryPrior`);
//! - object name, category, dimensions and mass ([`object_properties`]);
//! - how much material a part holds: its solid or a wall along its surface, whichever is less
//!   ([`part_mass_model`]); the walls' thickness calibrated by the kind's typical mass
//!   ([`wall_factor`]);
//! - joints ([`articulate`]): declared ones completed; when no part name says that it slides or
//!   turns, from geometry alone (`unnamed`): the tree from size, contact and the ground
//!   (`tree`), and each part's joint from its shape and sweeps of its candidate motions
//!   (`motion_search`): round parts spin (`spin`), small ones are pushed or turned
//!   (`small_part`), panels hinge away from
//!   their handle (`handle`: what stands out of the outer face against the face around it),
//!   parts held by one small flat patch twist about its normal (`stem`),
//!   parts in an opening slide; a slide's range is its free travel, a hinge's comes from sweeping it both
//!   ways with the stops real hinges have (`hinge_range`); otherwise part names say which parts
//!   slide or turn and the joint of each is chosen by sweeping hypotheses (`hypotheses`:
//!   candidate axes x pivots x direction from the contact with its parent) with simple priors;
//!   passive dynamics from the moving parts' inertia
//!   ([`joint_dynamics`]).

mod articulate;
mod calibrate;
mod dynamics;
mod error;
mod hinge_range;
mod hypotheses;
mod intrinsic;
mod joint_geometry;
mod material_guess;
mod motion_search;
mod object;
mod roles;
mod small_part;
mod spin;
mod stem;
#[cfg(test)]
mod test_points;
mod tree;
mod unnamed;
mod wall;

pub use articulate::{Articulation, PartInput, articulate, sanitize};
pub use calibrate::{MAX_WALL_FACTOR, TYPICAL_MASS_WEIGHT, wall_factor};
pub use dynamics::{
    DAMPING_TIME_CONSTANT_SECS, FRICTION_FRACTION_OF_WEIGHT, HOLDING_MARGIN,
    MIN_DAMPING_TIME_CONSTANT_SECS, RigidMass, holding_friction, joint_dynamics,
    max_stable_damping, parallel_axis,
};
pub use error::{GroundError, GroundResult};
pub use object::{ObjectKind, object_kind, object_properties};
pub use wall::{PartMassInput, PartMassModel, part_mass_model, wall_thickness_m, walls_matter};

use uniphys_types::PartProperties;

/// Provider name of the built-in grounder, as it appears in provenance.
pub const BUILTIN_PROVIDER: &str = "builtin-grounder";

/// Material and intrinsic properties of one part from its material names, its part name and the
/// object's kind (whose body material stands in when no name says anything).
#[must_use]
pub fn ground_part(
    material_names: &[&str],
    part_name: &str,
    kind: Option<&ObjectKind>,
) -> PartProperties {
    let (material, provenance) = material_guess::guess_material(material_names, part_name, kind);
    intrinsic::part_properties(material, provenance, part_name)
}
