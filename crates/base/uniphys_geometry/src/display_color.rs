//! A display colour per part from its materials and textures (the colour simulators draw a link
//! in where no texture reaches).

use crate::{SurfaceMaterial, Texture, TriMesh};

/// The display colour of a part: the linear RGBA colour of the material covering most of its
/// triangles, multiplied by the mean colour of that material's base-colour texture if it has
/// one; mid grey without materials.
#[must_use]
pub fn display_rgba(
    mesh: &TriMesh,
    materials: &[SurfaceMaterial],
    textures: &[Texture],
) -> [f32; 4] {
    let Some(index) = majority_material(mesh) else {
        return [0.6, 0.6, 0.6, 1.0];
    };
    let Some(material) = materials.get(index as usize) else {
        return [0.6, 0.6, 0.6, 1.0];
    };
    let mut rgba = material.base_color_rgba;
    if let Some(texture) = material.base_color_texture.and_then(|t| textures.get(t)) {
        let pixels = texture.rgba8.chunks_exact(4);
        let n = pixels.len().max(1) as f32;
        let mut sum = [0.0f32; 3];
        for p in pixels {
            for c in 0..3 {
                sum[c] += srgb_to_linear(p[c]);
            }
        }
        for c in 0..3 {
            rgba[c] *= sum[c] / n;
        }
    }
    rgba.map(|c| c.clamp(0.0, 1.0))
}

/// Material indices of the part, most triangles first (ties: lower index first).
#[must_use]
pub fn materials_by_coverage(mesh: &TriMesh) -> Vec<u32> {
    let Some(materials) = &mesh.face_materials else {
        return Vec::new();
    };
    let mut counts: Vec<(u32, usize)> = Vec::new();
    for &m in materials {
        match counts.iter_mut().find(|(k, _)| *k == m) {
            Some((_, n)) => *n += 1,
            None => counts.push((m, 1)),
        }
    }
    counts.sort_by(|a, b| b.1.cmp(&a.1).then(a.0.cmp(&b.0)));
    counts.into_iter().map(|(m, _)| m).collect()
}

fn majority_material(mesh: &TriMesh) -> Option<u32> {
    materials_by_coverage(mesh).first().copied()
}

fn srgb_to_linear(c: u8) -> f32 {
    let c = f32::from(c) / 255.0;
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}
