"""The layer check (scripts/layers.py) passes on this workspace and fails, naming the edge, when a
crate depends on a layer above it, on a crate of its own layer it may not use, or on an external
crate fenced off from its layer."""

import copy
import json
import subprocess
import sys

import pytest

from conftest import REPO

sys.path.insert(0, str(REPO / "scripts"))
import layers  # noqa: E402


@pytest.fixture(scope="module")
def metadata():
    text = subprocess.run(
        ["cargo", "metadata", "--format-version", "1", "--no-deps", "--locked", "--offline"],
        check=True, capture_output=True, text=True, cwd=REPO,
    ).stdout
    return json.loads(text)


def with_dependency(metadata, crate, dependency, kind=None):
    changed = copy.deepcopy(metadata)
    package = next(p for p in changed["packages"] if p["name"] == crate)
    package["dependencies"].append({"name": dependency, "kind": kind})
    return changed


def test_the_workspace_keeps_its_layers(metadata):
    assert layers.violations(metadata) == []


@pytest.mark.parametrize(
    "crate, dependency, said",
    [
        ("uniphys_types", "uniphys_pipeline", "uniphys_types (base) depends on uniphys_pipeline (stages"),
        ("uniphys_verify", "uniphys_queue", "uniphys_verify (stages) depends on uniphys_queue (service"),
        ("uniphys_verify", "uniphys_ground", "within stages only"),
        ("uniphys_queue", "uniphys_storage", "uniphys_queue may use only"),
        ("uniphys_export", "tokio", "uniphys_export (stages) depends on tokio: fenced off from stages"),
        ("uniphys_geometry", "anyhow", "fenced off from base"),
    ],
)
def test_a_wrong_dependency_is_named(metadata, crate, dependency, said):
    found = layers.violations(with_dependency(metadata, crate, dependency))
    assert len(found) == 1 and said in found[0], found


def test_tests_may_use_the_testing_crates(metadata):
    assert layers.violations(with_dependency(metadata, "uniphys_types", "uniphys_examples", "dev")) == []
    found = layers.violations(with_dependency(metadata, "uniphys_types", "uniphys_examples"))
    assert len(found) == 1 and "testing" in found[0], found
