//! The file an asset is read from, among an archive's files.
//!
//! The format that refers to the others comes first: a URDF names its meshes, a glTF its
//! buffers and images, an OBJ its MTL (which names the textures); then PLY and STL, which
//! stand alone. Among files of the first format present, the shallowest is the asset. Files in
//! hidden folders and macOS resource forks (`__MACOSX/`, `._name`) are not candidates.

use uniphys_types::SourceFormat;

use crate::{ArchiveError, ArchiveResult};

/// Ranks of the formats: lower refers to higher (a URDF to its OBJ meshes).
fn rank(format: SourceFormat) -> u8 {
    match format {
        SourceFormat::Urdf => 0,
        SourceFormat::Gltf | SourceFormat::Glb => 1,
        SourceFormat::Obj => 2,
        SourceFormat::Ply | SourceFormat::Stl => 3,
    }
}

/// The asset's main file among `files` (paths as `/`-separated components): see the module's
/// documentation. Returned `/`-joined.
///
/// # Errors
/// [`ArchiveError::NoAsset`] when no file has a format the pipeline reads, or when two files of
/// the first format lie at the same, shallowest depth (two assets in one archive).
pub fn main_file(files: &[Vec<String>]) -> ArchiveResult<String> {
    let candidates: Vec<(u8, usize, String)> = files
        .iter()
        .filter(|c| {
            !c.iter()
                .any(|part| part.starts_with('.') || part == "__MACOSX")
        })
        .filter_map(|c| {
            let name = c.last()?;
            let (_, extension) = name.rsplit_once('.')?;
            let format = SourceFormat::from_extension(extension)?;
            Some((rank(format), c.len(), c.join("/")))
        })
        .collect();
    let Some(best) = candidates.iter().map(|(r, d, _)| (*r, *d)).min() else {
        return Err(ArchiveError::NoAsset(format!(
            "the archive holds no file the pipeline reads ({}); put the asset's main file in it",
            SourceFormat::listed_extensions()
        )));
    };
    let tied: Vec<&String> = candidates
        .iter()
        .filter(|(r, d, _)| (*r, *d) == best)
        .map(|(_, _, p)| p)
        .collect();
    if tied.len() > 1 {
        let shown: Vec<&str> = tied.iter().take(5).map(|p| p.as_str()).collect();
        return Err(ArchiveError::NoAsset(format!(
            "the archive holds {} files that could each be the asset ({}{}); submit one asset per archive",
            tied.len(),
            shown.join(", "),
            if tied.len() > 5 { ", ..." } else { "" }
        )));
    }
    Ok(tied[0].clone())
}

#[cfg(test)]
mod tests {
    use super::main_file;

    fn paths(list: &[&str]) -> Vec<Vec<String>> {
        list.iter()
            .map(|p| p.split('/').map(str::to_owned).collect())
            .collect()
    }

    #[test]
    fn the_file_that_names_the_others_is_the_asset() {
        let partnet = paths(&[
            "45213/textured_objs/original-1.obj",
            "45213/textured_objs/original-1.mtl",
            "45213/mobility.urdf",
            "45213/meta.json",
        ]);
        assert_eq!(main_file(&partnet).expect("a URDF"), "45213/mobility.urdf");
        let gltf = paths(&["scene.gltf", "scene.bin", "textures/wood.png"]);
        assert_eq!(main_file(&gltf).expect("a glTF"), "scene.gltf");
        let obj = paths(&[
            "chair.obj",
            "chair.mtl",
            "__MACOSX/._chair.obj",
            ".hidden/x.urdf",
        ]);
        assert_eq!(main_file(&obj).expect("an OBJ"), "chair.obj");
        // The shallowest of the first format: a model with a variant in a sub-folder.
        let nested = paths(&["lod/low.glb", "model.glb"]);
        assert_eq!(main_file(&nested).expect("the top one"), "model.glb");
    }

    #[test]
    fn no_asset_or_two_assets_are_refused_with_their_names() {
        let none = main_file(&paths(&["readme.txt", "a.png"])).expect_err("nothing readable");
        assert!(none.to_string().contains(".urdf"), "{none}");
        let two = main_file(&paths(&["a.urdf", "b.urdf", "m.obj"])).expect_err("two URDFs");
        let message = two.to_string();
        assert!(
            message.contains("a.urdf") && message.contains("b.urdf"),
            "{message}"
        );
    }
}
