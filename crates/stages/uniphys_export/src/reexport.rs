//! An earlier export read back from its own files, so it can be exported again without running
//! the pipeline (`uniphys export`): the record (`record.json`), the part meshes with their
//! materials and textures (`parts/`, object frame), the collision hulls (`meshes/`, moved back
//! from their link frames into the object frame), the checks, metrics and notes of `report.json`
//! (without its own export section, which the new export writes again) and the pairs of parts it
//! excluded for touching at rest.
//!
//! Coordinates come back as written: ten significant digits, so a second export matches the first
//! to that precision.

use std::collections::BTreeMap;

use serde_json::Value;
use uniphys_geometry::{DVec3, SurfaceMaterial, Texture, TriMesh, display_rgba};
use uniphys_types::{AssetRecord, PartId, VerificationReport};

use crate::checks::EXPORT_SECTION;
use crate::model::{TOUCH_AT_REST, link_anchor};
use crate::part_files::material_of_name;
use crate::visuals::{texture_file, texture_of_file};
use crate::{ExportError, ExportInput, ExportResult, MESH_DIR};

/// Everything [`crate::export`] needs, read back from an export's files.
#[derive(Debug, Clone)]
pub struct Exported {
    /// The annotated asset.
    pub record: AssetRecord,
    /// Part meshes (object frame), in the order of `record.parts`.
    pub part_meshes: Vec<TriMesh>,
    /// Convex hulls of each part (object frame).
    pub colliders: Vec<Vec<TriMesh>>,
    /// Display colour of each part ([`display_rgba`] of its mesh).
    pub part_colors: Vec<[f32; 4]>,
    /// Materials, indexed as the part meshes' face materials (unused indices are placeholders).
    pub materials: Vec<SurfaceMaterial>,
    /// Textures, indexed as the materials refer to them (unused indices are empty).
    pub textures: Vec<Texture>,
    /// Pairs of parts the earlier export excluded for touching at rest.
    pub touching_pairs: Vec<(PartId, PartId)>,
    /// The checks and metrics of earlier stages.
    pub report: VerificationReport,
    /// Notes of earlier stages.
    pub notes: Vec<String>,
}

impl Exported {
    /// Reads an export through `file`, which gives the bytes of a path relative to the export's
    /// folder (`None` when there is no such file).
    pub fn read(file: &dyn Fn(&str) -> Option<Vec<u8>>) -> ExportResult<Self> {
        let need = |path: &str| {
            file(path)
                .ok_or_else(|| unreadable(path, "missing: is this a folder `uniphys run` wrote?"))
        };
        let record: AssetRecord = serde_json::from_slice(&need("record.json")?)
            .map_err(|e| unreadable("record.json", &e.to_string()))?;
        record.validate()?;
        let mut materials: BTreeMap<usize, SurfaceMaterial> = BTreeMap::new();
        let mut textures: BTreeMap<usize, Texture> = BTreeMap::new();
        let mut part_meshes = Vec::with_capacity(record.parts.len());
        let mut colliders = Vec::with_capacity(record.parts.len());
        for (i, part) in record.parts.iter().enumerate() {
            let obj_path = format!("parts/{}.obj", part.id);
            let mtl_path = format!("parts/{}.mtl", part.id);
            let mtl = parse_mtl(&mtl_path, &text(&mtl_path, &need(&mtl_path)?)?)?;
            for (&index, material) in &mtl.materials {
                if let Some(t) = material.base_color_texture
                    && !textures.contains_key(&t)
                {
                    let path = format!("parts/{}", texture_file(t));
                    textures.insert(t, decode_png(&path, &need(&path)?)?);
                }
                materials
                    .entry(index as usize)
                    .or_insert_with(|| material.clone());
            }
            part_meshes.push(parse_obj(
                &obj_path,
                &text(&obj_path, &need(&obj_path)?)?,
                Some(&mtl),
            )?);
            let anchor = link_anchor(&record, i);
            let mut hulls = Vec::new();
            for k in 0.. {
                let path = format!("{MESH_DIR}/{}_collision_{k}.obj", part.id);
                let Some(bytes) = file(&path) else { break };
                let mut hull = parse_obj(&path, &text(&path, &bytes)?, None)?;
                for p in &mut hull.positions {
                    *p += anchor;
                }
                hulls.push(hull);
            }
            colliders.push(hulls);
        }
        let materials = dense(materials, |i| SurfaceMaterial {
            name: format!("unused_{i}"),
            base_color_rgba: [0.6, 0.6, 0.6, 1.0],
            base_color_texture: None,
        });
        let textures = dense(textures, |_| Texture {
            name: String::new(),
            width: 0,
            height: 0,
            rgba8: Vec::new(),
        });
        let part_colors = part_meshes
            .iter()
            .map(|m| display_rgba(m, &materials, &textures))
            .collect();
        let report_json: Value = serde_json::from_slice(&need("report.json")?)
            .map_err(|e| unreadable("report.json", &e.to_string()))?;
        let ReportRead {
            report,
            notes,
            touching_pairs,
        } = read_report(&report_json, &record)?;
        Ok(Self {
            record,
            part_meshes,
            colliders,
            part_colors,
            materials,
            textures,
            touching_pairs,
            report,
            notes,
        })
    }

    /// The export input over what was read.
    #[must_use]
    pub fn input(&self) -> ExportInput<'_> {
        ExportInput {
            record: &self.record,
            part_meshes: &self.part_meshes,
            colliders: &self.colliders,
            part_colors: &self.part_colors,
            materials: &self.materials,
            textures: &self.textures,
            touching_pairs: &self.touching_pairs,
            report: &self.report,
            notes: &self.notes,
        }
    }
}

fn unreadable(path: &str, message: &str) -> ExportError {
    ExportError::Unreadable {
        path: path.to_owned(),
        message: message.to_owned(),
    }
}

fn text(path: &str, bytes: &[u8]) -> ExportResult<String> {
    String::from_utf8(bytes.to_vec()).map_err(|_| unreadable(path, "not UTF-8 text"))
}

/// A map by index made a list, gaps filled by `placeholder`.
fn dense<T>(mut map: BTreeMap<usize, T>, placeholder: impl Fn(usize) -> T) -> Vec<T> {
    let len = map.keys().last().map_or(0, |&k| k + 1);
    (0..len)
        .map(|i| map.remove(&i).unwrap_or_else(|| placeholder(i)))
        .collect()
}

/// The materials of a part's MTL, by their index in the asset (the `m<i>_` of their names), and
/// each material name's index (`None` for the part's own colour, which is no asset material).
struct Mtl {
    materials: BTreeMap<u32, SurfaceMaterial>,
    by_name: BTreeMap<String, Option<u32>>,
}

fn parse_mtl(path: &str, text: &str) -> ExportResult<Mtl> {
    let mut materials = BTreeMap::new();
    let mut by_name = BTreeMap::new();
    let mut current: Option<(String, Option<u32>)> = None;
    for (n, line) in text.lines().enumerate() {
        let bad = |what: &str| unreadable(path, &format!("line {}: {what}", n + 1));
        let mut words = line.split_whitespace();
        match words.next() {
            Some("newmtl") => {
                let name = words
                    .next()
                    .ok_or_else(|| bad("newmtl without a name"))?
                    .to_owned();
                let parsed = material_of_name(&name);
                let index = parsed.as_ref().map(|(i, _)| *i);
                if let Some((i, clean)) = parsed {
                    materials.insert(
                        i,
                        SurfaceMaterial {
                            name: clean,
                            base_color_rgba: [1.0; 4],
                            base_color_texture: None,
                        },
                    );
                }
                by_name.insert(name.clone(), index);
                current = Some((name, index));
            }
            Some(key @ ("Kd" | "d" | "map_Kd")) => {
                let Some((_, Some(i))) = &current else {
                    continue;
                };
                let material = materials.get_mut(i).ok_or_else(|| bad("no material"))?;
                let values: Vec<&str> = words.collect();
                match key {
                    "Kd" => {
                        for (c, v) in values.iter().take(3).enumerate() {
                            material.base_color_rgba[c] = v
                                .parse()
                                .map_err(|_| bad("a colour that is not a number"))?;
                        }
                    }
                    "d" => {
                        material.base_color_rgba[3] =
                            values
                                .first()
                                .and_then(|v| v.parse().ok())
                                .ok_or_else(|| bad("an opacity that is not a number"))?;
                    }
                    _ => {
                        let file = values.first().ok_or_else(|| bad("map_Kd without a file"))?;
                        let t = texture_of_file(file)
                            .ok_or_else(|| bad("a texture not named texture_<t>.png"))?;
                        material.base_color_texture = Some(t);
                    }
                }
            }
            _ => {}
        }
    }
    Ok(Mtl { materials, by_name })
}

/// An OBJ as the export writes it: `v`, optional `vt` (one per vertex, OBJ's v up the image),
/// `usemtl` runs naming the MTL's materials, and triangles `f a b c` or `f a/a b/b c/c`.
fn parse_obj(path: &str, text: &str, mtl: Option<&Mtl>) -> ExportResult<TriMesh> {
    let mut positions = Vec::new();
    let mut uvs: Vec<[f32; 2]> = Vec::new();
    let mut triangles = Vec::new();
    let mut face_materials = Vec::new();
    let mut current: Option<u32> = None;
    for (n, line) in text.lines().enumerate() {
        let bad = |what: &str| unreadable(path, &format!("line {}: {what}", n + 1));
        let mut words = line.split_whitespace();
        match words.next() {
            Some("v") => {
                let xyz: Vec<f64> = words
                    .map(str::parse)
                    .collect::<Result<_, _>>()
                    .map_err(|_| bad("a vertex that is not three numbers"))?;
                let [x, y, z] = xyz[..] else {
                    return Err(bad("a vertex that is not three numbers"));
                };
                positions.push(DVec3::new(x, y, z));
            }
            Some("vt") => {
                let uv: Vec<f32> = words
                    .map(str::parse)
                    .collect::<Result<_, _>>()
                    .map_err(|_| bad("a texture coordinate that is not two numbers"))?;
                let [u, v] = uv[..] else {
                    return Err(bad("a texture coordinate that is not two numbers"));
                };
                // OBJ's v runs up the image, glTF's down.
                uvs.push([u, 1.0 - v]);
            }
            Some("usemtl") => {
                let name = words.next().ok_or_else(|| bad("usemtl without a name"))?;
                current = mtl.and_then(|m| m.by_name.get(name).copied().flatten());
            }
            Some("f") => {
                let corners: Vec<u32> = words
                    .map(|w| w.split('/').next().and_then(|i| i.parse::<u32>().ok()))
                    .collect::<Option<_>>()
                    .ok_or_else(|| bad("a face that is not three vertex numbers"))?;
                let [a, b, c] = corners[..] else {
                    return Err(bad("a face that is not a triangle"));
                };
                if [a, b, c]
                    .iter()
                    .any(|&i| i == 0 || i as usize > positions.len())
                {
                    return Err(bad("a face that refers to a vertex not yet given"));
                }
                triangles.push([a - 1, b - 1, c - 1]);
                face_materials.push(current);
            }
            _ => {}
        }
    }
    let mut mesh =
        TriMesh::new(positions, triangles).map_err(|e| unreadable(path, &e.to_string()))?;
    if !uvs.is_empty() {
        if uvs.len() != mesh.positions.len() {
            return Err(unreadable(
                path,
                "texture coordinates do not match the vertices one to one",
            ));
        }
        mesh.uvs = Some(uvs);
    }
    if face_materials.iter().all(Option::is_some) && !face_materials.is_empty() {
        mesh.face_materials = Some(face_materials.into_iter().flatten().collect());
    }
    Ok(mesh)
}

fn decode_png(path: &str, bytes: &[u8]) -> ExportResult<Texture> {
    let image = image::load_from_memory_with_format(bytes, image::ImageFormat::Png)
        .map_err(|e| unreadable(path, &e.to_string()))?
        .to_rgba8();
    Ok(Texture {
        name: path.rsplit('/').next().unwrap_or(path).to_owned(),
        width: image.width(),
        height: image.height(),
        rgba8: image.into_raw(),
    })
}

/// What the export needs of `report.json`.
struct ReportRead {
    report: VerificationReport,
    notes: Vec<String>,
    touching_pairs: Vec<(PartId, PartId)>,
}

/// The checks, metrics and notes of `report.json` (less the export's own section) and the pairs it
/// excluded for touching at rest, named by link (`part_<id>_...`).
fn read_report(value: &Value, record: &AssetRecord) -> ExportResult<ReportRead> {
    let bad = |message: &str| unreadable("report.json", message);
    // A field of the report, read as `T`; an absent one is empty.
    fn field<T: serde::de::DeserializeOwned + Default>(
        value: &Value,
        key: &str,
    ) -> ExportResult<T> {
        match value.get(key) {
            None => Ok(T::default()),
            Some(v) => serde_json::from_value(v.clone())
                .map_err(|e| unreadable("report.json", &format!("{key}: {e}"))),
        }
    }
    let mut report = VerificationReport {
        sections: field(value, "sections")?,
        metrics: field(value, "metrics")?,
    };
    report.sections.retain(|s| s.name != EXPORT_SECTION);
    let notes: Vec<String> = field(value, "notes")?;
    let part_of_link = |link: &str| {
        record
            .parts
            .iter()
            .find(|p| {
                link.strip_prefix(&p.id.to_string())
                    .is_some_and(|rest| rest.starts_with('_'))
            })
            .map(|p| p.id)
    };
    let mut touching = Vec::new();
    for exclude in value
        .get("contact_excludes")
        .and_then(Value::as_array)
        .into_iter()
        .flatten()
    {
        if exclude.get("why").and_then(Value::as_str) != Some(TOUCH_AT_REST) {
            continue;
        }
        let links: Vec<&str> = exclude
            .get("links")
            .and_then(Value::as_array)
            .map(|l| l.iter().filter_map(Value::as_str).collect())
            .unwrap_or_default();
        let [a, b] = links[..] else {
            return Err(bad("a contact exclude that does not name two links"));
        };
        match (part_of_link(a), part_of_link(b)) {
            (Some(a), Some(b)) => touching.push((a, b)),
            _ => {
                return Err(bad(&format!(
                    "a contact exclude of links {a} and {b}, which are not parts of the record"
                )));
            }
        }
    }
    Ok(ReportRead {
        report,
        notes,
        touching_pairs: touching,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_face_before_its_vertices_is_refused_naming_the_file_and_line() {
        let text = "v 0 0 0\nv 1 0 0\nf 1 2 3\nv 0 1 0\n";
        let error = parse_obj("parts/part_0.obj", text, None).expect_err("vertex 3 comes later");
        let message = error.to_string();
        assert!(
            message.contains("parts/part_0.obj") && message.contains("line 3"),
            "{message}"
        );
    }

    #[test]
    fn part_files_read_back_give_the_mesh_its_materials_and_texture_coordinates() {
        let mut mesh = TriMesh::new(
            vec![
                DVec3::new(0.0, 0.0, 0.0),
                DVec3::new(0.25, 0.0, 0.0),
                DVec3::new(0.0, 0.5, 0.125),
            ],
            vec![[0, 1, 2]],
        )
        .expect("mesh");
        mesh.uvs = Some(vec![[0.0, 0.25], [0.5, 0.75], [1.0, 0.0]]);
        mesh.face_materials = Some(vec![2]);
        let materials = vec![
            SurfaceMaterial {
                name: "unused".into(),
                base_color_rgba: [1.0; 4],
                base_color_texture: None,
            };
            3
        ]
        .into_iter()
        .enumerate()
        .map(|(i, mut m)| {
            if i == 2 {
                m.name = "oak".into();
                m.base_color_rgba = [0.5, 0.25, 0.125, 1.0];
                m.base_color_texture = Some(4);
            }
            m
        })
        .collect::<Vec<_>>();
        let files = crate::part_files::part_files(PartId(0), &mesh, &materials, [0.6; 4]);
        let mtl =
            parse_mtl("mtl", std::str::from_utf8(&files[1].bytes).expect("utf8")).expect("mtl");
        assert_eq!(mtl.materials.get(&2), Some(&materials[2]));
        let read = parse_obj(
            "obj",
            std::str::from_utf8(&files[0].bytes).expect("utf8"),
            Some(&mtl),
        )
        .expect("obj");
        assert_eq!(read.positions, mesh.positions);
        assert_eq!(read.triangles, mesh.triangles);
        assert_eq!(read.uvs, mesh.uvs);
        assert_eq!(read.face_materials, mesh.face_materials);
    }
}
