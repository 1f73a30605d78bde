"""A tiny training run from a changed copy of a documented recipe, for the tests that check
what a recipe's settings reach (the evaluation's env, the policy's encoder); and the recipe's
clone stage at a size of seconds, for the grid's tests."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import yaml

from agents.imitation.clone_stage import train_with_clone_stage
from agents.sb3.recipes import HYPERPARAMS_DIR
from agents.sb3.training import TrainSettings
from tactile_search import ENV_ID

# The PPO recipe's clone stage at a size of seconds (an imitation section's overrides).
SMALL_IMITATION = {
    "demo_episodes": 12,
    "dagger_rounds": 1,
    "dagger_episodes": 4,
    "dagger_epochs": 1,
    "cloning": {"epochs": 2},
}


def train_with_recipe(
    tmp_path: Path,
    map_mode: str,
    train_kwargs: dict[str, Any] | None = None,
    imitation_overrides: dict[str, Any] | None = None,
    **changes: Any,
) -> Path:
    """Trains PPO for 64 steps on 2 envs with ``agents/hyperparams/ppo.yml``'s recipe for
    ``map_mode``, its keys replaced by ``changes`` (``train_kwargs`` go to ``TrainSettings``,
    ``imitation_overrides`` to the clone stage); returns the run directory. The recipe's
    ``imitation`` section (minutes of cloning the planner first) is left out unless
    ``changes`` give one (then the run clones first, as ``agents.train`` does)."""
    recipe = yaml.safe_load((HYPERPARAMS_DIR / "ppo.yml").read_text())[ENV_ID][map_mode]
    recipe.pop("imitation", None)
    recipe.update(changes)
    tmp_path.mkdir(parents=True, exist_ok=True)
    path = tmp_path / "ppo.yml"
    path.write_text(yaml.safe_dump({ENV_ID: {map_mode: recipe}}))
    settings = TrainSettings(
        "ppo",
        map_mode,
        out=tmp_path / "runs",
        timesteps=64,
        n_envs=2,
        torch_threads=1,
        hyperparams=path,
        progress_bar=False,
        **(train_kwargs or {}),
    )
    return train_with_clone_stage(settings, imitation_overrides)
