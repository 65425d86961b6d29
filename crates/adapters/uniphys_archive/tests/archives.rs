//! Archives as an asset pipeline sends them, and as an attacker would.

use std::io::Write;
use std::path::{Path, PathBuf};

use uniphys_archive::{ArchiveError, ArchiveKind, ArchiveLimits, inspect, pack_folder, unpack};

fn write(path: &Path, bytes: &[u8]) {
    std::fs::create_dir_all(path.parent().expect("a parent")).expect("mkdir");
    std::fs::write(path, bytes).expect("write");
}

/// A small URDF folder laid out as PartNet-Mobility's.
fn urdf_folder(root: &Path) -> PathBuf {
    let folder = root.join("45213");
    write(
        &folder.join("mobility.urdf"),
        b"<robot name=\"r\"><link name=\"base\"/></robot>",
    );
    write(&folder.join("meta.json"), b"{\"model_cat\": \"Oven\"}");
    for i in 0..3 {
        write(
            &folder.join(format!("textured_objs/original-{i}.obj")),
            format!("mtllib original-{i}.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 {i}\nf 1 2 3\n").as_bytes(),
        );
        write(
            &folder.join(format!("textured_objs/original-{i}.mtl")),
            b"newmtl m\nKd 1 1 1\n",
        );
    }
    write(&folder.join(".DS_Store"), b"finder");
    folder
}

/// A tar entry written with a raw name (the tar crate's own setters refuse unsafe ones).
fn raw_tar(entries: &[(&str, tar::EntryType, &[u8], Option<&str>)]) -> Vec<u8> {
    let mut builder = tar::Builder::new(Vec::new());
    for (name, kind, data, link) in entries {
        let mut header = tar::Header::new_old();
        let raw = &mut header.as_old_mut().name;
        raw[..name.len()].copy_from_slice(name.as_bytes());
        header.set_entry_type(*kind);
        header.set_size(data.len() as u64);
        header.set_mode(0o644);
        if let Some(link) = link {
            header.as_old_mut().linkname[..link.len()].copy_from_slice(link.as_bytes());
        }
        header.set_cksum();
        builder.append(&header, *data).expect("append");
    }
    builder.into_inner().expect("tar")
}

fn zip_of(entries: &[(&str, &[u8])], method: zip::CompressionMethod) -> Vec<u8> {
    let mut writer = zip::ZipWriter::new(std::io::Cursor::new(Vec::new()));
    let options = zip::write::SimpleFileOptions::default().compression_method(method);
    for (name, data) in entries {
        writer.start_file(*name, options).expect("start");
        writer.write_all(data).expect("data");
    }
    writer.finish().expect("zip").into_inner()
}

fn saved(dir: &Path, name: &str, bytes: &[u8]) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, bytes).expect("write");
    path
}

fn refused(path: &Path, kind: ArchiveKind, limits: &ArchiveLimits) -> ArchiveError {
    let error = inspect(path, kind, limits).expect_err("refused");
    assert!(error.is_refusal(), "{error}");
    // Unpacking refuses it too and writes nothing beside the folder it was given.
    let out = tempfile::tempdir().expect("tempdir");
    let folder = out.path().join("asset");
    unpack(path, kind, &folder, limits).expect_err("refused when unpacking too");
    let beside: Vec<_> = std::fs::read_dir(out.path())
        .expect("list")
        .map(|e| e.expect("entry").file_name())
        .collect();
    assert_eq!(beside, ["asset"], "nothing outside the asset's folder");
    error
}

#[test]
fn a_packed_urdf_folder_unpacks_whole_with_its_urdf_as_the_asset() {
    let dir = tempfile::tempdir().expect("tempdir");
    let folder = urdf_folder(dir.path());
    let archive = dir.path().join("45213.tar.gz");
    let packed = pack_folder(&folder, &archive).expect("pack");
    assert_eq!(
        packed.files, 8,
        "the URDF, meta.json and three OBJ+MTL; not .DS_Store"
    );
    assert_eq!(packed.main_file, "mobility.urdf");
    let listing = inspect(&archive, ArchiveKind::TarGz, &ArchiveLimits::default()).expect("ok");
    assert_eq!(listing.main_file, "mobility.urdf");
    assert_eq!(listing.files, 8);
    assert_eq!(listing.unpacked_bytes, packed.bytes);
    let out = dir.path().join("out");
    let (main, _) = unpack(
        &archive,
        ArchiveKind::TarGz,
        &out,
        &ArchiveLimits::default(),
    )
    .expect("unpack");
    assert_eq!(main, out.join("mobility.urdf"));
    for i in 0..3 {
        let name = format!("textured_objs/original-{i}.obj");
        assert_eq!(
            std::fs::read(out.join(&name)).expect("unpacked"),
            std::fs::read(folder.join(&name)).expect("source"),
        );
    }
    // The same folder packs to the same bytes: a re-submission is the same asset.
    let again = dir.path().join("again.tar.gz");
    pack_folder(&folder, &again).expect("pack again");
    assert_eq!(
        std::fs::read(&archive).expect("a"),
        std::fs::read(&again).expect("b")
    );
}

#[test]
fn an_obj_with_its_mtl_and_texture_in_a_zip_is_read_from_the_obj() {
    let dir = tempfile::tempdir().expect("tempdir");
    let zip = zip_of(
        &[
            ("chair/chair.obj", b"mtllib chair.mtl\nv 0 0 0\n".as_slice()),
            ("chair/chair.mtl", b"newmtl wood\nmap_Kd tex/wood.png\n"),
            ("chair/tex/wood.png", &[0x89, b'P', b'N', b'G']),
            ("__MACOSX/chair/._chair.obj", b"resource fork"),
        ],
        zip::CompressionMethod::Deflated,
    );
    let path = saved(dir.path(), "chair.zip", &zip);
    let out = dir.path().join("out");
    let (main, listing) =
        unpack(&path, ArchiveKind::Zip, &out, &ArchiveLimits::default()).expect("unpack");
    assert_eq!(listing.main_file, "chair/chair.obj");
    assert_eq!(main, out.join("chair").join("chair.obj"));
    assert!(out.join("chair/tex/wood.png").is_file());
}

#[test]
fn a_gltf_with_external_buffers_in_a_tar_is_read_from_the_gltf() {
    let dir = tempfile::tempdir().expect("tempdir");
    let tar = raw_tar(&[
        (
            "scene.gltf",
            tar::EntryType::Regular,
            b"{\"buffers\":[{\"uri\":\"scene.bin\"}]}",
            None,
        ),
        ("scene.bin", tar::EntryType::Regular, &[0u8; 64], None),
        ("textures/", tar::EntryType::Directory, b"", None),
        ("textures/wood.png", tar::EntryType::Regular, b"png", None),
    ]);
    let path = saved(dir.path(), "scene.tar", &tar);
    let listing = inspect(&path, ArchiveKind::Tar, &ArchiveLimits::default()).expect("ok");
    assert_eq!(
        (listing.main_file.as_str(), listing.files),
        ("scene.gltf", 3)
    );
}

#[test]
fn paths_out_of_the_folder_are_refused() {
    let dir = tempfile::tempdir().expect("tempdir");
    for (name, why) in [
        ("../evil.obj", ".."),
        ("a/../../evil.obj", ".."),
        ("/etc/evil.obj", "absolute"),
        ("C:/evil.obj", "drive"),
    ] {
        let tar = raw_tar(&[
            ("ok.obj", tar::EntryType::Regular, b"v 0 0 0\n", None),
            (name, tar::EntryType::Regular, b"v 0 0 0\n", None),
        ]);
        let path = saved(dir.path(), "evil.tar", &tar);
        let error = refused(&path, ArchiveKind::Tar, &ArchiveLimits::default());
        assert!(
            matches!(&error, ArchiveError::UnsafeEntry { reason, .. } if reason.contains(why)),
            "{name}: {error}"
        );
        let zip = zip_of(&[(name, b"v 0 0 0\n")], zip::CompressionMethod::Stored);
        let path = saved(dir.path(), "evil.zip", &zip);
        let error = refused(&path, ArchiveKind::Zip, &ArchiveLimits::default());
        assert!(
            matches!(error, ArchiveError::UnsafeEntry { .. }),
            "{name}: {error}"
        );
    }
    assert!(!dir.path().join("evil.obj").exists());
}

#[test]
fn links_and_special_entries_are_refused() {
    let dir = tempfile::tempdir().expect("tempdir");
    for (kind, link) in [
        (tar::EntryType::Symlink, Some("/etc/passwd")),
        (tar::EntryType::Link, Some("model.obj")),
        (tar::EntryType::Char, None),
        (tar::EntryType::Fifo, None),
    ] {
        let tar = raw_tar(&[
            ("model.obj", tar::EntryType::Regular, b"v 0 0 0\n", None),
            ("textures", kind, b"", link),
        ]);
        let path = saved(dir.path(), "links.tar", &tar);
        let error = refused(&path, ArchiveKind::Tar, &ArchiveLimits::default());
        assert!(
            matches!(error, ArchiveError::UnsafeEntry { .. }),
            "{kind:?}: {error}"
        );
    }
    let mut writer = zip::ZipWriter::new(std::io::Cursor::new(Vec::new()));
    let options = zip::write::SimpleFileOptions::default();
    writer.start_file("model.obj", options).expect("file");
    writer.write_all(b"v 0 0 0\n").expect("data");
    writer
        .add_symlink("wood.png", "/etc/shadow", options)
        .expect("link");
    let zip = writer.finish().expect("zip").into_inner();
    let path = saved(dir.path(), "links.zip", &zip);
    let error = refused(&path, ArchiveKind::Zip, &ArchiveLimits::default());
    assert!(error.to_string().contains("a link"), "{error}");
}

#[test]
fn a_decompression_bomb_is_refused_before_it_is_written() {
    let dir = tempfile::tempdir().expect("tempdir");
    // 32 MiB of zeros deflate to about 32 KiB: a thousandfold expansion.
    let zeros = vec![0u8; 32 << 20];
    let zip = zip_of(
        &[
            ("model.obj", b"v 0 0 0\n".as_slice()),
            ("padding.bin", &zeros),
        ],
        zip::CompressionMethod::Deflated,
    );
    assert!(zip.len() < 1 << 20);
    let path = saved(dir.path(), "bomb.zip", &zip);
    let error = refused(&path, ArchiveKind::Zip, &ArchiveLimits::default());
    assert!(error.to_string().contains("decompression bomb"), "{error}");
    // The absolute cap holds too, whatever the ratio.
    let capped = ArchiveLimits {
        max_unpacked_bytes: 1 << 20,
        max_expansion_ratio: u64::MAX,
        ..ArchiveLimits::default()
    };
    let error = refused(&path, ArchiveKind::Zip, &capped);
    assert!(
        error.to_string().contains("more than 1048576 bytes"),
        "{error}"
    );
}

#[test]
fn too_many_entries_are_refused() {
    let dir = tempfile::tempdir().expect("tempdir");
    // 100 000 entries: counted from the zip's directory before any is read.
    let mut writer = zip::ZipWriter::new(std::io::Cursor::new(Vec::new()));
    let options =
        zip::write::SimpleFileOptions::default().compression_method(zip::CompressionMethod::Stored);
    writer.start_file("model.obj", options).expect("file");
    for i in 0..100_000 {
        writer
            .start_file(format!("d/{i}.txt"), options)
            .expect("file");
    }
    let zip = writer.finish().expect("zip").into_inner();
    let path = saved(dir.path(), "many.zip", &zip);
    let error = refused(&path, ArchiveKind::Zip, &ArchiveLimits::default());
    assert!(matches!(error, ArchiveError::TooLarge(_)), "{error}");
    assert!(error.to_string().contains("100001 entries"), "{error}");
    // A tar is counted as it is read.
    let names: Vec<String> = (0..20).map(|i| format!("{i}.obj")).collect();
    let entries: Vec<_> = names
        .iter()
        .map(|n| {
            (
                n.as_str(),
                tar::EntryType::Regular,
                b"v 0 0 0\n".as_slice(),
                None,
            )
        })
        .collect();
    let path = saved(dir.path(), "many.tar", &raw_tar(&entries));
    let limits = ArchiveLimits {
        max_entries: 10,
        ..ArchiveLimits::default()
    };
    let error = refused(&path, ArchiveKind::Tar, &limits);
    assert!(matches!(error, ArchiveError::TooLarge(_)), "{error}");
}

#[test]
fn clashing_entries_corrupt_archives_and_archives_without_an_asset_are_refused() {
    let dir = tempfile::tempdir().expect("tempdir");
    let same = raw_tar(&[
        ("model.obj", tar::EntryType::Regular, b"v 0 0 0\n", None),
        ("model.obj", tar::EntryType::Regular, b"v 1 1 1\n", None),
    ]);
    let path = saved(dir.path(), "same.tar", &same);
    let error = refused(&path, ArchiveKind::Tar, &ArchiveLimits::default());
    assert!(error.to_string().contains("same path"), "{error}");
    let under_file = raw_tar(&[
        ("model.obj", tar::EntryType::Regular, b"v 0 0 0\n", None),
        ("model.obj/x.png", tar::EntryType::Regular, b"png", None),
    ]);
    let path = saved(dir.path(), "under.tar", &under_file);
    refused(&path, ArchiveKind::Tar, &ArchiveLimits::default());

    let dir_path = tempfile::tempdir().expect("tempdir");
    let folder = urdf_folder(dir_path.path());
    let archive = dir.path().join("cut.tar.gz");
    pack_folder(&folder, &archive).expect("pack");
    let bytes = std::fs::read(&archive).expect("read");
    let path = saved(dir.path(), "cut.tar.gz", &bytes[..bytes.len() / 2]);
    let error = refused(&path, ArchiveKind::TarGz, &ArchiveLimits::default());
    assert!(matches!(error, ArchiveError::Unreadable(_)), "{error}");
    let path = saved(dir.path(), "not.zip", b"this is not a zip file at all");
    let error = refused(&path, ArchiveKind::Zip, &ArchiveLimits::default());
    assert!(matches!(error, ArchiveError::Unreadable(_)), "{error}");

    let zip = zip_of(&[("notes.txt", b"no mesh")], zip::CompressionMethod::Stored);
    let path = saved(dir.path(), "empty.zip", &zip);
    let error = inspect(&path, ArchiveKind::Zip, &ArchiveLimits::default()).expect_err("no asset");
    assert!(matches!(error, ArchiveError::NoAsset(_)), "{error}");
}

#[test]
fn packing_refuses_a_folder_with_a_link_or_without_an_asset() {
    let dir = tempfile::tempdir().expect("tempdir");
    let folder = urdf_folder(dir.path());
    #[cfg(unix)]
    {
        std::os::unix::fs::symlink("/etc/passwd", folder.join("textured_objs/x.png"))
            .expect("link");
        let error = pack_folder(&folder, &dir.path().join("x.tar.gz")).expect_err("a link");
        assert!(error.to_string().contains("x.png"), "{error}");
        std::fs::remove_file(folder.join("textured_objs/x.png")).expect("unlink");
    }
    let empty = dir.path().join("empty");
    write(&empty.join("notes.txt"), b"nothing");
    let error = pack_folder(&empty, &dir.path().join("e.tar.gz")).expect_err("no asset");
    assert!(matches!(error, ArchiveError::NoAsset(_)), "{error}");
}
