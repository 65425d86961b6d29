//! STL, ASCII and binary: one part, vertices welded by exact position so a closed surface stays
//! closed.

use std::collections::HashMap;
use std::io::Cursor;
use std::path::Path;

use uniphys_geometry::{DVec3, MeshAsset, MeshPart, TriMesh};

use crate::guard::guarded;
use crate::source::Session;
use crate::{IngestError, IngestResult};

const HEADER: usize = 80;
const RECORD: u64 = 50;

/// Reads an STL file's bytes into a one-part asset named after the file stem.
pub(crate) fn read_stl(
    path: &Path,
    mut bytes: Vec<u8>,
    session: &Session<'_>,
) -> IngestResult<MeshAsset> {
    let parse_err = |message: String| IngestError::parse(path, "stl", message);
    match binary_triangle_count(&bytes) {
        Some(count) if is_binary(&bytes, count) => {
            let needed = 84 + RECORD * u64::from(count);
            let available = bytes.len() as u64;
            if needed > available {
                return Err(parse_err(format!(
                    "the binary header declares {count} triangles ({needed} bytes) but the file has only {available} bytes; the file is truncated"
                )));
            }
            session.check_triangles(path, count as usize)?;
            bytes.truncate(usize::try_from(needed).unwrap_or(usize::MAX));
            // A binary header may start with "solid"; make sure stl_io does not take it for ASCII.
            bytes[0] = b'\n';
        }
        _ if bytes.starts_with(b"solid") && !bytes.contains(&0) => {
            if !bytes.starts_with(b"solid ") {
                bytes.insert(5, b' ');
            }
            // A Latin-1 solid name must not make the line reader fail.
            if std::str::from_utf8(&bytes).is_err() {
                bytes = String::from_utf8_lossy(&bytes).into_owned().into_bytes();
            }
        }
        _ => {
            return Err(parse_err(format!(
                "it is neither ASCII (no leading \"solid\") nor binary (only {} bytes, shorter than the 84-byte header)",
                bytes.len()
            )));
        }
    }
    let indexed = guarded(path, "stl", || stl_io::read_stl(&mut Cursor::new(&bytes)))?
        .map_err(|e| parse_err(e.to_string()))?;
    session.check_triangles(path, indexed.faces.len())?;

    // stl_io welds by bit pattern; also merge -0.0 with +0.0 so the mesh can close.
    let mut index_of: HashMap<[u64; 3], u32> = HashMap::new();
    let mut positions = Vec::new();
    let mut remap = Vec::with_capacity(indexed.vertices.len());
    for v in &indexed.vertices {
        let p = DVec3::new(f64::from(v[0]), f64::from(v[1]), f64::from(v[2]));
        let key = [
            (p.x + 0.0).to_bits(),
            (p.y + 0.0).to_bits(),
            (p.z + 0.0).to_bits(),
        ];
        let next =
            u32::try_from(positions.len()).map_err(|_| parse_err("too many vertices".into()))?;
        let idx = *index_of.entry(key).or_insert_with(|| {
            positions.push(p);
            next
        });
        remap.push(idx);
    }
    let triangles = indexed
        .faces
        .iter()
        .map(|f| {
            f.vertices
                .map(|v| remap.get(v).copied().unwrap_or(u32::MAX))
        })
        .collect();
    let name = crate::source::part_name_of_file(path);
    Ok(MeshAsset {
        parts: vec![MeshPart {
            name,
            mesh: TriMesh {
                positions,
                triangles,
                ..TriMesh::default()
            },
        }],
        ..MeshAsset::default()
    })
}

/// The triangle count of a binary header, if the file is long enough to have one.
fn binary_triangle_count(bytes: &[u8]) -> Option<u32> {
    let raw = bytes.get(HEADER..HEADER + 4)?;
    Some(u32::from_le_bytes([raw[0], raw[1], raw[2], raw[3]]))
}

/// Binary if the size matches the declared count exactly, or if it does not look like text (a
/// leading "solid" and no control characters besides whitespace in the first KiB; binary headers
/// often start with "solid" too, but their triangle data holds control bytes such as NUL).
fn is_binary(bytes: &[u8], count: u32) -> bool {
    let exact = 84 + RECORD * u64::from(count) == bytes.len() as u64;
    let text = |b: &u8| *b >= 0x20 || b.is_ascii_whitespace();
    let looks_ascii = bytes.starts_with(b"solid") && bytes.iter().take(1024).all(text);
    exact || !looks_ascii
}
