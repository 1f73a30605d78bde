"""The release wheel (``make wheel``: abi3, manylinux_2_28, built by zig) installs and works
in a fresh virtual environment of CPython 3.10, 3.11 and 3.12 where they are here (``make
wheel-check``: every Python here that it admits), with no Rust toolchain
on PATH: ``scripts/wheel_install_check.py`` runs gymnasium's ``check_env`` on every
registered id and the benchmark with a random policy there. It checks the wheel that
``TACTILE_SEARCH_WHEEL`` names, else ``dist/``'s wheel of this version, else the wheel
maturin builds from the release build (seconds, from its artefacts; tagged with this
machine's glibc, which only ``make wheel``'s zig link lowers: ``make wheel-check`` checks
that one). The helpers it relies on are tested here without a wheel."""

from __future__ import annotations

import os
import subprocess
import sys
import zipfile
from pathlib import Path

import pytest

import tactile_search
from scripts.wheel_install_check import (
    DIST,
    ROOT,
    RUST_TOOLS,
    interpreters,
    wheel_metadata,
    without_rust,
)
from tests.fresh_install import release_build_wheel

SCRIPT = ROOT / "scripts" / "wheel_install_check.py"
#: Names a wheel to check instead of dist/'s.
WHEEL_VARIABLE = "TACTILE_SEARCH_WHEEL"
#: The CPythons the test installs into where they are here, the oldest the wheel admits to
#: the newest the issue asked for; ``make wheel-check`` installs into every one here.
TESTED_VERSIONS = ((3, 10), (3, 11), (3, 12))


def tested_pythons() -> list[str]:
    """The interpreters of ``TESTED_VERSIONS`` found here, else this one."""
    found = [str(path) for v, path in interpreters().items() if v[:2] in TESTED_VERSIONS]
    return found or [sys.executable]


def built_wheel(tmp_path: Path) -> Path:
    """The wheel to check (see the module docstring); a skip where maturin is not next to
    this Python and no wheel is given."""
    named = os.environ.get(WHEEL_VARIABLE)
    if named:
        if not Path(named).is_file():
            raise FileNotFoundError(f"{WHEEL_VARIABLE} names {named!r}, which is not a file")
        return Path(named)
    wheels = sorted(DIST.glob(f"tactile_search-{tactile_search.__version__}-*.whl"))
    if wheels:
        return wheels[-1]
    return release_build_wheel(tmp_path / "wheels")


def test_the_built_wheel_passes_check_env_and_the_benchmark_on_three_pythons_without_rust(
    tmp_path: Path,
) -> None:
    wheel = built_wheel(tmp_path)
    pythons = [arg for python in tested_pythons() for arg in ("--python", python)]
    result = subprocess.run(
        [sys.executable, str(SCRIPT), str(wheel), "--workdir", str(tmp_path), *pythons],
        cwd=tmp_path, capture_output=True, text=True, timeout=3600,
    )  # fmt: skip
    assert result.returncode == 0, result.stdout[-6000:] + result.stderr[-4000:]
    print(result.stdout)  # the Pythons checked and the times, in pytest's -s / -rA output
    for env_id in tactile_search.ENV_IDS:
        assert f"{env_id}: check_env" in result.stdout, result.stdout


def test_the_fresh_environments_path_reaches_no_rust_tool_nor_the_repository(
    tmp_path: Path,
) -> None:
    rust, other = tmp_path / "rust_bin", tmp_path / "bin"
    for folder in (rust, other):
        folder.mkdir()
    (rust / RUST_TOOLS[0]).touch()
    environ = {
        "PATH": os.pathsep.join([str(rust), str(other)]),
        "PYTHONPATH": str(ROOT),
        "HOME": str(tmp_path),
    }
    clean = without_rust(environ)
    assert clean["PATH"] == str(other)
    assert "PYTHONPATH" not in clean and clean["HOME"] == str(tmp_path)


def test_the_wheels_version_and_requires_python_come_from_its_metadata(tmp_path: Path) -> None:
    wheel = tmp_path / "tactile_search-9.8.7-cp310-abi3-manylinux_2_28_x86_64.whl"
    with zipfile.ZipFile(wheel, "w") as archive:
        archive.writestr(
            "tactile_search-9.8.7.dist-info/METADATA",
            "Metadata-Version: 2.4\nName: tactile_search\nVersion: 9.8.7\n"
            "Requires-Python: >=3.10\n",
        )
    assert wheel_metadata(wheel) == ("9.8.7", ">=3.10")
    with pytest.raises(ValueError, match=r"a \.whl file, got .*METADATA"):
        wheel_metadata(tmp_path / "METADATA")
