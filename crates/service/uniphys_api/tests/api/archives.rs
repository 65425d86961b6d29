//! Multi-file assets submitted as archives: a URDF folder or an OBJ with its MTL and texture is
//! stored whole; a hostile archive is refused with its reason before anything is stored.

use std::io::Write;

use axum::http::StatusCode;
use uniphys_queue::Backend;

use crate::harness::TestApp;

/// A tar of a small PartNet-Mobility-style folder (a URDF naming an OBJ mesh and its MTL; gzip
/// is covered by uniphys_archive's own tests).
fn urdf_folder_tar() -> Vec<u8> {
    let mut tar = tar::Builder::new(Vec::new());
    let files: [(&str, &[u8]); 3] = [
        (
            "45213/mobility.urdf",
            b"<robot name=\"r\"><link name=\"base\"><visual><geometry><mesh filename=\"textured_objs/a.obj\"/></geometry></visual></link></robot>",
        ),
        ("45213/textured_objs/a.obj", b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"),
        ("45213/textured_objs/a.mtl", b"newmtl m\nKd 1 1 1\n"),
    ];
    for (name, data) in files {
        let mut header = tar::Header::new_gnu();
        header.set_size(data.len() as u64);
        header.set_mode(0o644);
        tar.append_data(&mut header, name, data).expect("append");
    }
    tar.into_inner().expect("tar")
}

fn zip_of(entries: &[(&str, &[u8])]) -> Vec<u8> {
    let mut writer = zip::ZipWriter::new(std::io::Cursor::new(Vec::new()));
    let options = zip::write::SimpleFileOptions::default()
        .compression_method(zip::CompressionMethod::Deflated);
    for (name, data) in entries {
        writer.start_file(*name, options).expect("start");
        writer.write_all(data).expect("data");
    }
    writer.finish().expect("zip").into_inner()
}

pub async fn an_archived_asset_folder_is_accepted_stored_whole_and_idempotent(backend: Backend) {
    let Some(app) = TestApp::open(backend, |c| c).await else {
        return;
    };
    let folder = urdf_folder_tar();
    let first = app.upload("45213.tar", &folder).await;
    assert_eq!(first.status, StatusCode::CREATED, "{}", first.error().1);
    let key = first.json()["source_key"].as_str().expect("key").to_owned();
    assert!(key.ends_with("/45213.tar"), "{key}");
    assert_eq!(app.artifacts.get(&key).await.expect("stored"), folder);
    let again = app.upload("45213.tar", &folder).await;
    assert_eq!(again.status, StatusCode::OK);
    assert_eq!(again.json()["asset_id"], first.json()["asset_id"]);

    let chair = zip_of(&[
        ("chair.obj", b"mtllib chair.mtl\nv 0 0 0\n"),
        ("chair.mtl", b"newmtl wood\nmap_Kd wood.png\n"),
        ("wood.png", &[0x89, b'P', b'N', b'G']),
    ]);
    let zipped = app.upload("chair.zip", &chair).await;
    assert_eq!(zipped.status, StatusCode::CREATED, "{}", zipped.error().1);
    app.finish().await;
}

pub async fn a_hostile_archive_is_422_with_its_reason_and_stores_nothing(backend: Backend) {
    let Some(app) = TestApp::open(backend, |c| c).await else {
        return;
    };
    let traversal = zip_of(&[
        ("model.obj", b"v 0 0 0\n"),
        ("../../etc/cron.d/x", b"* * * * *"),
    ]);
    let bomb = zip_of(&[
        ("model.obj", b"v 0 0 0\n"),
        ("pad.bin", &vec![0u8; 8 << 20]),
    ]);
    let mut linked = zip::ZipWriter::new(std::io::Cursor::new(Vec::new()));
    let options = zip::write::SimpleFileOptions::default();
    linked.start_file("model.obj", options).expect("file");
    linked.write_all(b"v 0 0 0\n").expect("data");
    linked
        .add_symlink("wood.png", "/etc/shadow", options)
        .expect("link");
    let linked = linked.finish().expect("zip").into_inner();
    let no_asset = zip_of(&[("notes.txt", b"no mesh here")]);
    for (name, bytes, reason) in [
        ("traversal.zip", traversal.as_slice(), ".. component"),
        ("bomb.zip", bomb.as_slice(), "decompression bomb"),
        ("linked.zip", linked.as_slice(), "a link"),
        (
            "notes.zip",
            no_asset.as_slice(),
            "no file the pipeline reads",
        ),
        (
            "garbage.tar.gz",
            b"not gzip at all".as_slice(),
            "cannot be read",
        ),
    ] {
        let answer = app.upload(name, bytes).await;
        assert_eq!(answer.status, StatusCode::UNPROCESSABLE_ENTITY, "{name}");
        let (_, message) = answer.error();
        assert!(
            message.contains(name) && message.contains(reason),
            "{name}: {message}"
        );
    }
    // By key the same check applies.
    let key = app.put_incoming("traversal.zip", &traversal).await;
    let by_key = app
        .post_json("/v1/assets/by-url", &format!(r#"{{"url": "{key}"}}"#))
        .await;
    assert_eq!(by_key.status, StatusCode::UNPROCESSABLE_ENTITY);
    assert!(
        by_key.error().1.contains(".. component"),
        "{}",
        by_key.error().1
    );
    app.assert_nothing_submitted().await;
    assert_eq!(app.spool_files(), 0, "refused uploads leave no spool file");
    app.finish().await;
}

pub async fn a_folder_in_the_store_is_submitted_by_its_prefix(backend: Backend) {
    let Some(app) = TestApp::open(backend, |c| c).await else {
        return;
    };
    let t = app.tenant.0;
    let files: [(&str, &[u8]); 3] = [
        (
            "mobility.urdf",
            b"<robot name=\"r\"><link name=\"base\"/></robot>",
        ),
        (
            "textured_objs/a.obj",
            b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
        ),
        ("textured_objs/a.mtl", b"newmtl m\n"),
    ];
    for (name, bytes) in files {
        app.put_incoming(&format!("45213/{name}"), bytes).await;
    }
    let by_prefix = format!(r#"{{"url": "incoming/t{t}/45213/"}}"#);
    let first = app.post_json("/v1/assets/by-url", &by_prefix).await;
    assert_eq!(first.status, StatusCode::CREATED, "{}", first.error().1);
    let key = first.json()["source_key"].as_str().expect("key").to_owned();
    assert!(key.ends_with("/45213.tar"), "{key}");
    // The stored tar holds the folder's files under their paths, and is read from the URDF.
    let stored = app.artifacts.get(&key).await.expect("stored");
    let mut archive = tar::Archive::new(stored.as_slice());
    let mut names: Vec<String> = archive
        .entries()
        .expect("entries")
        .map(|e| {
            e.expect("entry")
                .path()
                .expect("path")
                .display()
                .to_string()
        })
        .collect();
    names.sort();
    assert_eq!(
        names,
        [
            "mobility.urdf",
            "textured_objs/a.mtl",
            "textured_objs/a.obj"
        ]
    );
    // The same objects make the same asset.
    let again = app.post_json("/v1/assets/by-url", &by_prefix).await;
    assert_eq!(again.status, StatusCode::OK);
    assert_eq!(again.json()["asset_id"], first.json()["asset_id"]);

    app.put_incoming("notes/readme.txt", b"no mesh").await;
    for (body, expect) in [
        (
            format!(r#"{{"url": "incoming/t{t}/nothing/"}}"#),
            "no objects under",
        ),
        (
            format!(r#"{{"url": "incoming/t{t}/notes/"}}"#),
            "no file the pipeline reads",
        ),
        (
            format!(r#"{{"url": "incoming/t{t}/45213/", "filename": "x.zip"}}"#),
            "must end in .tar",
        ),
    ] {
        let answer = app.post_json("/v1/assets/by-url", &body).await;
        assert_eq!(answer.status, StatusCode::UNPROCESSABLE_ENTITY, "{body}");
        assert!(
            answer.error().1.contains(expect),
            "{body}: {}",
            answer.error().1
        );
    }
    app.finish().await;
}
