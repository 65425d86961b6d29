//! Stanford PLY, ASCII and binary: `vertex` x/y/z with optional red/green/blue(/alpha) colours,
//! `face` lists named `vertex_indices` or `vertex_index` (polygons fan-triangulated); one part.

use std::io::Cursor;
use std::path::Path;

use ply_rs_bw::parser::{Parser, Reader};
use ply_rs_bw::ply::{
    ElementDef, Encoding, PropertyAccess, PropertyAccessResult, PropertyType, ScalarType,
};
use uniphys_geometry::{DVec3, MeshAsset, MeshPart, TriMesh};

use crate::guard::guarded;
use crate::source::Session;
use crate::{IngestError, IngestResult};

/// One PLY record: a vertex or a face, whichever properties the element has.
#[derive(Debug, Clone)]
struct Record {
    xyz: [f64; 3],
    rgba: [f32; 4],
    indices: Vec<u32>,
}

impl Record {
    fn set_number(&mut self, name: &str, value: f64) -> PropertyAccessResult {
        let slot = match name {
            "x" => &mut self.xyz[0],
            "y" => &mut self.xyz[1],
            "z" => &mut self.xyz[2],
            _ => return PropertyAccessResult::Ignored,
        };
        *slot = value;
        PropertyAccessResult::Set
    }

    fn set_colour(&mut self, name: &str, linear: f32) -> Option<PropertyAccessResult> {
        let channel = ["red", "green", "blue", "alpha"]
            .iter()
            .position(|c| *c == name)?;
        self.rgba[channel] = linear;
        Some(PropertyAccessResult::Set)
    }

    fn set_indices(
        &mut self,
        name: &str,
        values: impl Iterator<Item = i64>,
    ) -> PropertyAccessResult {
        if !is_index_list(name) {
            return PropertyAccessResult::Ignored;
        }
        // Negative indices become u32::MAX, reported as out of range by the checks.
        self.indices = values
            .map(|v| u32::try_from(v).unwrap_or(u32::MAX))
            .collect();
        PropertyAccessResult::Set
    }
}

impl PropertyAccess for Record {
    fn new() -> Self {
        Self {
            xyz: [0.0; 3],
            rgba: [1.0; 4],
            indices: Vec::new(),
        }
    }
    fn set_uchar(&mut self, name: &str, value: u8) -> PropertyAccessResult {
        let channel = if name == "alpha" {
            f32::from(value) / 255.0
        } else {
            srgb_to_linear(f32::from(value) / 255.0)
        };
        self.set_colour(name, channel)
            .unwrap_or_else(|| self.set_number(name, f64::from(value)))
    }
    fn set_char(&mut self, name: &str, value: i8) -> PropertyAccessResult {
        self.set_number(name, f64::from(value))
    }
    fn set_short(&mut self, name: &str, value: i16) -> PropertyAccessResult {
        self.set_number(name, f64::from(value))
    }
    fn set_ushort(&mut self, name: &str, value: u16) -> PropertyAccessResult {
        self.set_number(name, f64::from(value))
    }
    fn set_int(&mut self, name: &str, value: i32) -> PropertyAccessResult {
        self.set_number(name, f64::from(value))
    }
    fn set_uint(&mut self, name: &str, value: u32) -> PropertyAccessResult {
        self.set_number(name, f64::from(value))
    }
    fn set_float(&mut self, name: &str, value: f32) -> PropertyAccessResult {
        // Float colours are taken as linear values in [0, 1].
        self.set_colour(name, value)
            .unwrap_or_else(|| self.set_number(name, f64::from(value)))
    }
    fn set_double(&mut self, name: &str, value: f64) -> PropertyAccessResult {
        #[expect(clippy::cast_possible_truncation, reason = "colour channel precision")]
        let channel = value as f32;
        self.set_colour(name, channel)
            .unwrap_or_else(|| self.set_number(name, value))
    }
    fn set_list_char(&mut self, name: &str, v: Vec<i8>) -> PropertyAccessResult {
        self.set_indices(name, v.into_iter().map(i64::from))
    }
    fn set_list_uchar(&mut self, name: &str, v: Vec<u8>) -> PropertyAccessResult {
        self.set_indices(name, v.into_iter().map(i64::from))
    }
    fn set_list_short(&mut self, name: &str, v: Vec<i16>) -> PropertyAccessResult {
        self.set_indices(name, v.into_iter().map(i64::from))
    }
    fn set_list_ushort(&mut self, name: &str, v: Vec<u16>) -> PropertyAccessResult {
        self.set_indices(name, v.into_iter().map(i64::from))
    }
    fn set_list_int(&mut self, name: &str, v: Vec<i32>) -> PropertyAccessResult {
        self.set_indices(name, v.into_iter().map(i64::from))
    }
    fn set_list_uint(&mut self, name: &str, v: Vec<u32>) -> PropertyAccessResult {
        self.set_indices(name, v.into_iter().map(i64::from))
    }
}

fn is_index_list(name: &str) -> bool {
    name == "vertex_indices" || name == "vertex_index"
}

/// Decodes an sRGB-encoded channel in [0, 1] to linear.
fn srgb_to_linear(c: f32) -> f32 {
    if c <= 0.040_45 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

/// Reads a PLY file's bytes into a one-part asset named after the file stem.
pub(crate) fn read_ply(
    path: &Path,
    bytes: &[u8],
    session: &Session<'_>,
) -> IngestResult<MeshAsset> {
    let parse_err = |message: String| IngestError::parse(path, "ply", message);
    let parser = Parser::<Record>::new();
    let mut reader = Reader::new(Cursor::new(bytes));
    let header = guarded(path, "ply", || parser.read_header(&mut reader))?
        .map_err(|e| parse_err(format!("bad header: {e}")))?;
    let vertex_def = header
        .elements
        .get("vertex")
        .ok_or_else(|| parse_err("the header declares no `vertex` element".into()))?;
    for axis in ["x", "y", "z"] {
        if !vertex_def.properties.contains_key(axis) {
            return Err(parse_err(format!(
                "the `vertex` element has no `{axis}` property"
            )));
        }
    }
    let has_colour = ["red", "green", "blue"]
        .iter()
        .all(|c| vertex_def.properties.contains_key(*c));
    let face_def = header.elements.get("face");
    if let Some(face) = face_def {
        if !face.properties.keys().any(|k| is_index_list(k)) {
            return Err(parse_err(
                "the `face` element has no `vertex_indices` or `vertex_index` list".into(),
            ));
        }
        session.check_triangles(path, face.count)?;
    }
    let vertex_limit = session.options.max_triangles.saturating_mul(3);
    if vertex_def.count > vertex_limit {
        return Err(IngestError::TooManyVertices {
            path: path.to_path_buf(),
            count: vertex_def.count,
            limit: vertex_limit,
        });
    }
    let remaining = bytes.len() as u64 - reader.get_ref().position().min(bytes.len() as u64);
    check_declared_sizes(&header.elements, header.encoding, remaining).map_err(parse_err)?;

    let payload = guarded(path, "ply", || parser.read_payload(&mut reader, &header))?
        .map_err(|e| parse_err(e.to_string()))?;
    let vertices = payload.get("vertex").map_or(&[][..], Vec::as_slice);
    let positions: Vec<DVec3> = vertices.iter().map(|r| DVec3::from_array(r.xyz)).collect();
    let mut triangles = Vec::new();
    for face in payload.get("face").map_or(&[][..], Vec::as_slice) {
        if let Some((&first, rest)) = face.indices.split_first() {
            triangles.extend(rest.windows(2).map(|w| [first, w[0], w[1]]));
        }
    }
    session.check_triangles(path, triangles.len())?;
    let name = crate::source::part_name_of_file(path);
    Ok(MeshAsset {
        parts: vec![MeshPart {
            name,
            mesh: TriMesh {
                vertex_colors: has_colour.then(|| vertices.iter().map(|r| r.rgba).collect()),
                positions,
                triangles,
                ..TriMesh::default()
            },
        }],
        ..MeshAsset::default()
    })
}

/// Checks that the declared element counts fit in the bytes after the header, so a corrupt
/// count cannot make the parser loop or allocate far beyond the file's size.
fn check_declared_sizes(
    elements: &ply_rs_bw::ply::KeyMap<ElementDef>,
    encoding: Encoding,
    remaining: u64,
) -> Result<(), String> {
    let mut needed: u64 = 0;
    for def in elements.values() {
        let per_record = match encoding {
            Encoding::Ascii => 1,
            Encoding::BinaryBigEndian | Encoding::BinaryLittleEndian => def
                .properties
                .values()
                .map(|p| min_binary_size(&p.data_type))
                .sum(),
        };
        let count = def.count as u64;
        if per_record == 0 && count > 0 {
            return Err(format!(
                "element `{}` declares {count} records without any property",
                def.name
            ));
        }
        needed = needed.saturating_add(count.saturating_mul(per_record));
    }
    if needed > remaining {
        return Err(format!(
            "the header declares records needing at least {needed} bytes, but only {remaining} bytes follow it; the file is truncated or the counts are wrong"
        ));
    }
    Ok(())
}

fn min_binary_size(ty: &PropertyType) -> u64 {
    match ty {
        PropertyType::Scalar(s) | PropertyType::List(s, _) => scalar_size(s),
    }
}

fn scalar_size(s: &ScalarType) -> u64 {
    match s {
        ScalarType::Char | ScalarType::UChar => 1,
        ScalarType::Short | ScalarType::UShort => 2,
        ScalarType::Int | ScalarType::UInt | ScalarType::Float => 4,
        ScalarType::Double => 8,
    }
}
