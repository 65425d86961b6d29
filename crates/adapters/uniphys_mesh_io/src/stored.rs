//! An ingested asset as the job queue stores it between stages ([`IngestedAsset`]): what
//! [`crate::load_asset`] read, written once by the `ingest` stage so later stages read it back
//! instead of parsing the submitted file again.
//!
//! Layout (little-endian): the magic `UPASSET\0`, the format version (u32), the length of a
//! JSON header (u64), the header (name, source, warnings, facts, joints, materials, texture
//! sizes, part sizes), then the arrays: each part's positions (f64 x 3), triangles (u32 x 3),
//! UVs (f32 x 2), vertex colours (f32 x 4) and face materials (u32) when it has them, then each
//! texture as a PNG (lossless, and far smaller than its decoded pixels). Coordinates and pixels
//! keep their exact values, so a stage reading it computes what it would have from the source.
//! Decoding checks every size against the bytes present before allocating, every mesh's indices
//! and every image's size, as the readers do.

use std::path::Path;

use image::ImageEncoder;
use image::codecs::png::{CompressionType, FilterType, PngEncoder};
use serde::{Deserialize, Serialize};
use uniphys_geometry::{DVec3, MeshAsset, MeshPart, SurfaceMaterial, Texture, TriMesh};
use uniphys_types::{Joint, SourceInfo};

use crate::texture::decode_texture;
use crate::{IngestError, IngestResult, InputFacts, InputUnits, LoadedAsset};

/// The first bytes of a stored asset.
const MAGIC: &[u8; 8] = b"UPASSET\0";

/// The layout version; [`IngestedAsset::from_bytes`] refuses any other.
pub const STORED_ASSET_VERSION: u32 = 1;

/// An asset read by the `ingest` stage: its name (from the submitted file's name) and what the
/// reader returned.
#[derive(Debug, Clone, PartialEq)]
pub struct IngestedAsset {
    /// The asset's name, as the pipeline names outputs.
    pub name: String,
    /// What the reader returned.
    pub loaded: LoadedAsset,
}

#[derive(Serialize, Deserialize)]
struct Header {
    name: String,
    source: SourceInfo,
    dropped_degenerate_triangles: usize,
    warnings: Vec<String>,
    units: InputUnits,
    declared_category: Option<String>,
    joints: Vec<Joint>,
    materials: Vec<SurfaceMaterial>,
    textures: Vec<TextureHeader>,
    parts: Vec<PartHeader>,
}

#[derive(Serialize, Deserialize)]
struct TextureHeader {
    name: String,
    width: u32,
    height: u32,
    png_bytes: usize,
}

#[derive(Serialize, Deserialize)]
struct PartHeader {
    name: String,
    vertices: usize,
    triangles: usize,
    uvs: bool,
    vertex_colors: bool,
    face_materials: bool,
}

impl IngestedAsset {
    /// The stored form; fails when a texture's pixels do not match its size or the header
    /// cannot be written.
    pub fn to_bytes(&self) -> IngestResult<Vec<u8>> {
        let asset = &self.loaded.asset;
        let pngs = asset
            .textures
            .iter()
            .map(png)
            .collect::<IngestResult<Vec<_>>>()?;
        let header = Header {
            name: self.name.clone(),
            source: self.loaded.source.clone(),
            dropped_degenerate_triangles: self.loaded.dropped_degenerate_triangles,
            warnings: self.loaded.warnings.clone(),
            units: self.loaded.facts.units,
            declared_category: self.loaded.facts.declared_category.clone(),
            joints: asset.joints.clone(),
            materials: asset.materials.clone(),
            textures: asset
                .textures
                .iter()
                .zip(&pngs)
                .map(|(t, png)| TextureHeader {
                    name: t.name.clone(),
                    width: t.width,
                    height: t.height,
                    png_bytes: png.len(),
                })
                .collect(),
            parts: asset
                .parts
                .iter()
                .map(|p| PartHeader {
                    name: p.name.clone(),
                    vertices: p.mesh.positions.len(),
                    triangles: p.mesh.triangles.len(),
                    uvs: p.mesh.uvs.is_some(),
                    vertex_colors: p.mesh.vertex_colors.is_some(),
                    face_materials: p.mesh.face_materials.is_some(),
                })
                .collect(),
        };
        let header = serde_json::to_vec(&header).map_err(|e| stored(format!("the header: {e}")))?;
        let pngs_len: usize = pngs.iter().map(Vec::len).sum();
        let mut out = Vec::with_capacity(20 + header.len() + meshes_len(asset) + pngs_len);
        out.extend_from_slice(MAGIC);
        out.extend_from_slice(&STORED_ASSET_VERSION.to_le_bytes());
        out.extend_from_slice(&(header.len() as u64).to_le_bytes());
        out.extend_from_slice(&header);
        for part in &asset.parts {
            let mesh = &part.mesh;
            for p in &mesh.positions {
                for c in p.to_array() {
                    out.extend_from_slice(&c.to_le_bytes());
                }
            }
            put_u32s(&mut out, mesh.triangles.iter().flatten());
            if let Some(uvs) = &mesh.uvs {
                put_f32s(&mut out, uvs.iter().flatten());
            }
            if let Some(colors) = &mesh.vertex_colors {
                put_f32s(&mut out, colors.iter().flatten());
            }
            if let Some(materials) = &mesh.face_materials {
                put_u32s(&mut out, materials.iter());
            }
        }
        for png in &pngs {
            out.extend_from_slice(png);
        }
        Ok(out)
    }

    /// Reads a stored asset back; bytes of another layout version, truncated or inconsistent
    /// are an [`IngestError::Stored`].
    pub fn from_bytes(bytes: &[u8]) -> IngestResult<Self> {
        let mut r = Reader { bytes, at: 0 };
        if r.take(MAGIC.len())? != MAGIC {
            return Err(stored("it does not start as a stored asset does"));
        }
        let version = u32::from_le_bytes(r.array()?);
        if version != STORED_ASSET_VERSION {
            return Err(stored(format!(
                "layout version {version}, this build reads {STORED_ASSET_VERSION}"
            )));
        }
        let header_len = usize::try_from(u64::from_le_bytes(r.array()?))
            .map_err(|_| stored("the header length does not fit in memory"))?;
        let header: Header = serde_json::from_slice(r.take(header_len)?)
            .map_err(|e| stored(format!("the header: {e}")))?;
        let mut parts = Vec::with_capacity(header.parts.len().min(r.remaining()));
        for part in header.parts {
            parts.push(MeshPart {
                mesh: r.mesh(&part).map_err(|e| match e {
                    IngestError::Stored { message } => {
                        stored(format!("part {:?}: {message}", part.name))
                    }
                    other => other,
                })?,
                name: part.name,
            });
        }
        let mut textures = Vec::with_capacity(header.textures.len().min(r.remaining()));
        for texture in header.textures {
            let png = r.take(texture.png_bytes)?;
            let decoded = decode_texture(Path::new("the stored asset"), &texture.name, png)
                .map_err(|e| stored(e.to_string()))?;
            if (decoded.width, decoded.height) != (texture.width, texture.height) {
                return Err(stored(format!(
                    "texture {:?} is {}x{} pixels, its header says {}x{}",
                    texture.name, decoded.width, decoded.height, texture.width, texture.height
                )));
            }
            textures.push(decoded);
        }
        if r.remaining() != 0 {
            return Err(stored(format!(
                "{} bytes follow the last array",
                r.remaining()
            )));
        }
        let materials = header.materials;
        if let Some(m) = materials
            .iter()
            .find(|m| m.base_color_texture.is_some_and(|t| t >= textures.len()))
        {
            return Err(stored(format!(
                "material {:?} names a texture that is not stored",
                m.name
            )));
        }
        Ok(Self {
            name: header.name,
            loaded: LoadedAsset {
                asset: MeshAsset {
                    parts,
                    materials,
                    textures,
                    joints: header.joints,
                },
                source: header.source,
                dropped_degenerate_triangles: header.dropped_degenerate_triangles,
                warnings: header.warnings,
                facts: InputFacts {
                    units: header.units,
                    declared_category: header.declared_category,
                },
            },
        })
    }
}

/// `texture` as a PNG.
fn png(texture: &Texture) -> IngestResult<Vec<u8>> {
    let mut out = Vec::new();
    PngEncoder::new_with_quality(&mut out, CompressionType::Fast, FilterType::Adaptive)
        .write_image(
            &texture.rgba8,
            texture.width,
            texture.height,
            image::ExtendedColorType::Rgba8,
        )
        .map_err(|e| stored(format!("texture {:?}: {e}", texture.name)))?;
    Ok(out)
}

/// Bytes of the mesh arrays after the header.
fn meshes_len(asset: &MeshAsset) -> usize {
    asset
        .parts
        .iter()
        .map(|p| {
            let m = &p.mesh;
            let n = m.positions.len();
            let t = m.triangles.len();
            n * 24
                + t * 12
                + m.uvs.as_ref().map_or(0, |_| n * 8)
                + m.vertex_colors.as_ref().map_or(0, |_| n * 16)
                + m.face_materials.as_ref().map_or(0, |_| t * 4)
        })
        .sum()
}

fn put_u32s<'a>(out: &mut Vec<u8>, values: impl Iterator<Item = &'a u32>) {
    for v in values {
        out.extend_from_slice(&v.to_le_bytes());
    }
}

fn put_f32s<'a>(out: &mut Vec<u8>, values: impl Iterator<Item = &'a f32>) {
    for v in values {
        out.extend_from_slice(&v.to_le_bytes());
    }
}

fn stored(message: impl Into<String>) -> IngestError {
    IngestError::Stored {
        message: message.into(),
    }
}

/// A cursor over the stored bytes that refuses to read past their end.
struct Reader<'a> {
    bytes: &'a [u8],
    at: usize,
}

impl<'a> Reader<'a> {
    fn remaining(&self) -> usize {
        self.bytes.len() - self.at
    }

    fn take(&mut self, len: usize) -> IngestResult<&'a [u8]> {
        if len > self.remaining() {
            return Err(stored(format!(
                "it ends early: {len} bytes wanted at offset {}, {} left",
                self.at,
                self.remaining()
            )));
        }
        let slice = &self.bytes[self.at..self.at + len];
        self.at += len;
        Ok(slice)
    }

    fn array<const N: usize>(&mut self) -> IngestResult<[u8; N]> {
        let mut a = [0; N];
        a.copy_from_slice(self.take(N)?);
        Ok(a)
    }

    /// `count` values of `width` bytes each, checked against what is left first.
    fn values(&mut self, count: usize, width: usize) -> IngestResult<&'a [u8]> {
        let len = count
            .checked_mul(width)
            .ok_or_else(|| stored("an array length overflows"))?;
        self.take(len)
    }

    fn mesh(&mut self, part: &PartHeader) -> IngestResult<TriMesh> {
        let positions = self
            .values(part.vertices, 24)?
            .chunks_exact(24)
            .map(|c| {
                DVec3::new(
                    f64::from_le_bytes(c[0..8].try_into().unwrap_or_default()),
                    f64::from_le_bytes(c[8..16].try_into().unwrap_or_default()),
                    f64::from_le_bytes(c[16..24].try_into().unwrap_or_default()),
                )
            })
            .collect();
        let triangles = self
            .values(part.triangles, 12)?
            .chunks_exact(12)
            .map(|c| {
                let u = |i: usize| u32::from_le_bytes(c[i..i + 4].try_into().unwrap_or_default());
                [u(0), u(4), u(8)]
            })
            .collect();
        let uvs = part
            .uvs
            .then(|| self.f32s::<2>(part.vertices))
            .transpose()?;
        let vertex_colors = part
            .vertex_colors
            .then(|| self.f32s::<4>(part.vertices))
            .transpose()?;
        let face_materials = part
            .face_materials
            .then(|| {
                self.values(part.triangles, 4).map(|b| {
                    b.chunks_exact(4)
                        .map(|c| u32::from_le_bytes(c.try_into().unwrap_or_default()))
                        .collect()
                })
            })
            .transpose()?;
        let mesh = TriMesh {
            positions,
            triangles,
            uvs,
            vertex_colors,
            face_materials,
        };
        mesh.validate().map_err(|e| stored(e.to_string()))?;
        Ok(mesh)
    }

    fn f32s<const N: usize>(&mut self, count: usize) -> IngestResult<Vec<[f32; N]>> {
        Ok(self
            .values(count, 4 * N)?
            .chunks_exact(4 * N)
            .map(|c| {
                std::array::from_fn(|i| {
                    f32::from_le_bytes(c[4 * i..4 * i + 4].try_into().unwrap_or_default())
                })
            })
            .collect())
    }
}

#[cfg(test)]
mod tests {
    use uniphys_types::{JointKind, JointLimits, PartId, Provenance, SourceFormat, UpAxis};

    use super::*;

    /// A tetrahedron scaled by `size` and moved by `offset`.
    fn tetrahedron(size: f64, offset: DVec3) -> TriMesh {
        let corners = [DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::Z];
        TriMesh::new(
            corners.iter().map(|c| *c * size + offset).collect(),
            vec![[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]],
        )
        .unwrap()
    }

    fn sample() -> IngestedAsset {
        let mut body = tetrahedron(1.0 / 3.0, DVec3::ZERO);
        body.uvs = Some(vec![[0.25, 0.75]; body.positions.len()]);
        body.face_materials = Some(vec![1; body.triangles.len()]);
        let mut lid = tetrahedron(0.1, DVec3::new(0.0, 0.0, 1.0 / 3.0));
        lid.vertex_colors = Some(vec![[0.1, 0.2, 0.3, 1.0]; lid.positions.len()]);
        IngestedAsset {
            name: "box_with_lid".to_owned(),
            loaded: LoadedAsset {
                asset: MeshAsset {
                    parts: vec![
                        MeshPart {
                            name: "body".to_owned(),
                            mesh: body,
                        },
                        MeshPart {
                            name: "lid".to_owned(),
                            mesh: lid,
                        },
                    ],
                    materials: vec![
                        SurfaceMaterial {
                            name: "plain".to_owned(),
                            base_color_rgba: [0.5, 0.5, 0.5, 1.0],
                            base_color_texture: None,
                        },
                        SurfaceMaterial {
                            name: "wood".to_owned(),
                            base_color_rgba: [1.0, 0.9, 0.8, 1.0],
                            base_color_texture: Some(0),
                        },
                    ],
                    textures: vec![Texture {
                        name: "wood.png".to_owned(),
                        width: 2,
                        height: 3,
                        rgba8: (0..24).collect(),
                    }],
                    joints: vec![Joint {
                        name: "lid_hinge".to_owned(),
                        kind: JointKind::Revolute,
                        parent: PartId(0),
                        child: PartId(1),
                        axis_in_object: [0.0, 1.0, 0.0],
                        pivot_in_object_m: [0.1, 0.0, 1.0 / 3.0],
                        limits: Some(JointLimits {
                            lower: 0.0,
                            upper: 1.9,
                        }),
                        damping: 0.01,
                        friction: 0.0,
                        coupled_parts: Vec::new(),
                        provenance: Provenance::Input {
                            detail: "URDF joint lid_hinge".to_owned(),
                        },
                    }],
                },
                source: SourceInfo {
                    file_name: "box.glb".to_owned(),
                    format: SourceFormat::Glb,
                    content_sha256: "ab".repeat(32),
                    metres_per_unit: 0.01,
                    up_axis: UpAxis::Y,
                },
                dropped_degenerate_triangles: 3,
                warnings: vec!["texture x.png is missing".to_owned()],
                facts: InputFacts {
                    units: InputUnits::Normalised,
                    declared_category: Some("Box".to_owned()),
                },
            },
        }
    }

    #[test]
    fn a_stored_asset_reads_back_bit_for_bit() {
        let asset = sample();
        let bytes = asset.to_bytes().unwrap();
        assert_eq!(IngestedAsset::from_bytes(&bytes).unwrap(), asset);
    }

    #[test]
    fn a_texture_is_stored_as_an_image_not_as_its_pixels() {
        let mut asset = sample();
        let gradient: Vec<u8> = (0..512 * 512)
            .flat_map(|i: u32| [(i % 512 / 2) as u8, (i / 512 / 2) as u8, 128, 255])
            .collect();
        asset.loaded.asset.textures[0] = Texture {
            name: "gradient.png".to_owned(),
            width: 512,
            height: 512,
            rgba8: gradient,
        };
        let bytes = asset.to_bytes().unwrap();
        assert!(bytes.len() < 512 * 512 * 4 / 10, "{} bytes", bytes.len());
        assert_eq!(IngestedAsset::from_bytes(&bytes).unwrap(), asset);
    }

    #[test]
    fn truncated_padded_or_foreign_bytes_are_refused_with_a_reason() {
        let bytes = sample().to_bytes().unwrap();
        let short = IngestedAsset::from_bytes(&bytes[..bytes.len() - 1]).unwrap_err();
        assert!(short.to_string().contains("ends early"), "{short}");
        let mut long = bytes.clone();
        long.push(0);
        let long = IngestedAsset::from_bytes(&long).unwrap_err();
        assert!(long.to_string().contains("follow the last array"), "{long}");
        let mut other = bytes.clone();
        other[8] = 9;
        let other = IngestedAsset::from_bytes(&other).unwrap_err();
        assert!(other.to_string().contains("layout version 9"), "{other}");
        let foreign = IngestedAsset::from_bytes(b"glTF....").unwrap_err();
        assert!(foreign.to_string().contains("does not start"), "{foreign}");
    }

    #[test]
    fn an_index_past_the_vertices_is_refused() {
        let mut asset = sample();
        asset.loaded.asset.parts[1].mesh.triangles[0][2] = 10_000;
        let err = IngestedAsset::from_bytes(&asset.to_bytes().unwrap()).unwrap_err();
        assert!(err.to_string().contains("part \"lid\""), "{err}");
    }
}
