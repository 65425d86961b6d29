//! The exported colliders of a real table with two drawers (kitchen-28164 of the shared
//! PartNet-Mobility set, as shipped): the table's convex hulls leave the drawers' slots empty,
//! so a gripper can reach in once a drawer is out.

use uniphys_examples::shared_partnet_object;
use uniphys_geometry::DVec3;
use uniphys_pipeline::{NoProgress, RunOptions, run};
use uniphys_types::JointKind;

/// The vertices and triangles of an OBJ written by the export.
fn obj(bytes: &[u8]) -> (Vec<DVec3>, Vec<[usize; 3]>) {
    let text = String::from_utf8_lossy(bytes);
    let (mut vertices, mut faces) = (Vec::new(), Vec::new());
    for line in text.lines() {
        let mut words = line.split_whitespace();
        match words.next() {
            Some("v") => {
                let v: Vec<f64> = words.filter_map(|w| w.parse().ok()).collect();
                vertices.push(DVec3::new(v[0], v[1], v[2]));
            }
            Some("f") => {
                let f: Vec<usize> = words
                    .filter_map(|w| w.split('/').next()?.parse::<usize>().ok())
                    .map(|i| i - 1)
                    .collect();
                faces.push([f[0], f[1], f[2]]);
            }
            _ => {}
        }
    }
    (vertices, faces)
}

/// Whether `p` lies inside the closed convex hull (`vertices`, `faces`), at least `margin`
/// from its faces.
fn inside_hull(p: DVec3, vertices: &[DVec3], faces: &[[usize; 3]], margin: f64) -> bool {
    let centre = vertices.iter().sum::<DVec3>() / vertices.len() as f64;
    faces.iter().all(|f| {
        let [a, b, c] = f.map(|i| vertices[i]);
        let mut n = (b - a).cross(c - a).normalize_or_zero();
        if n.dot(centre - a) > 0.0 {
            n = -n;
        }
        n.dot(p - a) < -margin
    })
}

#[test]
fn a_tables_hulls_leave_its_drawers_slots_empty() {
    let mut options = RunOptions::default();
    options.verify.dynamics = None;
    let out = run(
        &shared_partnet_object("kitchen-28164"),
        &options,
        &NoProgress,
    )
    .expect("pipeline runs");
    let record = &out.record;
    let root = record
        .parts
        .iter()
        .find(|p| p.id == record.root)
        .expect("the root part");
    // The root's link frame is the object frame.
    let hulls: Vec<(Vec<DVec3>, Vec<[usize; 3]>)> = out
        .artifacts
        .iter()
        .filter(|a| {
            a.path
                .starts_with(&format!("meshes/part_{}_collision_", root.id.0))
        })
        .map(|a| obj(&a.bytes))
        .collect();
    assert!(!hulls.is_empty(), "the table has colliders");
    let drawers: Vec<_> = record
        .joints
        .iter()
        .filter(|j| j.kind == JointKind::Prismatic && j.parent == record.root)
        .collect();
    assert_eq!(drawers.len(), 2, "{:?}", record.joints);
    for drawer in drawers {
        let part = record
            .parts
            .iter()
            .find(|p| p.id == drawer.child)
            .expect("the drawer part");
        let [lo, hi] = part.bounds_in_object_m.map(DVec3::from_array);
        // The middle of the drawer's box and points halfway to its corners.
        let centre = 0.5 * (lo + hi);
        let probes: Vec<DVec3> = (0..8)
            .map(|k| {
                let corner = DVec3::new(
                    if k & 1 == 0 { lo.x } else { hi.x },
                    if k & 2 == 0 { lo.y } else { hi.y },
                    if k & 4 == 0 { lo.z } else { hi.z },
                );
                0.5 * (centre + corner)
            })
            .chain([centre])
            .collect();
        let margin = 1e-3 * (hi - lo).length();
        for p in probes {
            assert!(
                !hulls.iter().any(|(v, f)| inside_hull(p, v, f, margin)),
                "{}: the table's hulls fill its slot at {p:?}",
                part.name
            );
        }
    }
}
