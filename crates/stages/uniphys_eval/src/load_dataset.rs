//! Ground truth from a UniPhys-40K entity directory (reference 15.2): `annotations/object.json`,
//! `annotations/part_<id>.json` and `parts/part_<id>.obj`.
//!
//! Units are the dataset's: density g/cm^3, Young's modulus GPa, hardness HV, dimensions cm
//! (converted to metres here), object mass kg, ranges radians (C) or the meshes' length unit
//! (B), `pos` in the part-mesh frame (the frame of `parts/*.obj`, whose bounds give the model
//! frame). Member ids of `dependency` are mapped to part names through the part files.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use serde_json::Value;
use uniphys_types::units::m_from_cm;

use crate::annotated::{
    AnnotatedAsset, AnnotatedJoint, AnnotatedPart, sorted_members, union_bounds,
};
use crate::{EvalError, EvalResult, ObjectValues, PhysicalProperties, normalise_id};

/// Whether `dir` looks like a UniPhys-40K entity (it has `annotations/` with part files).
#[must_use]
pub fn is_dataset_entity(dir: &Path) -> bool {
    dir.join("annotations").is_dir() && !part_files(dir).unwrap_or_default().is_empty()
}

/// `annotations/part_<id>.json` files with their ids, sorted by id.
fn part_files(dir: &Path) -> EvalResult<Vec<(String, PathBuf)>> {
    let annotations = dir.join("annotations");
    let entries = std::fs::read_dir(&annotations).map_err(|source| EvalError::Io {
        path: annotations.clone(),
        source,
    })?;
    let mut out: Vec<(String, PathBuf)> = entries
        .filter_map(Result::ok)
        .map(|e| e.path())
        .filter_map(|p| {
            let stem = p.file_stem()?.to_str()?.to_owned();
            let id = stem.strip_prefix("part_")?.to_owned();
            (p.extension()? == "json").then_some((id, p))
        })
        .collect();
    out.sort_by_key(|(id, _)| natural_key(id));
    Ok(out)
}

fn natural_key(id: &str) -> (u64, String) {
    (id.parse().unwrap_or(u64::MAX), id.to_owned())
}

fn read_json(path: &Path, what: &'static str) -> EvalResult<Value> {
    let bytes = std::fs::read(path).map_err(|source| EvalError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    serde_json::from_slice(&bytes).map_err(|e| EvalError::Json {
        path: path.to_path_buf(),
        what,
        message: e.to_string(),
    })
}

fn number(v: &Value) -> Option<f64> {
    v.as_f64().filter(|x| x.is_finite())
}

fn vec3(v: &Value) -> Option<[f64; 3]> {
    let a = v.as_array()?;
    (a.len() == 3).then(|| Some([number(&a[0])?, number(&a[1])?, number(&a[2])?]))?
}

fn pair(v: &Value) -> Option<[f64; 2]> {
    let a = v.as_array()?;
    (a.len() == 2).then(|| Some([number(&a[0])?, number(&a[1])?]))?
}

/// Loads the UniPhys-40K entity at `dir` as ground truth.
pub fn load_dataset_ground_truth(dir: &Path) -> EvalResult<AnnotatedAsset> {
    let files = part_files(dir)?;
    if files.is_empty() {
        return Err(EvalError::UnrecognisedInput {
            path: dir.to_path_buf(),
            expected: "a UniPhys-40K entity (annotations/part_<id>.json files)",
        });
    }
    let mut records = Vec::with_capacity(files.len());
    let mut name_of_id: BTreeMap<String, String> = BTreeMap::new();
    for (id, path) in &files {
        let json = read_json(path, "UniPhys-40K part record")?;
        let name = json["part_level"]["part_name"]
            .as_str()
            .map(str::trim)
            .filter(|s| !s.is_empty())
            .map_or_else(|| format!("part_{id}"), str::to_owned);
        name_of_id.insert(id.clone(), name.clone());
        if let Some(label) = json["index"]
            .get("label")
            .and_then(|l| normalise_id(l).ok())
        {
            name_of_id.entry(label).or_insert_with(|| name.clone());
        }
        records.push((name, json));
    }
    let mut parts = Vec::new();
    let mut joints = Vec::new();
    for (name, json) in &records {
        parts.push(AnnotatedPart {
            name: name.clone(),
            physics: Some(part_physics(json)),
        });
        if let Some(joint) = part_joint(name, &json["kinematic_info"], &name_of_id) {
            joints.push(joint);
        }
    }
    let object_path = dir.join("annotations").join("object.json");
    let object = if object_path.is_file() {
        Some(object_values(&read_json(
            &object_path,
            "UniPhys-40K object record",
        )?))
    } else {
        None
    };
    Ok(AnnotatedAsset {
        origin: dir.display().to_string(),
        bounds_in_object: obj_bounds(&dir.join("parts"))?,
        parts,
        joints,
        object,
    })
}

fn part_physics(json: &Value) -> PhysicalProperties {
    let basic = &json["basic_info"];
    let level = &json["part_level"];
    PhysicalProperties {
        material: basic["material"].as_str().map(str::to_owned),
        density: number(&basic["density"]),
        friction: number(&basic["friction"]),
        affordance: number(&level["affordance"]),
        young: number(&basic["young"]),
        hardness: number(&basic["hardness"]),
        poisson: number(&basic["poisson"]),
        graspable: level["graspable"].as_bool(),
    }
}

/// The first of `motion_types`, then `motion_info` keys, that is `B` or `C` with a mapping.
fn part_joint(
    name: &str,
    kinematic: &Value,
    name_of_id: &BTreeMap<String, String>,
) -> Option<AnnotatedJoint> {
    let info = kinematic.get("motion_info")?.as_object()?;
    let listed = kinematic["motion_types"]
        .as_array()
        .into_iter()
        .flatten()
        .filter_map(Value::as_str);
    let motion_type = listed
        .chain(info.keys().map(String::as_str))
        .find(|t| matches!(*t, "B" | "C") && info.get(*t).is_some_and(Value::is_object))?;
    let m = &info[motion_type];
    let members = info
        .get("dependency")
        .and_then(Value::as_array)
        .map(|ids| {
            ids.iter()
                .filter_map(|id| normalise_id(id).ok())
                .map(|id| name_of_id.get(&id).cloned().unwrap_or(id))
                .collect::<Vec<_>>()
        })
        .unwrap_or_else(|| vec![name.to_owned()]);
    Some(AnnotatedJoint {
        child: name.to_owned(),
        motion_type: motion_type.chars().next()?,
        axis: vec3(&m["axis"])?,
        pivot_in_object: vec3(&m["pos"]),
        range: pair(&m["range"]),
        members: sorted_members(members),
    })
}

/// Object values from `object.json`, flat or wrapped in `object_level`; dimensions from
/// `dimension` (or `volume`, the key the reference evaluator reads), in cm; mass from
/// `object_mass` (or `mass`), in kg.
fn object_values(json: &Value) -> ObjectValues {
    let o = json.get("object_level").unwrap_or(json);
    let dims = o
        .get("dimension")
        .or_else(|| o.get("volume"))
        .and_then(Value::as_array)
        .map(|a| {
            a.iter()
                .map(|v| number(v).map_or(f64::NAN, m_from_cm))
                .collect()
        });
    ObjectValues {
        dimensions: dims,
        mass: o
            .get("object_mass")
            .or_else(|| o.get("mass"))
            .and_then(number),
        category: o["category"].as_str().map(str::to_owned),
    }
}

/// Bounds of the vertices of every `*.obj` in `dir`; `None` if there is none.
fn obj_bounds(dir: &Path) -> EvalResult<Option<[[f64; 3]; 2]>> {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return Ok(None);
    };
    let mut bounds: Option<[[f64; 3]; 2]> = None;
    let mut paths: Vec<PathBuf> = entries
        .filter_map(Result::ok)
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|e| e.eq_ignore_ascii_case("obj")))
        .collect();
    paths.sort();
    for path in paths {
        let text = std::fs::read_to_string(&path).map_err(|source| EvalError::Io {
            path: path.clone(),
            source,
        })?;
        for line in text.lines() {
            let mut words = line.split_whitespace();
            if words.next() != Some("v") {
                continue;
            }
            let xyz: Vec<f64> = words.take(3).filter_map(|w| w.parse().ok()).collect();
            let Ok(p) = <[f64; 3]>::try_from(xyz) else {
                continue;
            };
            bounds = union_bounds(bounds, p, p);
        }
    }
    Ok(bounds)
}
