//! Real objects for `decompose-bench --partnet`: every PartNet-Mobility object merged into one
//! mesh at rest (links at joint value 0, as the URDF places them), with no names, groups,
//! colours, materials or textures, and the true part of every face.
//!
//! A true part is a link with its geometry, together with the links fixed to it (a handle fixed
//! to a door moves with the door, so no decomposition could tell them apart). Its joint kind is
//! that of the joint that moves it (`None` for the root and the parts fixed to it).

use std::path::Path;

use anyhow::Context;
use uniphys_geometry::{MeshAsset, MeshPart, TriMesh};
use uniphys_mesh_io::{IngestOptions, load_asset};
use uniphys_types::JointKind;

use crate::categories::read_categories;
use crate::object_dirs::{folder_name, object_dirs};

/// One real object, merged, with its true parts.
pub(crate) struct RealCase {
    /// Folder name.
    pub name: String,
    /// Category from `INDEX.tsv`, `?` if absent.
    pub category: String,
    /// The object as one part with no materials.
    pub asset: MeshAsset,
    /// True part of every face of `asset`'s single part.
    pub truth: Vec<u32>,
    /// Per true part, the kind of joint that moves it (`None`: rigid with the root).
    pub motion: Vec<Option<JointKind>>,
    /// Per true part, the name of its link (the URDF's link name).
    pub part_names: Vec<String>,
}

/// An object that failed to load: its folder name and why.
pub(crate) type LoadFailure = (String, String);

/// Loads every object folder of `root` that `wanted` accepts; objects that fail to load are
/// returned with the reason.
pub(crate) fn real_cases(
    root: &Path,
    wanted: &dyn Fn(&str) -> bool,
) -> anyhow::Result<(Vec<RealCase>, Vec<LoadFailure>)> {
    let categories = read_categories(root);
    let options = IngestOptions {
        max_triangles: 2_000_000,
        ..IngestOptions::default()
    };
    let mut cases = Vec::new();
    let mut failed = Vec::new();
    for dir in object_dirs(root, wanted)? {
        let name = folder_name(&dir);
        let urdf = dir.join("mobility.urdf");
        match load_asset(&urdf, &options).with_context(|| format!("{}", urdf.display())) {
            Ok(loaded) => {
                let (asset, truth, motion, part_names) = merged_at_rest(&loaded.asset);
                cases.push(RealCase {
                    category: categories
                        .get(&name)
                        .cloned()
                        .unwrap_or_else(|| "?".to_owned()),
                    name,
                    asset,
                    truth,
                    motion,
                    part_names,
                });
            }
            Err(error) => failed.push((name, format!("{error:#}"))),
        }
    }
    Ok((cases, failed))
}

/// The asset's parts as one mesh without colours or materials, the true part of each face
/// (parts fixed to their parent join it), each true part's joint kind and name.
fn merged_at_rest(asset: &MeshAsset) -> (MeshAsset, Vec<u32>, Vec<Option<JointKind>>, Vec<String>) {
    let parts = asset.parts.len();
    // Each part's rigid group: follow fixed joints up to a part that moves or the root.
    let mut parent_fixed: Vec<Option<usize>> = vec![None; parts];
    let mut kind: Vec<Option<JointKind>> = vec![None; parts];
    for joint in &asset.joints {
        let child = joint.child.0 as usize;
        if child >= parts {
            continue;
        }
        if joint.kind == JointKind::Fixed {
            parent_fixed[child] = Some(joint.parent.0 as usize);
        } else {
            kind[child] = Some(joint.kind);
        }
    }
    let group_head = |mut p: usize| {
        for _ in 0..parts {
            match parent_fixed[p] {
                Some(up) if kind[p].is_none() => p = up,
                _ => break,
            }
        }
        p
    };
    let mut label_of_head: Vec<Option<u32>> = vec![None; parts];
    let mut motion = Vec::new();
    let mut names = Vec::new();
    let mut truth = Vec::new();
    for (i, part) in asset.parts.iter().enumerate() {
        let head = group_head(i);
        let label = *label_of_head[head].get_or_insert_with(|| {
            motion.push(kind[head]);
            names.push(asset.parts[head].name.clone());
            u32::try_from(motion.len() - 1).unwrap_or(u32::MAX)
        });
        truth.extend(std::iter::repeat_n(label, part.mesh.triangle_count()));
    }
    let merged = asset.merged();
    let bare = TriMesh {
        positions: merged.positions,
        triangles: merged.triangles,
        uvs: None,
        vertex_colors: None,
        face_materials: None,
    };
    let single = MeshAsset {
        parts: vec![MeshPart {
            name: "object".into(),
            mesh: bare,
        }],
        materials: Vec::new(),
        textures: Vec::new(),
        joints: Vec::new(),
    };
    (single, truth, motion, names)
}

/// Writes `case`'s merged mesh, true parts and the labels after every kept step of
/// `decomposition` to `<dir>/<name>.json`.
pub(crate) fn dump_steps(
    dir: &Path,
    case: &RealCase,
    decomposition: &uniphys_decompose::Decomposition,
) -> anyhow::Result<()> {
    let mesh = &case.asset.parts[0].mesh;
    let positions: Vec<[f64; 3]> = mesh.positions.iter().map(|p| p.to_array()).collect();
    let steps: serde_json::Map<String, serde_json::Value> = decomposition
        .steps
        .iter()
        .map(|s| (s.step.clone(), serde_json::json!(s.face_part)))
        .collect();
    let motion: Vec<Option<String>> = case
        .motion
        .iter()
        .map(|m| m.map(|k| format!("{k:?}").to_lowercase()))
        .collect();
    let value = serde_json::json!({
        "positions": positions,
        "triangles": mesh.triangles,
        "truth": case.truth,
        "part_names": case.part_names,
        "motion": motion,
        "steps": steps,
        "final": decomposition.face_part,
    });
    std::fs::create_dir_all(dir)?;
    let path = dir.join(format!("{}.json", case.name));
    std::fs::write(&path, serde_json::to_vec(&value)?)
        .with_context(|| format!("writing {}", path.display()))?;
    Ok(())
}
