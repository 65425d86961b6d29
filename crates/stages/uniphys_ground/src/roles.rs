//! What a part is for, read from its name: the root body, a sliding or hinged part, or a small
//! attachment (handle, knob) that moves with whatever it is fixed to.

use uniphys_types::words::{first_match, tokens};

/// The role of a part in the articulation heuristic.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Role {
    /// A static body part.
    Body,
    /// A part that slides (drawer, tray).
    Sliding,
    /// A part that turns about a hinge (door, lid, flap).
    Hinged,
    /// A small part fixed to another one (handle, knob).
    Attachment,
}

const SLIDING: [&str; 4] = ["drawer", "tray", "slide", "slider"];
const HINGED: [&str; 8] = [
    "door", "lid", "flap", "cover", "hatch", "gate", "shutter", "cap",
];
const ATTACHMENT: [&str; 6] = ["handle", "knob", "pull", "grip", "button", "hinge"];

/// The role of a part with this name, and the keyword that decided it.
pub(crate) fn role_of(part_name: &str) -> (Role, Option<&'static str>) {
    let toks = tokens(part_name);
    // Attachment keywords win: a "door_handle" is a handle, not a door.
    if let Some(k) = first_match(&toks, &ATTACHMENT) {
        return (Role::Attachment, Some(k));
    }
    if let Some(k) = first_match(&toks, &SLIDING) {
        return (Role::Sliding, Some(k));
    }
    if let Some(k) = first_match(&toks, &HINGED) {
        return (Role::Hinged, Some(k));
    }
    (Role::Body, None)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn handles_are_attachments_even_on_doors() {
        assert_eq!(role_of("door_handle").0, Role::Attachment);
        assert_eq!(role_of("Door").0, Role::Hinged);
        assert_eq!(role_of("top_drawer").0, Role::Sliding);
        assert_eq!(role_of("cabinet_body").0, Role::Body);
        assert_eq!(role_of("lid").1, Some("lid"));
    }
}
