//! SRDF output (`model.srdf`, beside `model.urdf`): the pairs of links whose contacts are off, as
//! MoveIt's `<disable_collisions>` names them. URDF itself cannot turn off contacts between links
//! that no joint connects, so a part that touches a non-adjacent one at rest (a handle welded to a
//! door against the cabinet, two doors meeting in the middle, neighbouring knobs whose hulls
//! overlap) would hold the other fast in a loader that reads only the URDF. SAPIEN reads this file
//! beside the URDF and filters the pairs whose reason is `Default` (in contact in the default
//! pose), which is what a pair touching at rest is; jointed pairs are `Adjacent`.

use crate::model::{ExcludeReason, Model};
use crate::xml::Element;

pub(crate) fn write_srdf(model: &Model<'_>) -> String {
    let mut robot = Element::new("robot").attr("name", model.name.clone());
    for &(a, b, why) in &model.exclude_pairs {
        let reason = match why {
            ExcludeReason::Jointed => "Adjacent",
            ExcludeReason::TouchAtRest => "Default",
        };
        robot.push(
            Element::new("disable_collisions")
                .attr("link1", model.links[a].name.clone())
                .attr("link2", model.links[b].name.clone())
                .attr("reason", reason),
        );
    }
    robot.to_document()
}
