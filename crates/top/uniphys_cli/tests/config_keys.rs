//! The configuration keys used by `docker-compose.yml` and `deploy/k8s/` are the ones the binary
//! reads, and the README documents every key the binary reads.

use std::collections::BTreeSet;
use std::path::Path;

use clap::CommandFactory;
use uniphys_storage::StorageOptions;

fn repo() -> &'static Path {
    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../../.."))
}

fn env_keys(command: &clap::Command, keys: &mut BTreeSet<String>) {
    for arg in command.get_arguments() {
        if let Some(env) = arg.get_env() {
            keys.insert(env.to_string_lossy().into_owned());
        }
    }
    for sub in command.get_subcommands() {
        env_keys(sub, keys);
    }
}

fn keys_in(text: &str, prefix: &str) -> BTreeSet<String> {
    let mut found = BTreeSet::new();
    let mut rest = text;
    while let Some(at) = rest.find(prefix) {
        let tail = &rest[at..];
        let end = tail
            .find(|c: char| !(c.is_ascii_uppercase() || c.is_ascii_digit() || c == '_'))
            .unwrap_or(tail.len());
        if end > prefix.len() {
            found.insert(tail[..end].to_owned());
        }
        rest = &tail[end..];
    }
    found
}

fn deployment_files() -> Vec<(String, String)> {
    let mut files = vec![repo().join("docker-compose.yml")];
    let k8s = repo().join("deploy/k8s");
    let mut manifests: Vec<_> = std::fs::read_dir(&k8s)
        .expect("deploy/k8s exists")
        .flatten()
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|e| e == "yaml"))
        .collect();
    manifests.sort();
    files.extend(manifests);
    files
        .into_iter()
        .map(|p| {
            let text = std::fs::read_to_string(&p).expect("readable");
            (p.display().to_string(), text)
        })
        .collect()
}

#[test]
fn deployments_use_only_keys_the_binary_reads() {
    let mut known = BTreeSet::new();
    env_keys(&uniphys_cli::Cli::command(), &mut known);
    assert!(known.contains("UNIPHYS_DATABASE_URL") && known.contains("UNIPHYS_STAGES"));
    let files = deployment_files();
    assert!(files.len() >= 6, "compose file and k8s manifests");
    for (path, text) in &files {
        for key in keys_in(text, "UNIPHYS_") {
            assert!(
                known.contains(&key),
                "{path} sets {key}, which uniphys does not read"
            );
        }
        for key in keys_in(text, "AWS_") {
            let value = if key.ends_with("ALLOW_HTTP") {
                "true"
            } else {
                "x"
            };
            let options = StorageOptions::from_env_map([(key.as_str(), value)]).expect("valid");
            assert!(
                options != StorageOptions::default(),
                "{path} sets {key}, which the object store ignores"
            );
        }
    }
}

#[test]
fn the_readme_documents_every_key() {
    let mut known = BTreeSet::new();
    env_keys(&uniphys_cli::Cli::command(), &mut known);
    let readme = std::fs::read_to_string(repo().join("README.md")).expect("README");
    let missing: Vec<&String> = known
        .iter()
        .filter(|k| !readme.contains(k.as_str()))
        .collect();
    assert!(missing.is_empty(), "README does not document {missing:?}");
}
