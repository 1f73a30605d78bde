"""A clean install works as installed: the wheel maturin builds, installed into a fresh
virtual environment with only its dependencies (numpy, gymnasium: no extras, no
matplotlib), passes gymnasium's ``check_env`` (render check included), runs a rollout, and
renders as gymnasium's convention says: without a render mode a warning and None; in
``rgb_array`` an RGB array drawn with numpy alone. Writing a GIF, which needs the ``plots``
extra, raises an ImportError naming it, and so do the published agents' networks (the
``agents`` extra). The benchmark API runs there too."""

from __future__ import annotations

import subprocess
from pathlib import Path

from tests.fresh_install import fresh_install

# Runs inside the fresh environment, from a directory outside the repository.
CHECK = """
import importlib.util
import warnings

import gymnasium as gym
import numpy as np
from gymnasium.utils.env_checker import check_env

import tactile_search

assert importlib.util.find_spec("matplotlib") is None, "matplotlib leaked into the clean env"
assert "site-packages" in tactile_search.__file__, tactile_search.__file__

env = gym.make("tactile_search/CupboardSearch-v0")
check_env(env.unwrapped)
observation, info = env.reset(seed=1_000_000)
env.action_space.seed(0)
for _ in range(30):
    observation, reward, terminated, truncated, info = env.step(env.action_space.sample())
    assert np.isfinite(reward) and observation["map"].dtype == np.uint8
    if terminated or truncated:
        observation, info = env.reset()
with warnings.catch_warnings(record=True) as caught:
    warnings.simplefilter("always")
    assert env.unwrapped.render() is None
assert any("render mode" in str(w.message) for w in caught), [str(w.message) for w in caught]

drawing = gym.make("tactile_search/CupboardSearch-v0", render_mode="rgb_array")
drawing.reset(seed=1)
frame = drawing.render()
assert frame.dtype == np.uint8 and frame.ndim == 3 and frame.shape[2] == 3, frame.shape
from tactile_search.render import save_gif

try:
    save_gif([frame], "episode.gif")
except ImportError as error:
    assert "tactile_search[plots]" in str(error), error
else:
    raise AssertionError("a GIF was written without matplotlib")

from tactile_search.benchmark import evaluate  # installed, numpy and gymnasium only

result = evaluate(lambda observation: np.zeros(3, np.float32), episodes=2, map="none")
assert result.summary.episodes == 2 and [r["seed"] for r in result.rows] == [1_000_000, 1_000_001]
try:
    import tactile_search.networks.spatial_probe  # the published agents' networks: torch, SB3
except ModuleNotFoundError as error:
    assert "tactile_search[agents]" in str(error), error
else:
    raise AssertionError("the networks imported without torch")
print("clean install ok")
"""


def test_the_wheel_works_in_a_fresh_environment_without_extras(tmp_path: Path) -> None:
    python = fresh_install(tmp_path)
    result = subprocess.run(
        [str(python), "-c", CHECK], cwd=tmp_path, capture_output=True, text=True, timeout=600
    )
    assert result.returncode == 0, result.stdout + result.stderr
    assert "clean install ok" in result.stdout
