#!/usr/bin/env python3
"""The workspace's layer rules (ARCHITECTURE.md, "Crates"), checked on `cargo metadata`.

A crate's group is its folder, `crates/<group>/<crate>`. A crate may depend on crates of the groups
its group may use (`MAY_USE`); within its own group only on the crates listed in `WITHIN_GROUP`;
a crate in `ONLY` on nothing beyond what it lists. Dev-dependencies may also use `testing`. Some
external crates are fenced off from whole groups (`FENCED`): the service's databases and HTTP
servers, network clients and async runtimes stay out of `base` and the stages (which are
synchronous CPU code that runs without servers), and `anyhow` stays in binaries.

    scripts/layers.py                   check this workspace (exit 1 naming every broken rule)
    scripts/layers.py --metadata F      check the output of `cargo metadata --no-deps` saved in F
"""

import argparse
import json
import subprocess
import sys
from pathlib import Path

# Groups from the bottom up; `testing` serves tests, benchmarks and the CLI's `examples` command.
MAY_USE = {
    "base": set(),
    "adapters": {"base"},
    "stages": {"base", "adapters"},
    "service": {"base", "adapters", "stages"},
    "testing": {"base", "adapters", "stages", "service"},
    "top": {"base", "adapters", "stages", "service", "testing"},
}

# Edges allowed inside a group (every other one is refused).
WITHIN_GROUP = {
    "uniphys_geometry": {"uniphys_types"},
    # The model-service clients share one error and retry policy over one HTTP client.
    "uniphys_lvlm": {"uniphys_http"},
    "uniphys_vision": {"uniphys_http"},
    "uniphys_uniphysgen": {"uniphys_http"},
    "uniphys_render": {"uniphys_geometry", "uniphys_types"},
    # The grounder and the annotator score motions with the verifier's sweep.
    "uniphys_ground": {"uniphys_verify"},
    "uniphys_annotate": {"uniphys_verify"},
    "uniphys_pipeline": {
        "uniphys_annotate", "uniphys_decompose", "uniphys_eval", "uniphys_export",
        "uniphys_ground", "uniphys_simulate", "uniphys_verify",
    },
    "uniphys_api": {"uniphys_queue", "uniphys_dashboard"},
    "uniphys_telemetry": {"uniphys_queue"},
    "uniphys_worker": {"uniphys_queue", "uniphys_hints", "uniphys_telemetry"},
    "uniphys_bench": {"uniphys_examples", "uniphys_replay"},
}

# Crates held to fewer groups than their own may use (normal dependencies).
ONLY = {
    # No IO, no async: the types every layer shares.
    "uniphys_types": set(),
    # The queue's own parts depend on no other group.
    "uniphys_queue": set(),
    "uniphys_hints": set(),
    "uniphys_dashboard": set(),
    "uniphys_telemetry": {"uniphys_queue"},
    # Test data and replay servers are built from the base alone.
    "uniphys_examples": {"uniphys_geometry", "uniphys_types"},
    "uniphys_replay": set(),
}

SERVICE = {"sqlx", "redis", "axum", "hyper", "hyper-util", "tower-http", "apalis", "apalis-postgres"}
NETWORK = {"ureq", "reqwest", "object_store"}
ASYNC = {"tokio", "tokio-util", "futures", "async-trait"}
FENCED = {
    "base": SERVICE | NETWORK | ASYNC | {"anyhow"},
    "stages": SERVICE | NETWORK | ASYNC | {"anyhow"},
    "adapters": SERVICE | {"anyhow"},
    "service": {"anyhow"},
}
# Binaries may use anyhow.
BINARIES = {"uniphys_cli", "uniphys_bench", "uniphys_queue_bench"}


def workspace(metadata):
    """Workspace crates by name: (group, [(dependency, kind)])."""
    root = Path(metadata["workspace_root"])
    crates = {}
    for package in metadata["packages"]:
        parts = Path(package["manifest_path"]).relative_to(root).parts
        group = parts[1] if len(parts) >= 4 and parts[0] == "crates" else None
        deps = [(d["name"], d.get("kind") or "normal") for d in package["dependencies"]]
        crates[package["name"]] = (group, deps)
    return crates


def violations(metadata):
    """Every broken rule, as sentences."""
    crates = workspace(metadata)
    out = []
    for name, (group, deps) in sorted(crates.items()):
        if group not in MAY_USE:
            out.append(f"{name}: not under crates/<group>/ with a known group ({', '.join(MAY_USE)})")
            continue
        for dep, kind in deps:
            if kind == "build":
                continue
            if dep in crates:
                dep_group = crates[dep][0]
                if kind == "dev" and dep_group == "testing":
                    continue
                if dep_group == group:
                    allowed = dep in WITHIN_GROUP.get(name, set())
                    why = f"within {group} only {sorted(WITHIN_GROUP.get(name, set())) or 'nothing'}"
                else:
                    allowed = dep_group in MAY_USE[group]
                    why = f"{group} may use {sorted(MAY_USE[group]) or 'no other group'}"
                if allowed and kind == "normal" and name in ONLY and dep not in ONLY[name]:
                    allowed = False
                    why = f"{name} may use only {sorted(ONLY[name]) or 'no workspace crate'}"
                if not allowed:
                    out.append(f"{name} ({group}) depends on {dep} ({dep_group}, {kind}): {why}")
            elif kind == "normal" and dep in FENCED.get(group, set()) and name not in BINARIES:
                out.append(f"{name} ({group}) depends on {dep}: fenced off from {group}")
    return out


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--metadata", type=Path, help="saved `cargo metadata --no-deps` output")
    args = parser.parse_args()
    if args.metadata:
        metadata = json.loads(args.metadata.read_text())
    else:
        text = subprocess.run(
            ["cargo", "metadata", "--format-version", "1", "--no-deps", "--locked", "--offline"],
            check=True, capture_output=True, text=True,
        ).stdout
        metadata = json.loads(text)
    found = violations(metadata)
    for line in found:
        print(f"layer rule broken: {line}")
    if found:
        print(f"{len(found)} layer rule(s) broken; the rules are in scripts/layers.py (ARCHITECTURE.md, Crates)")
        return 1
    print(f"layer rules hold for {len(workspace(metadata))} crates")
    return 0


if __name__ == "__main__":
    sys.exit(main())
