"""The package's wheel installed into a fresh virtual environment, for the install tests
(``test_clean_install.py``, ``test_newest_gymnasium.py``)."""

from __future__ import annotations

import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]


def release_build_wheel(out: Path) -> Path:
    """The wheel maturin builds from the repository's release build into ``out`` (seconds:
    from the build's artefacts). Skips the test where maturin is not next to this Python."""
    maturin = shutil.which("maturin", path=str(Path(sys.executable).parent))
    if maturin is None:
        pytest.skip("maturin is not installed next to this Python")
    subprocess.run(
        [maturin, "build", "--release", "--quiet", "--out", str(out)], cwd=ROOT, check=True
    )
    (wheel,) = out.glob("tactile_search-*.whl")
    return wheel


def fresh_install(tmp_path: Path, *requirements: str) -> Path:
    """The Python of a new venv in ``tmp_path`` holding the wheel maturin builds from the
    repository and its dependencies, plus ``requirements`` (pip arguments, e.g.
    ``"--upgrade", "gymnasium"``). Skips the test where maturin is not next to this Python."""
    wheel = release_build_wheel(tmp_path / "wheels")
    venv = tmp_path / "venv"
    subprocess.run([sys.executable, "-m", "venv", str(venv)], check=True)
    python = venv / "bin" / "python"
    pip = [str(python), "-m", "pip", "install", "--quiet", "--disable-pip-version-check"]
    subprocess.run([*pip, str(wheel)], check=True)
    if requirements:
        subprocess.run([*pip, *requirements], check=True)
    return python
