"""rl-baselines3-zoo reads the training recipes: one config per recipe in
``agents/hyperparams/zoo/`` (``agents/sb3/zoo.py``), in rl-zoo3's format, and rl-zoo3 trains
from it as it is."""

from __future__ import annotations

import ast
import runpy
import subprocess
import sys
from pathlib import Path
from typing import Any

import pytest
import yaml

pytest.importorskip("stable_baselines3")

from agents.sb3.recipes import HYPERPARAMS_DIR, RUN_KEYS
from agents.sb3.zoo import ZOO_RUN_KEYS
from tactile_search import ENV_ID

ROOT = Path(__file__).resolve().parents[1]
ZOO_DIR = HYPERPARAMS_DIR / "zoo"


def recipes() -> list[tuple[str, str]]:
    """Every (algo, map mode) the YAML recipes hold."""
    found = []
    for path in sorted(HYPERPARAMS_DIR.glob("*.yml")):
        found += [(path.stem, mode) for mode in yaml.safe_load(path.read_text())[ENV_ID]]
    return found


def test_every_recipe_has_its_zoo_config_and_no_other() -> None:
    expected = {f"{algo}_{mode}.py" for algo, mode in recipes()}
    assert {path.name for path in ZOO_DIR.glob("*.py")} == expected


@pytest.mark.parametrize(("algo", "mode"), recipes())
def test_a_zoo_config_is_in_rl_zoo3s_format(algo: str, mode: str) -> None:
    hyperparams = runpy.run_path(str(ZOO_DIR / f"{algo}_{mode}.py"))["hyperparams"]
    assert list(hyperparams) == [ENV_ID]
    config = hyperparams[ENV_ID]
    assert config["env_kwargs"]["map"] == mode
    project_only = set(RUN_KEYS) - set(ZOO_RUN_KEYS)  # max_minutes, deterministic_evaluation
    assert not project_only & set(config)
    module = ast.get_docstring(ast.parse((ZOO_DIR / f"{algo}_{mode}.py").read_text()))
    assert "--stochastic" in module  # the advice to evaluate sampled
    extractor = config.get("policy_kwargs", {}).get("features_extractor_class")
    assert extractor is None or isinstance(extractor, type)  # a class, as rl-zoo3 passes it


def plain(value: Any, path: str = "config") -> Any:
    """``value`` with each class replaced by its dotted name (the one thing a Python config
    holds on purpose that YAML's safe dumper refuses), after asserting that every number in
    it, through dicts, lists and tuples, is a plain ``int``/``float``/``bool``."""
    if isinstance(value, dict):
        return {key: plain(item, f"{path}.{key}") for key, item in value.items()}
    if isinstance(value, (list, tuple)):
        return [plain(item, f"{path}[{index}]") for index, item in enumerate(value)]
    if isinstance(value, type):
        return f"{value.__module__}.{value.__qualname__}"
    assert type(value) in (int, float, bool, str, type(None)), (path, type(value))
    return value


@pytest.mark.parametrize(("algo", "mode"), recipes())
def test_a_zoo_config_holds_plain_python_numbers(algo: str, mode: str) -> None:
    """No numpy scalars (``np.float64(...)``): rl-zoo3 prints the config and writes it to
    the run's ``config.yml`` with ``yaml.dump``, where a numpy scalar becomes a
    numpy object tag; the spatial policy's probe points were ones."""
    hyperparams = runpy.run_path(str(ZOO_DIR / f"{algo}_{mode}.py"))["hyperparams"]
    yaml.safe_load(yaml.safe_dump(plain(hyperparams)))
    assert "numpy" not in yaml.dump(hyperparams)  # as rl-zoo3's config.yml writes it
    assert "np." not in repr(hyperparams)  # as rl-zoo3 prints it


def test_rl_zoo3_trains_from_a_config_as_it_is(tmp_path: Path) -> None:
    pytest.importorskip("rl_zoo3")
    result = subprocess.run(
        [sys.executable, "-m", "rl_zoo3.train", "--algo", "ppo", "--env", ENV_ID,
         "--gym-packages", "tactile_search", "-conf", "agents/hyperparams/zoo/ppo_gpis.py",
         "-n", "32", "--hyperparams", "n_envs:2", "n_steps:16", "batch_size:32", "n_epochs:1",
         "--eval-freq", "-1", "-f", str(tmp_path), "--seed", "0", "--log-interval", "-1",
         "--device", "cpu"],
        cwd=ROOT, capture_output=True, text=True, timeout=600,
    )  # fmt: skip
    assert result.returncode == 0, result.stdout[-3000:] + result.stderr[-3000:]
    (model,) = tmp_path.glob("ppo/*/*.zip")
    assert model.stat().st_size > 0
    assert "np.float64" not in result.stdout  # rl-zoo3 prints the config it read
    (config,) = tmp_path.glob("ppo/*/*/config.yml")
    assert "numpy" not in config.read_text()
