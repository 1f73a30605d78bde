"""Both Gymnasium lines: ``make test`` runs on the version Ray pins; here the package alone,
installed with the newest gymnasium the registry has, passes ``check_env`` in every map and
action mode, the vector equivalence test (``test_vector_equivalence.py``) and Gymnasium's
time-limit conventions (``test_gymnasium_conventions.py``: the env reads ``make``'s arguments,
gymnasium's own code), each run against the installed package."""

from __future__ import annotations

import shutil
import subprocess
from pathlib import Path

from tests.fresh_install import ROOT, fresh_install

CHECK = """
import gymnasium as gym
from gymnasium.utils.env_checker import check_env

import tactile_search
from tactile_search.envs.config import ACTION_MODES, MAP_MODES

for mode in MAP_MODES:
    for action_mode in ACTION_MODES:
        check_env(gym.make(tactile_search.ENV_ID, map=mode, action_mode=action_mode).unwrapped)
print("gymnasium", gym.__version__, "check_env ok")
"""


def test_the_package_with_the_newest_gymnasium_passes_check_env_equivalence_and_conventions(
    tmp_path: Path,
) -> None:
    python = fresh_install(tmp_path, "--upgrade", "gymnasium", "pytest")
    checked = subprocess.run(
        [str(python), "-c", CHECK], cwd=tmp_path, capture_output=True, text=True, timeout=600
    )
    assert checked.returncode == 0, checked.stdout + checked.stderr
    print(checked.stdout.strip())  # the version tested, in pytest's -s / -rA output
    # The tests from a directory of their own, so they import the installed wheel.
    tests = tmp_path / "equivalence"
    tests.mkdir()
    for name in ("test_vector_equivalence.py", "test_gymnasium_conventions.py"):
        shutil.copy(ROOT / "tests" / name, tests)
    equivalence = subprocess.run(
        [str(python), "-m", "pytest", "-q", "-p", "no:cacheprovider", str(tests)],
        cwd=tests, capture_output=True, text=True, timeout=1200,
    )  # fmt: skip
    assert equivalence.returncode == 0, equivalence.stdout[-4000:] + equivalence.stderr[-2000:]
