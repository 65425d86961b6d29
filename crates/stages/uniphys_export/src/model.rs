//! The simulator-neutral model both URDF and MJCF are written from: one link per part, its
//! frame, mass properties and mesh files, and the joints in tree order.

use uniphys_geometry::{DMat3, DVec3, with_triangle_margin};
use uniphys_types::{AssetRecord, Joint, JointKind, PartId};

use crate::visuals::{Visual, link_visuals};
use crate::{ExportError, ExportInput, ExportResult};

/// One link (rigid body) of the export: a part.
#[derive(Debug, Clone)]
pub(crate) struct Link {
    pub id: PartId,
    /// Unique ASCII name: `part_<id>_<sanitised part name>`.
    pub name: String,
    /// Origin of the link frame in the object frame; the link's axes are the object's axes.
    pub anchor: DVec3,
    pub mass_kg: f64,
    /// Centre of mass in the link frame.
    pub com_in_link: DVec3,
    pub inertia_kg_m2: DMat3,
    pub friction: f64,
    pub rgba: [f32; 4],
    /// Visual meshes: one in `rgba`, or one per textured material and one for the rest.
    pub visuals: Vec<Visual>,
    /// Collision mesh file stems (`part_<id>_collision_<k>`).
    pub collision_stems: Vec<String>,
}

/// The export model: links indexed like the record's parts, and joints from root to leaves.
#[derive(Debug, Clone)]
pub(crate) struct Model<'a> {
    pub name: String,
    pub links: Vec<Link>,
    pub root: usize,
    /// Joints ordered so that a parent's joint precedes its children's.
    pub joints: Vec<&'a Joint>,
    /// Pairs of links (indices, smaller first) whose contacts the MJCF excludes, and why.
    pub exclude_pairs: Vec<(usize, usize, ExcludeReason)>,
}

/// How `report.json` names contacts excluded because the parts touch at rest.
pub(crate) const TOUCH_AT_REST: &str = "touch at rest";

/// Why two links' contacts are excluded.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub(crate) enum ExcludeReason {
    /// A joint connects them.
    Jointed,
    /// They touch at rest.
    TouchAtRest,
}

impl ExcludeReason {
    /// The reason as `report.json` names it.
    pub(crate) fn label(self) -> &'static str {
        match self {
            Self::Jointed => "jointed",
            Self::TouchAtRest => TOUCH_AT_REST,
        }
    }
}

impl<'a> Model<'a> {
    pub(crate) fn build(input: &ExportInput<'a>) -> ExportResult<Self> {
        let record: &AssetRecord = input.record;
        record.validate()?;
        let n = record.parts.len();
        if input.part_meshes.len() != n
            || input.colliders.len() != n
            || input.part_colors.len() != n
        {
            return Err(ExportError::InputMismatch(format!(
                "{n} parts but {} meshes, {} collider sets and {} colours",
                input.part_meshes.len(),
                input.colliders.len(),
                input.part_colors.len()
            )));
        }
        let index_of = |id: PartId| record.parts.iter().position(|p| p.id == id);
        let root = index_of(record.root)
            .ok_or_else(|| ExportError::InputMismatch("root is not a part".into()))?;
        let mut links = Vec::with_capacity(n);
        for (i, part) in record.parts.iter().enumerate() {
            let anchor = link_anchor(record, i);
            let com = DVec3::from_array(part.mass.com_in_object_m);
            // A zero-thickness part is a lamina (A + B = C exactly): keep it off the bound.
            let inertia = with_triangle_margin(
                DMat3::from_cols_array_2d(&part.mass.inertia_about_com_kg_m2).transpose(),
            );
            let collision_stems = (0..input.colliders[i].len())
                .map(|k| format!("{}_collision_{k}", part.id))
                .collect();
            let name = format!("{}_{}", part.id, sanitize(&part.name));
            let visuals = link_visuals(
                &part.id.to_string(),
                &name,
                &input.part_meshes[i],
                input.materials,
                input.part_colors[i],
            );
            links.push(Link {
                id: part.id,
                name,
                anchor,
                mass_kg: part.mass.mass_kg.value,
                com_in_link: com - anchor,
                inertia_kg_m2: inertia,
                friction: part.properties.friction_coefficient.value,
                rgba: input.part_colors[i],
                visuals,
                collision_stems,
            });
        }
        // Parents before children: by depth in the tree, then by child id.
        let mut joints: Vec<&Joint> = record.joints.iter().collect();
        joints.sort_by_key(|j| (depth(record, j.child), j.child));
        // A part never collides with the part it is jointed to (MuJoCo's own parent filter skips
        // bodies welded to the world, so the root's children need it said) nor with a part it
        // touches at rest (their hulls overlap where the meshes meet).
        let mut exclude_pairs = Vec::new();
        let jointed = record
            .joints
            .iter()
            .map(|j| (j.parent, j.child, ExcludeReason::Jointed));
        let touching = input
            .touching_pairs
            .iter()
            .map(|&(a, b)| (a, b, ExcludeReason::TouchAtRest));
        for (a, b, why) in jointed.chain(touching) {
            if let (Some(ia), Some(ib)) = (index_of(a), index_of(b))
                && ia != ib
            {
                exclude_pairs.push((ia.min(ib), ia.max(ib), why));
            }
        }
        exclude_pairs.sort_unstable();
        exclude_pairs.dedup_by_key(|(a, b, _)| (*a, *b));
        Ok(Self {
            name: sanitize(&record.name),
            links,
            root,
            joints,
            exclude_pairs,
        })
    }

    pub(crate) fn link(&self, id: PartId) -> &Link {
        self.links
            .iter()
            .find(|l| l.id == id)
            .expect("joints reference parts; checked by AssetRecord::validate")
    }

    /// Position of the child link frame in the parent link frame.
    pub(crate) fn joint_origin(&self, joint: &Joint) -> DVec3 {
        self.link(joint.child).anchor - self.link(joint.parent).anchor
    }
}

/// The origin of part `index`'s link frame in the object frame: the object origin for the root,
/// the joint pivot for a jointed part, the centre of mass for a part fixed to another.
pub(crate) fn link_anchor(record: &AssetRecord, index: usize) -> DVec3 {
    let part = &record.parts[index];
    match record.joints.iter().find(|j| j.child == part.id) {
        None => DVec3::ZERO,
        Some(j) if j.kind == JointKind::Fixed => DVec3::from_array(part.mass.com_in_object_m),
        Some(j) => DVec3::from_array(j.pivot_in_object_m),
    }
}

fn depth(record: &AssetRecord, mut part: PartId) -> usize {
    let mut d = 0;
    while let Some(j) = record.joints.iter().find(|j| j.child == part) {
        part = j.parent;
        d += 1;
        if d > record.parts.len() {
            break;
        }
    }
    d
}

/// ASCII letters, digits and `_`; anything else becomes `_`.
pub(crate) fn sanitize(name: &str) -> String {
    let s: String = name
        .chars()
        .map(|c| if c.is_ascii_alphanumeric() { c } else { '_' })
        .collect();
    if s.is_empty() { "part".to_owned() } else { s }
}
