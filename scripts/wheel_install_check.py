"""The built wheel works wherever it installs: it goes into a fresh virtual environment of
every CPython on this machine that its ``Requires-Python`` admits (``python3.N`` on PATH and
pyenv's installs), with no Rust toolchain on PATH and binary packages only (nothing is
compiled on the way), and there, imported from the environment's own site-packages, it
passes gymnasium's ``check_env`` on every registered id in both action modes and runs the
benchmark (``tactile_search.benchmark.evaluate``) with a random policy on each id.

    python scripts/wheel_install_check.py                    # the wheel in dist/ (make wheel)
    python scripts/wheel_install_check.py WHEEL --workdir DIR --python python3.12

``make wheel-check`` runs it after ``make wheel``; ``tests/test_wheel_install.py`` runs it on a
wheel in dist/ (or the one ``TACTILE_SEARCH_WHEEL`` names). It prints how long each
install and check took. Inside each environment it runs itself again with ``--installed``:
that part imports only what the wheel brings.
"""

from __future__ import annotations

import argparse
import email.parser
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time
import zipfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
DIST = ROOT / "dist"
#: The executables whose directories leave PATH: the check proves the wheel needs no Rust.
RUST_TOOLS = ("cargo", "rustc", "rustup")
#: Unset for the fresh environment: those that would let it see the repository, another
#: environment or Rust's homes, and the one that would turn the checks' asserts off.
UNSET = ("PYTHONPATH", "PYTHONHOME", "VIRTUAL_ENV", "CARGO_HOME", "RUSTUP_HOME", "PYTHONOPTIMIZE")
#: Episodes of the benchmark's random policy on each id.
EPISODES = 2
PYTHON_NAME = re.compile(r"python3\.\d+")
#: What a candidate interpreter reports: its binary (a venv's Python resolves to its base
#: one), implementation and version; it fails where the venv module is missing.
PROBE = (
    "import ensurepip, json, os, sys, venv; print(json.dumps([os.path.realpath(sys.executable), "
    "sys.implementation.name, *sys.version_info[:3]]))"
)


def the_wheel(dist: Path = DIST) -> Path:
    """The one tactile_search wheel in ``dist`` (``make wheel`` leaves one there)."""
    wheels = sorted(dist.glob("tactile_search-*.whl"))
    if len(wheels) != 1:
        raise FileNotFoundError(
            f"expected one tactile_search wheel in {dist} (make wheel builds it), "
            f"found {[w.name for w in wheels]}"
        )
    return wheels[0]


def wheel_metadata(wheel: Path) -> tuple[str, str]:
    """The wheel's version and its ``Requires-Python``, read from its METADATA."""
    if wheel.suffix != ".whl" or not wheel.is_file():
        raise ValueError(f"expected the path of a .whl file, got {str(wheel)!r}")
    with zipfile.ZipFile(wheel) as archive:
        (name,) = [n for n in archive.namelist() if n.endswith(".dist-info/METADATA")]
        metadata = email.parser.Parser().parsestr(archive.read(name).decode())
    return metadata["Version"], metadata["Requires-Python"] or ""


def described(candidate: Path) -> tuple[tuple[int, int, int], Path] | None:
    """The version and executable of the CPython ``candidate`` runs, if it runs one that can
    make a venv (None for a pyenv shim of an unselected version, or no venv module)."""
    probe = subprocess.run([str(candidate), "-c", PROBE], capture_output=True, text=True)
    if probe.returncode != 0:
        return None
    executable, implementation, major, minor, micro = json.loads(probe.stdout)
    return ((major, minor, micro), Path(executable)) if implementation == "cpython" else None


def interpreters() -> dict[tuple[int, int, int], Path]:
    """Every CPython 3.N here that can make a venv, by version: ``python3.N`` on PATH first,
    then pyenv's installs (its shims run only the versions selected, so its installs are
    asked directly). The first one found of a minor version is kept."""
    candidates = [
        path
        for folder in os.environ.get("PATH", "").split(os.pathsep)
        if folder and Path(folder).is_dir()
        for path in sorted(Path(folder).iterdir())
        if PYTHON_NAME.fullmatch(path.name)
    ]
    pyenv = shutil.which("pyenv")
    if pyenv is not None:
        root = subprocess.run([pyenv, "root"], capture_output=True, text=True, check=True)
        candidates += sorted(Path(root.stdout.strip(), "versions").glob("3.*/bin/python3"))
    found: dict[tuple[int, int], tuple[tuple[int, int, int], Path]] = {}
    for candidate in candidates:
        python = described(candidate)
        if python is not None:
            found.setdefault(python[0][:2], python)
    return dict(sorted(found.values()))


def without_rust(environ: dict[str, str]) -> dict[str, str]:
    """``environ`` with every PATH folder that holds a Rust tool removed and the variables
    that reach outside a fresh environment unset."""
    folders = [
        folder
        for folder in environ.get("PATH", "").split(os.pathsep)
        if folder and not any((Path(folder) / tool).exists() for tool in RUST_TOOLS)
    ]
    clean = {k: v for k, v in environ.items() if k not in UNSET}
    clean["PATH"] = os.pathsep.join(folders)
    return clean


def check_with(python: Path, wheel: Path, workdir: Path, version: str) -> str:
    """Installs ``wheel`` into a new venv of ``python`` under ``workdir`` and runs the
    installed checks there; returns their report with the times taken."""
    environ = without_rust(dict(os.environ))
    venv = Path(tempfile.mkdtemp(prefix="venv-", dir=workdir))
    started = time.perf_counter()
    subprocess.run([str(python), "-m", "venv", str(venv)], env=environ, check=True)
    venv_python = venv / "bin" / "python"
    subprocess.run(
        [str(venv_python), "-m", "pip", "install", "--quiet", "--disable-pip-version-check",
         "--only-binary", ":all:", str(wheel)],
        env=environ, cwd=workdir, check=True,
    )  # fmt: skip
    installed = time.perf_counter()
    checked = subprocess.run(
        [str(venv_python), str(Path(__file__).resolve()), "--installed", version],
        env=environ, cwd=workdir, capture_output=True, text=True,
    )  # fmt: skip
    if checked.returncode != 0:
        raise RuntimeError(
            f"the wheel installed for {python} failed its checks:\n{checked.stdout}{checked.stderr}"
        )
    done = time.perf_counter()
    return (
        f"{checked.stdout.rstrip()}\n  venv and install {installed - started:.1f} s, "
        f"checks {done - installed:.1f} s"
    )


def check_installed(version: str) -> None:
    """The checks inside the fresh environment: the installed package, not the repository's;
    no Rust tool reachable; its version; ``check_env`` on every id in both action modes; the
    benchmark with a random policy on every id."""
    from importlib.metadata import version as installed_version

    import gymnasium as gym
    import numpy as np
    from gymnasium.utils.env_checker import check_env

    import tactile_search
    from tactile_search.benchmark import evaluate
    from tactile_search.envs.config import ACTION_MODES
    from tactile_search.seed_ranges import held_out_seeds

    site = Path(sys.prefix).resolve()
    assert site in Path(tactile_search.__file__).resolve().parents, tactile_search.__file__
    reachable = {tool: shutil.which(tool) for tool in RUST_TOOLS}
    assert not any(reachable.values()), f"a Rust tool is on PATH: {reachable}"
    assert tactile_search.__version__ == installed_version("tactile_search") == version, (
        tactile_search.__version__,
        installed_version("tactile_search"),
        version,
    )
    print(
        f"python {'.'.join(map(str, sys.version_info[:3]))}: tactile_search "
        f"{tactile_search.__version__} from {site}, numpy {np.__version__}, "
        f"gymnasium {gym.__version__}"
    )
    for env_id in tactile_search.ENV_IDS:
        for action_mode in ACTION_MODES:
            check_env(gym.make(env_id, action_mode=action_mode).unwrapped)
        action_space = gym.make(env_id).action_space
        action_space.seed(0)
        result = evaluate(
            lambda _observation, space=action_space: space.sample(),
            episodes=EPISODES,
            env_id=env_id,
            progress=False,
        )
        seeds = [row["seed"] for row in result.rows]
        assert result.summary.episodes == EPISODES, result.summary
        assert seeds == list(held_out_seeds("validation", EPISODES)), seeds
        assert all(np.isfinite(row["reward"]) for row in result.rows), result.rows
        print(f"  {env_id}: check_env ({', '.join(ACTION_MODES)}) and {EPISODES} episodes ok")


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("wheel", nargs="?", type=Path, help="default: the one in dist/")
    parser.add_argument("--workdir", type=Path, help="where the venvs go (default: a temp dir)")
    parser.add_argument(
        "--python", action="append", default=None, help="check only these interpreters"
    )
    parser.add_argument("--installed", metavar="VERSION", help=argparse.SUPPRESS)
    args = parser.parse_args(argv)
    if args.installed:
        check_installed(args.installed)
        return 0
    from packaging.specifiers import SpecifierSet

    started = time.perf_counter()
    wheel = (args.wheel or the_wheel()).resolve()
    version, requires_python = wheel_metadata(wheel)
    if args.python:
        chosen = [(p, described(Path(shutil.which(p) or p))) for p in args.python]
        unusable = [name for name, python in chosen if python is None]
        if unusable:
            raise ValueError(f"--python expects CPythons that can make a venv, got {unusable}")
        found = dict(python for _, python in chosen if python is not None)
    else:
        found = interpreters()
    admitted = SpecifierSet(requires_python)
    pythons = [python for v, python in found.items() if admitted.contains(".".join(map(str, v)))]
    if not pythons:
        raise SystemExit(
            f"no Python among {[str(p) for p in found.values()]} is admitted by the wheel's "
            f"Requires-Python {requires_python!r}"
        )
    print(f"{wheel.name} (Requires-Python {requires_python}) on {[str(p) for p in pythons]}")
    with tempfile.TemporaryDirectory(prefix="wheel-check-") as scratch:
        workdir = (args.workdir or Path(scratch)).resolve()
        workdir.mkdir(parents=True, exist_ok=True)
        for python in pythons:
            print(check_with(python, wheel, workdir, version), flush=True)
    print(f"the wheel passed on {len(pythons)} Pythons in {time.perf_counter() - started:.0f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
