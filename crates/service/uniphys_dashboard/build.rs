//! Gathers the dashboard's files into `$OUT_DIR/ui/` and writes `$OUT_DIR/files.rs`, the table
//! `lib.rs` embeds:
//! - every file under `web/static/`, as written;
//! - three.js from the npm registry: `npm ci` runs on a copy of `web/package.json` and
//!   `web/package-lock.json` in `$OUT_DIR/npm` (so nothing is written into the source tree), and
//!   the module builds plus the addons the viewer imports are copied to `vendor/three/`.
//!
//! Without npm (or with `UNIPHYS_DASHBOARD_NO_NPM=1`) the build still succeeds: the vendor module
//! is a stub that throws, the asset page says the 3D viewer was not bundled, and a cargo warning
//! says how to get it.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::{env, fs};

/// The addons of `three/examples/jsm/` the viewer imports.
const ADDONS: &[&str] = &["loaders/OBJLoader.js", "controls/OrbitControls.js"];
/// The module builds of `three/build/` (`three.module.js` imports `three.core.js`).
const BUILDS: &[&str] = &["three.module.js", "three.core.js"];

fn main() {
    let manifest_dir = PathBuf::from(env::var_os("CARGO_MANIFEST_DIR").expect("cargo sets it"));
    let out_dir = PathBuf::from(env::var_os("OUT_DIR").expect("cargo sets it"));
    let web = manifest_dir.join("web");
    for path in ["static", "package.json", "package-lock.json"] {
        println!("cargo::rerun-if-changed={}", web.join(path).display());
    }
    println!("cargo::rerun-if-env-changed=UNIPHYS_DASHBOARD_NO_NPM");
    // npm installed after a build without it changes PATH's lookup, not a file here: rebuild
    // when PATH changes (cheap: the packages are installed once per lock file).
    println!("cargo::rerun-if-env-changed=PATH");

    let ui = out_dir.join("ui");
    if ui.exists() {
        fs::remove_dir_all(&ui).expect("clear the previous ui folder");
    }
    let mut files = Vec::new();
    copy_tree(&web.join("static"), &ui, "", &mut files);

    let three = match npm_three(&web, &out_dir.join("npm")) {
        Ok(three) => Some(three),
        Err(why) => {
            println!(
                "cargo::warning=the dashboard's 3D viewer is not bundled ({why}); install Node.js and npm, then `cargo clean -p uniphys_dashboard` and rebuild"
            );
            None
        }
    };
    let vendor = ui.join("vendor/three");
    fs::create_dir_all(vendor.join("addons")).expect("create the vendor folder");
    if let Some(three) = &three {
        for name in BUILDS {
            let from = three.join("build").join(name);
            copy(
                &from,
                &vendor.join(name),
                &format!("vendor/three/{name}"),
                &mut files,
            );
        }
        for addon in ADDONS {
            let from = three.join("examples/jsm").join(addon);
            let to = vendor.join("addons").join(addon);
            copy(
                &from,
                &to,
                &format!("vendor/three/addons/{addon}"),
                &mut files,
            );
        }
    } else {
        let stub = "throw new Error('three.js was not bundled into this build: install Node.js and npm, then rebuild');\n";
        let path = vendor.join("three.module.js");
        fs::write(&path, stub).expect("write the stub");
        files.push(("vendor/three/three.module.js".to_owned(), path));
    }

    files.sort();
    let mut table = String::from("/// Every embedded file: (path under /ui/, content).\n");
    table.push_str("pub(crate) static FILES: &[(&str, &[u8])] = &[\n");
    for (name, path) in &files {
        writeln!(
            table,
            "    ({name:?}, include_bytes!({:?})),",
            path.display().to_string()
        )
        .expect("write to a string");
    }
    table.push_str("];\n");
    writeln!(
        table,
        "/// Whether three.js came from npm (false: a stub that throws).\npub(crate) const THREE_BUNDLED: bool = {};",
        three.is_some()
    )
    .expect("write to a string");
    let index = fs::read_to_string(web.join("static/index.html")).expect("read index.html");
    writeln!(
        table,
        "/// CSP sources of the inline scripts of index.html (the import map).\npub(crate) const INLINE_SCRIPT_HASHES: &str = {:?};",
        inline_script_hashes(&index).join(" ")
    )
    .expect("write to a string");
    fs::write(out_dir.join("files.rs"), table).expect("write files.rs");
}

/// `'sha256-<base64>'` of each inline `<script>` of `html` (its exact text between the tags), so
/// the Content-Security-Policy can allow the import map and no other inline script.
fn inline_script_hashes(html: &str) -> Vec<String> {
    use sha2::{Digest, Sha256};
    let mut hashes = Vec::new();
    let mut rest = html;
    while let Some(open) = rest.find("<script") {
        let tag_end = open + rest[open..].find('>').expect("a closed <script> tag") + 1;
        let close = tag_end + rest[tag_end..].find("</script>").expect("a </script>");
        let is_inline = !rest[open..tag_end].contains(" src=");
        if is_inline {
            let digest = Sha256::digest(&rest.as_bytes()[tag_end..close]);
            hashes.push(format!("'sha256-{}'", base64::encode(digest)));
        }
        rest = &rest[close..];
    }
    hashes
}

/// Installs the locked packages into `npm_dir` (once per lock file) and returns the path of the
/// `three` package.
fn npm_three(web: &Path, npm_dir: &Path) -> Result<PathBuf, String> {
    if env::var_os("UNIPHYS_DASHBOARD_NO_NPM").is_some_and(|v| v == "1") {
        return Err("UNIPHYS_DASHBOARD_NO_NPM=1".into());
    }
    fs::create_dir_all(npm_dir).map_err(|e| e.to_string())?;
    let lock =
        fs::read(web.join("package-lock.json")).map_err(|e| format!("package-lock.json: {e}"))?;
    let stamp = npm_dir.join("installed.lock");
    let three = npm_dir.join("node_modules/three");
    if fs::read(&stamp).is_ok_and(|installed| installed == lock) && three.exists() {
        return Ok(three);
    }
    for name in ["package.json", "package-lock.json"] {
        fs::copy(web.join(name), npm_dir.join(name)).map_err(|e| format!("{name}: {e}"))?;
    }
    let output = Command::new("npm")
        .args([
            "ci",
            "--ignore-scripts",
            "--no-audit",
            "--no-fund",
            "--loglevel=error",
        ])
        .current_dir(npm_dir)
        .output()
        .map_err(|e| format!("cannot run npm: {e}"))?;
    if !output.status.success() {
        let stderr = String::from_utf8_lossy(&output.stderr);
        return Err(format!("npm ci failed: {}", stderr.trim()));
    }
    fs::write(&stamp, lock).map_err(|e| e.to_string())?;
    Ok(three)
}

fn copy_tree(from: &Path, to: &Path, prefix: &str, files: &mut Vec<(String, PathBuf)>) {
    let entries = fs::read_dir(from).unwrap_or_else(|e| panic!("read {}: {e}", from.display()));
    for entry in entries {
        let entry = entry.expect("readable entry");
        let name = entry.file_name().to_string_lossy().into_owned();
        let path = entry.path();
        let url = format!("{prefix}{name}");
        if path.is_dir() {
            copy_tree(&path, &to.join(&name), &format!("{url}/"), files);
        } else {
            copy(&path, &to.join(&name), &url, files);
        }
    }
}

fn copy(from: &Path, to: &Path, url: &str, files: &mut Vec<(String, PathBuf)>) {
    if let Some(parent) = to.parent() {
        fs::create_dir_all(parent).expect("create a folder");
    }
    fs::copy(from, to).unwrap_or_else(|e| panic!("copy {}: {e}", from.display()));
    files.push((url.to_owned(), to.to_path_buf()));
}
