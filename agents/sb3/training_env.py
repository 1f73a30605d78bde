"""The vector env a training run steps: the Rust batch as an SB3 ``VecEnv`` drawing layouts
from the training seed range, monitored for episode statistics."""

from __future__ import annotations

from typing import Any

from tactile_search import ENV_ID, seed_ranges

# Training draws its layouts from the protocol's training range, disjoint from the held-out
# ranges the evaluation reads (``tactile_search.seed_ranges``).
TRAIN_LAYOUT_SEEDS = seed_ranges.TRAINING


def make_training_env(
    env_kwargs: dict[str, Any],
    n_envs: int,
    seed: int,
    env_id: str = ENV_ID,
    threads: int | None = None,
) -> Any:
    """The SB3 vector env for training: the Rust batch (``threads`` worker threads, default
    every core), monitored for episode statistics."""
    from stable_baselines3.common.vec_env import VecMonitor

    from tactile_search.envs.sb3_vec_env import CupboardSearchSb3VecEnv

    # The time limit is the env's own `max_steps` (in env_kwargs or the core's default).
    venv = CupboardSearchSb3VecEnv(
        num_envs=n_envs,
        seed=seed,
        layout_seeds=TRAIN_LAYOUT_SEEDS,
        threads=threads,
        **env_kwargs,
    )
    return VecMonitor(venv, info_keywords=("success", "tips", "jar_displacement", "iou"))
