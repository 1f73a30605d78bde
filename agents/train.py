"""Train a stable-baselines3 agent on ``tactile_search/CupboardSearch-v0``.

Importable functions under a thin CLI (the rl-baselines3-zoo layout)::

    python -m agents.train --algo ppo --map gpis --seed 0 --out runs
    python -m agents.train --algo recurrent_ppo --map none --timesteps 200000

Hyperparameters come from ``agents/hyperparams/<algo>.yml``, keyed by env id and map mode.
Each run writes into ``<out>/<algo>_<map>_seed<seed>/``: ``model.zip``, ``config.yml`` (the
resolved recipe, the command's arguments, package versions and the wall-clock time),
``progress.csv`` and TensorBoard events. Training runs on ``CupboardSearchSb3VecEnv`` (the
Rust batch, both cores) and draws layout seeds from ``TRAIN_LAYOUT_SEEDS``, a range disjoint
from the held-out evaluation seeds of ``agents/evaluate.py``.
"""

from __future__ import annotations

import argparse
import copy
import os
import platform
import time
from pathlib import Path
from typing import Any

import gymnasium as gym
import yaml

import tactile_search
from tactile_search.envs.config import MAP_MODES

# Torch's OpenMP threads busy-wait between parallel regions by default; on this 2-core
# machine they then fight the environment batch's worker threads (and other jobs) for the
# cores. Passive waiting, set before torch loads its OpenMP runtime, measured: PPO with the
# GPIS recipe on the Rust batch 417 vs ~100 steps/s (torch threads 2), and 0.81 instead of
# 0.52 of the speed on a zero-cost VecEnv (`python -m benchmarks.ppo_env_overhead`). A value
# the user set is kept.
os.environ.setdefault("OMP_WAIT_POLICY", "PASSIVE")

ENV_ID = "tactile_search/CupboardSearch-v0"
HYPERPARAMS_DIR = Path(__file__).parent / "hyperparams"
ALGORITHMS = ("ppo", "recurrent_ppo")
# Training layouts are drawn from [2**32, 2**63); evaluation holds out seeds below 2**32.
TRAIN_LAYOUT_SEEDS = (2**32, 2**63)
# Recipe keys that configure the run rather than the algorithm.
RUN_KEYS = ("n_timesteps", "max_minutes", "n_envs", "policy", "env_kwargs")


def algorithm_class(algo: str) -> type:
    """The SB3 class of ``algo`` (``ppo`` or ``recurrent_ppo``)."""
    if algo == "ppo":
        from stable_baselines3 import PPO

        return PPO
    if algo == "recurrent_ppo":
        from sb3_contrib import RecurrentPPO

        return RecurrentPPO
    raise ValueError(f"algo must be one of {ALGORITHMS}, got {algo!r}")


def load_hyperparams(
    algo: str, map_mode: str, env_id: str = ENV_ID, path: Path | None = None
) -> dict[str, Any]:
    """The recipe for ``algo`` on ``env_id`` with ``map_mode`` from its YAML file."""
    if algo not in ALGORITHMS:
        raise ValueError(f"algo must be one of {ALGORITHMS}, got {algo!r}")
    path = path or HYPERPARAMS_DIR / f"{algo}.yml"
    recipes = yaml.safe_load(path.read_text())
    if env_id not in recipes:
        raise ValueError(f"{path} has no recipe for env id {env_id!r}; it has {sorted(recipes)}")
    by_map = recipes[env_id]
    if map_mode not in by_map:
        raise ValueError(
            f"{path} has no {env_id!r} recipe for map {map_mode!r}; it has {sorted(by_map)}"
        )
    recipe = copy.deepcopy(by_map[map_mode])
    recipe.setdefault("env_kwargs", {})["map"] = map_mode
    return recipe


def make_training_env(
    env_kwargs: dict[str, Any], n_envs: int, seed: int, env_id: str = ENV_ID
) -> Any:
    """The SB3 vector env for training: the Rust batch, monitored for episode statistics."""
    from stable_baselines3.common.vec_env import VecMonitor

    from tactile_search.envs.sb3_vec_env import CupboardSearchSb3VecEnv

    # The time limit is the env's own `max_steps` (in env_kwargs or the core's default).
    venv = CupboardSearchSb3VecEnv(
        num_envs=n_envs,
        seed=seed,
        layout_seeds=TRAIN_LAYOUT_SEEDS,
        **env_kwargs,
    )
    return VecMonitor(venv, info_keywords=("success", "tips", "jar_displacement", "iou"))


def run_name(algo: str, map_mode: str, seed: int) -> str:
    """The run directory's name."""
    return f"{algo}_{map_mode}_seed{seed}"


def versions() -> dict[str, str]:
    """Versions of what produced a run."""
    import stable_baselines3
    import torch

    return {
        "tactile_search": tactile_search.__version__,
        "stable_baselines3": stable_baselines3.__version__,
        "torch": str(torch.__version__),
        "gymnasium": gym.__version__,
        "python": platform.python_version(),
    }


def wall_clock_limit(minutes: float) -> Any:
    """An SB3 callback that stops training once ``minutes`` of wall-clock time have passed
    (checked after every step; the model is then saved as usual)."""
    from stable_baselines3.common.callbacks import BaseCallback

    class StopAfter(BaseCallback):
        def _on_training_start(self) -> None:
            self.deadline = time.perf_counter() + 60.0 * minutes

        def _on_step(self) -> bool:
            return time.perf_counter() < self.deadline

    return StopAfter()


def train(
    algo: str,
    map_mode: str,
    *,
    out: Path = Path("runs"),
    seed: int = 0,
    timesteps: int | None = None,
    n_envs: int | None = None,
    torch_threads: int = 2,
    progress_bar: bool = True,
    env_id: str = ENV_ID,
    hyperparams: Path | None = None,
    max_minutes: float | None = None,
) -> Path:
    """Trains one agent and returns its run directory (``model.zip``, ``config.yml``, logs).

    ``timesteps`` and ``n_envs`` override the recipe's ``n_timesteps`` and ``n_envs``;
    ``max_minutes`` (or the recipe's ``max_minutes``) stops training earlier on wall-clock
    time, and ``config.yml`` records the timesteps done.
    ``torch_threads`` sets torch's intra-op threads. On this 2-core machine, training alone,
    2 threads ran PPO with the GPIS map 1.38x faster than 1 (median 1148 vs 832 steps/s,
    ``python benchmarks/train_threads.py --timesteps 8192 --repeats 2``); use 1 when two
    runs share the cores.
    """
    if map_mode not in MAP_MODES:
        raise ValueError(f"map must be one of {MAP_MODES}, got {map_mode!r}")
    if not isinstance(seed, int) or seed < 0:
        raise ValueError(f"seed must be a non-negative int, got {seed!r}")
    if timesteps is not None and timesteps < 1:
        raise ValueError(f"timesteps must be >= 1, got {timesteps}")
    if torch_threads < 1:
        raise ValueError(f"torch_threads must be >= 1, got {torch_threads}")
    if max_minutes is not None and not max_minutes > 0:
        raise ValueError(f"max_minutes must be > 0, got {max_minutes}")
    import torch
    from stable_baselines3.common.logger import configure
    from stable_baselines3.common.utils import set_random_seed

    recipe = load_hyperparams(algo, map_mode, env_id, hyperparams)
    if timesteps is not None:
        recipe["n_timesteps"] = int(timesteps)
    if n_envs is not None:
        recipe["n_envs"] = int(n_envs)
    if max_minutes is not None:
        recipe["max_minutes"] = float(max_minutes)
    run_dir = Path(out) / run_name(algo, map_mode, seed)
    run_dir.mkdir(parents=True, exist_ok=True)
    config = {
        "algo": algo,
        "env_id": env_id,
        "map": map_mode,
        "seed": seed,
        "torch_threads": torch_threads,
        "train_layout_seeds": list(TRAIN_LAYOUT_SEEDS),
        "hyperparams": recipe,
        "versions": versions(),
    }
    config_path = run_dir / "config.yml"
    config_path.write_text(yaml.safe_dump(config, sort_keys=False))

    torch.set_num_threads(torch_threads)
    set_random_seed(seed)
    env = make_training_env(recipe["env_kwargs"], recipe["n_envs"], seed, env_id)
    algo_kwargs = {k: v for k, v in recipe.items() if k not in RUN_KEYS}
    model = algorithm_class(algo)(recipe["policy"], env, seed=seed, device="cpu", **algo_kwargs)
    model.set_logger(configure(str(run_dir), ["csv", "tensorboard"]))
    started = time.perf_counter()
    limit = recipe.get("max_minutes")
    model.learn(
        total_timesteps=recipe["n_timesteps"],
        callback=None if limit is None else wall_clock_limit(limit),
        progress_bar=progress_bar,
    )
    config["wall_clock_seconds"] = round(time.perf_counter() - started, 1)
    config["timesteps_done"] = int(model.num_timesteps)
    model.save(run_dir / "model.zip")
    config_path.write_text(yaml.safe_dump(config, sort_keys=False))
    env.close()
    return run_dir


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--algo", choices=ALGORITHMS, default="ppo")
    parser.add_argument("--map", choices=MAP_MODES, default="gpis", dest="map_mode")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--timesteps", type=int, help="override the recipe's n_timesteps")
    parser.add_argument("--n-envs", type=int, help="override the recipe's n_envs")
    parser.add_argument("--max-minutes", type=float, help="stop after this much wall-clock")
    parser.add_argument("--torch-threads", type=int, default=2)
    parser.add_argument("--out", type=Path, default=Path("runs"))
    parser.add_argument("--hyperparams", type=Path, help="a recipe file instead of the default")
    parser.add_argument("--no-progress", action="store_true", help="no progress bar")
    args = parser.parse_args(argv)
    run_dir = train(
        args.algo,
        args.map_mode,
        out=args.out,
        seed=args.seed,
        timesteps=args.timesteps,
        n_envs=args.n_envs,
        torch_threads=args.torch_threads,
        progress_bar=not args.no_progress,
        hyperparams=args.hyperparams,
        max_minutes=args.max_minutes,
    )
    print(f"trained {run_dir}")


if __name__ == "__main__":
    main()
