"""The core's dependency graph is the same in the extension's build and in its test builds.

``env_core/Cargo.toml`` asks for the features that numpy and pyo3 (the ``python`` feature)
and the dev-dependencies turn on in crates the core shares with them (num-traits,
matrixmultiply, either, syn, ...), so that the extension's build (``maturin develop
--release``: ``python``, no dev-dependencies), ``cargo clippy --all-targets`` with and
without the feature and ``cargo test --release`` (dev-dependencies, no ``python``) share one
compiled copy of rapier and faer. When a dependency update makes the graphs part, each of
those builds compiles the whole tree again: this test names the crates whose features differ.
"""

from __future__ import annotations

import re
import shutil
import subprocess
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[1]
LINE = re.compile(r"^(?P<crate>\S+ v\S+)(?: \(.*?\))? \[(?P<features>[^\]]*)\]")

pytestmark = pytest.mark.skipif(shutil.which("cargo") is None, reason="needs cargo")


def crate_features(edges: str, *cargo_args: str) -> dict[str, set[str]]:
    """Every crate of the core's graph over ``edges`` (``normal,build`` for the extension;
    with ``dev`` for a test build; proc macros among them) with the features cargo resolves
    for it, by ``name vX.Y.Z``."""
    done = subprocess.run(
        [
            "cargo",
            "tree",
            "--locked",
            "-p",
            "env_core",
            "-e",
            edges,
            "--prefix",
            "none",
            "-f",
            "{p} [{f}]",
            *cargo_args,
        ],
        cwd=REPO,
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert done.returncode == 0, done.stderr
    found: dict[str, set[str]] = {}
    for line in done.stdout.splitlines():
        match = LINE.match(line)
        if match:
            features = {f for f in match["features"].split(",") if f}
            found.setdefault(match["crate"], set()).update(features)
    return found


def test_the_parser_reads_cargo_trees_lines() -> None:
    match = LINE.match("env_core v0.1.0 (/work/env_core) [default,python]")
    assert match and match["crate"] == "env_core v0.1.0" and match["features"] == "default,python"
    match = LINE.match("pyo3-macros v0.30.1 (proc-macro) []")
    assert match and match["crate"] == "pyo3-macros v0.30.1" and match["features"] == ""


@pytest.mark.parametrize("build", ["without python", "tests"])
def test_shared_crates_get_the_extensions_features(build: str) -> None:
    extension = crate_features("normal,build", "--features", "python")
    other = crate_features("normal,build,dev" if build == "tests" else "normal,build")
    assert "rapier3d" in " ".join(other) and "pyo3" in " ".join(extension)
    parted = {
        crate: {build: sorted(other[crate]), "extension": sorted(extension[crate])}
        for crate in sorted(set(other) & set(extension))
        if other[crate] != extension[crate] and not crate.startswith("env_core ")
    }
    assert parted == {}, (
        "ask for these features in env_core/Cargo.toml too (see its feature-unification note)"
    )
