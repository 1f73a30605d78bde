"""RLlib's PPO (new API stack) on ``CupboardSearch-v0``: an example, under the small CLI
``python -m agents.rllib_ppo``.

::

    python -m agents.rllib_ppo --map gpis --env-runners 2 --envs-per-runner 4 --iterations 5
    python -m agents.rllib_ppo --map none --grid-shape 36 72 --setting max_steps=64
    RAY_ADDRESS=HEAD:6379 python -m agents.rllib_ppo --map gpis --out runs/rllib_gpis

Each env runner (one CPU) steps one ``CupboardSearchVectorEnv`` of ``--envs-per-runner``
episodes on one Rust thread (``agents.rllib.env``: training layouts, seeded per runner); the
policy is ``agents.rllib.module.CupboardSearchRLModule``; the learner runs on the driver.
The env settings and PPO's numbers follow the SB3 recipe (``agents/hyperparams/ppo.yml``:
approach shaping, lr, gamma, GAE lambda, clip, epochs, minibatch, log-std -1; no KL loss).
A training batch is one round of fragments: runners x envs x ``--fragment`` env steps.

Ray: ``--address`` or ``RAY_ADDRESS`` names a running cluster (``ray start --head`` on the
head node, ``ray start --address=HEAD:6379`` on the others); with neither, a fresh Ray
starts on this machine (``agents.grid.ray_session.connect``, which also ships ``agents`` to the
workers). ``tactile_search`` itself (a compiled extension) must be installed on every node.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Mapping
from pathlib import Path
from typing import Any

from agents.grid.ray_session import connect
from agents.rllib.env import ENV_NAME, register
from agents.sb3.recipes import load_hyperparams, schedule
from tactile_search._validation import as_count
from tactile_search.envs.config import MAP_MODES

#: SB3 recipe key -> RLlib PPO ``training()`` argument.
RECIPE_TO_RLLIB = {
    "learning_rate": "lr",
    "gamma": "gamma",
    "gae_lambda": "lambda_",
    "clip_range": "clip_param",
    "ent_coef": "entropy_coeff",
    "n_epochs": "num_epochs",
    "batch_size": "minibatch_size",
}


#: The per-iteration figures ``train_rllib`` returns (one dict per iteration).
FIGURES = (
    "iteration",
    "env_steps",
    "env_steps_lifetime",
    "episodes",
    "episodes_lifetime",
    "episode_return_mean",
    "seconds",
    "steps_per_second",
)


def recipe(map_mode: str) -> tuple[dict[str, Any], dict[str, Any], float]:
    """The SB3 PPO recipe for ``map_mode`` as (env settings, RLlib ``training()``
    arguments, initial log-std): the recipe's action mode (``probe``; the module has a
    categorical head per probe index; ``settings={"action_mode": "wrist"}`` trains its
    Gaussian over wrist motions instead)."""
    if map_mode not in MAP_MODES:
        raise ValueError(f"map must be one of {MAP_MODES}, got {map_mode!r}")
    hyper = load_hyperparams("ppo", map_mode)
    training = {RECIPE_TO_RLLIB[k]: v for k, v in hyper.items() if k in RECIPE_TO_RLLIB}
    if isinstance(hyper.get("learning_rate"), str):
        # rl-zoo3's lin_<value>, linear to 0 over the recipe's timesteps: RLlib's
        # piecewise schedule of [timestep, rate] pairs.
        start = schedule("learning_rate", hyper["learning_rate"])(1.0)
        training["lr"] = [[0, start], [int(hyper["n_timesteps"]), 0.0]]
    if isinstance(hyper.get("clip_range"), str):
        raise ValueError("RLlib's clip_param takes no schedule: give the recipe a number")
    log_std_init = float(hyper.get("policy_kwargs", {}).get("log_std_init", -1.0))
    return dict(hyper["env_kwargs"]), training, log_std_init


def build_config(
    *,
    map_mode: str = "gpis",
    env_runners: int = 2,
    envs_per_runner: int = 4,
    fragment: int = 128,
    seed: int | None = 0,
    settings: Mapping[str, Any] | None = None,
    training: Mapping[str, Any] | None = None,
    model_config: Mapping[str, Any] | None = None,
) -> Any:
    """The ``PPOConfig``: the recipe for ``map_mode``, updated by ``settings`` (env) and
    ``training`` (``PPOConfig.training`` arguments); one batch is one round of fragments."""
    import gymnasium as gym
    from ray.rllib.algorithms.ppo import PPOConfig
    from ray.rllib.core.rl_module.rl_module import RLModuleSpec

    from agents.rllib.module import CupboardSearchRLModule

    if isinstance(env_runners, bool) or not isinstance(env_runners, int):
        raise TypeError(f"env_runners must be an int, got {type(env_runners).__name__}")
    if env_runners < 0:
        raise ValueError(f"env_runners must be >= 0 (0: sample on the driver), got {env_runners}")
    as_count("envs_per_runner", envs_per_runner)
    as_count("fragment", fragment)
    if seed is not None and (isinstance(seed, bool) or not isinstance(seed, int)):
        raise TypeError(f"seed must be an int or None, got {type(seed).__name__}: {seed!r}")
    if seed is not None and seed < 0:
        raise ValueError(f"seed must be >= 0, got {seed}")
    if settings is not None and not isinstance(settings, Mapping):
        raise TypeError(f"settings must be a mapping, got {type(settings).__name__}")
    env_config, ppo, log_std_init = recipe(map_mode)
    env_config.update(settings or {})
    if env_config.get("map", map_mode) != map_mode:
        raise ValueError(f"settings give map={env_config['map']!r} but map_mode is {map_mode!r}")
    batch = max(env_runners, 1) * envs_per_runner * fragment
    ppo.update(
        train_batch_size_per_learner=batch,
        use_kl_loss=False,  # SB3's PPO has none
        vf_loss_coeff=0.5,
        grad_clip=0.5,
    )
    ppo["minibatch_size"] = min(ppo.get("minibatch_size", 256), batch)
    ppo.update(training or {})
    return (
        PPOConfig()
        .api_stack(enable_rl_module_and_learner=True, enable_env_runner_and_connector_v2=True)
        .environment(ENV_NAME, env_config=env_config)
        .env_runners(
            num_env_runners=env_runners,
            num_envs_per_env_runner=envs_per_runner,
            gym_env_vectorize_mode=gym.VectorizeMode.VECTOR_ENTRY_POINT,
            num_cpus_per_env_runner=1,
            rollout_fragment_length=fragment,
        )
        .learners(num_learners=0, num_gpus_per_learner=0)
        .rl_module(
            rl_module_spec=RLModuleSpec(
                module_class=CupboardSearchRLModule,
                model_config={"log_std_init": log_std_init, **(model_config or {})},
            )
        )
        .training(**ppo)
        .debugging(seed=seed)
    )


def figures(iteration: int, result: Mapping[str, Any], seconds: float) -> dict[str, Any]:
    """The per-iteration figures (``FIGURES``) of one ``algo.train()`` result."""
    runners = result.get("env_runners", {})
    steps = int(runners.get("num_env_steps_sampled", 0))
    return {
        "iteration": iteration,
        "env_steps": steps,
        "env_steps_lifetime": int(runners.get("num_env_steps_sampled_lifetime", 0)),
        "episodes": int(runners.get("num_episodes", 0)),
        "episodes_lifetime": int(runners.get("num_episodes_lifetime", 0)),
        "episode_return_mean": float(runners.get("episode_return_mean", math.nan)),
        "seconds": seconds,
        "steps_per_second": steps / seconds if seconds > 0 else math.nan,
    }


def print_figures(row: Mapping[str, Any]) -> None:
    """One line per iteration; ``-`` for the mean return before any episode has ended."""
    ret = row["episode_return_mean"]
    print(
        f"iter {row['iteration']:3d}  env steps {row['env_steps_lifetime']:8d}  "
        f"episodes {row['episodes_lifetime']:6d}  "
        f"return {'-' if math.isnan(ret) else f'{ret:8.3f}':>8}  "
        f"{row['seconds']:6.1f} s  {row['steps_per_second']:7.0f} steps/s",
        flush=True,
    )


def train_rllib(
    *,
    iterations: int = 5,
    address: str | None = None,
    out: str | Path | None = None,
    report: Callable[[dict[str, Any]], None] | None = print_figures,
    num_cpus: int | None = None,
    **config: Any,
) -> list[dict[str, Any]]:
    """Trains PPO for ``iterations`` and returns the per-iteration figures (``FIGURES``).

    ``env_steps`` counts the steps sampled in the iteration (RLlib does not count an
    autoreset step, and a runner stops at the first vector step that reaches its quota, so
    it can exceed runners x envs x fragment by up to envs - 1 per runner);
    ``episode_return_mean`` is RLlib's mean over its window of recent episodes (100),
    carried over iterations in which none ended, NaN until the first ends.

    Args:
        iterations: ``algo.train()`` calls.
        address: the Ray cluster (else ``RAY_ADDRESS``, else a fresh Ray here:
            ``agents.grid.ray_session.connect``); unused when Ray is already initialised (then
            it is left running).
        out: a directory to save the algorithm to at the end (``algo.save_to_path``).
        report: called with each iteration's figures (default: print a line).
        num_cpus: the CPUs of a fresh local Ray (default: every core).
        **config: ``build_config``'s arguments.
    """
    import ray

    as_count("iterations", iterations)
    started = connect(address, num_cpus)
    register()
    algo = build_config(**config).build_algo()
    rows: list[dict[str, Any]] = []
    try:
        for iteration in range(1, iterations + 1):
            start = time.perf_counter()
            result = algo.train()
            row = figures(iteration, result, time.perf_counter() - start)
            # RLlib reports the windowed mean return only in iterations in which episodes
            # ended: carry the last one over the others (NaN until the first ends).
            if math.isnan(row["episode_return_mean"]) and rows:
                row["episode_return_mean"] = rows[-1]["episode_return_mean"]
            rows.append(row)
            if report is not None:
                report(rows[-1])
        if out is not None:
            path = algo.save_to_path(Path(out).resolve())
            print(f"saved to {path}", flush=True)
    finally:
        algo.stop()
        if started:
            ray.shutdown()
    return rows
