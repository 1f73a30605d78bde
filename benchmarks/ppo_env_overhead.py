"""What the environment costs PPO: the documented GPIS recipe (``agents/hyperparams/ppo.yml``)
on ``CupboardSearchSb3VecEnv`` against the same PPO on a zero-cost ``VecEnv`` with identical
spaces, in one process, alternating rounds of a few thousand steps each, so the shared
machine's noise hits both alike. Prints each round, the median steps/s of each, the ratio
(target: at least 0.85) and the share of wall-clock time spent inside ``step_wait``. On a
shared machine the rounds' speeds swing with other jobs' load; the step_wait share within
the environment's own rounds gives a second, load-robust estimate of the ratio,
1 - share (what training would run at if the environment cost nothing). Run from the repo
root::

    python -m benchmarks.ppo_env_overhead [--steps 2048] [--rounds 6] [--torch-threads 2]

Like ``agents/train.py``, it sets ``OMP_WAIT_POLICY=PASSIVE`` (unless set) before torch
loads, for both PPOs alike; run with ``OMP_WAIT_POLICY=ACTIVE`` to see the busy-waiting
default.
"""

from __future__ import annotations

import os

# Before torch loads (stable_baselines3 imports it): see agents/train.py.
os.environ.setdefault("OMP_WAIT_POLICY", "PASSIVE")

import argparse
import statistics
import time
from typing import Any

import numpy as np
from stable_baselines3.common.vec_env import VecEnv, VecEnvWrapper

from agents.sb3.recipes import algorithm_class, load_hyperparams, new_model
from agents.sb3.training_env import make_training_env


class ZeroCostVecEnv(VecEnv):
    """A ``VecEnv`` with the given spaces whose step costs nothing: zero observations,
    rewards and dones (the ceiling PPO's own cost sets)."""

    def __init__(self, num_envs: int, observation_space: Any, action_space: Any) -> None:
        super().__init__(num_envs, observation_space, action_space)
        self._obs = {
            key: np.zeros((num_envs, *space.shape), space.dtype)
            for key, space in observation_space.spaces.items()
        }
        self._rewards = np.zeros(num_envs, np.float32)
        self._dones = np.zeros(num_envs, bool)

    def reset(self) -> dict[str, np.ndarray]:
        return self._obs

    def step_async(self, actions: np.ndarray) -> None:
        pass

    def step_wait(self) -> tuple:
        return self._obs, self._rewards, self._dones, [{} for _ in range(self.num_envs)]

    def close(self) -> None:
        pass

    def get_attr(self, attr_name: str, indices: Any = None) -> list:
        return [None] * self.num_envs

    def set_attr(self, attr_name: str, value: Any, indices: Any = None) -> None:
        pass

    def env_method(self, method_name: str, *args: Any, indices: Any = None, **kw: Any) -> list:
        return [None] * self.num_envs

    def env_is_wrapped(self, wrapper_class: type, indices: Any = None) -> list[bool]:
        return [False] * self.num_envs


class StepTimer(VecEnvWrapper):
    """Adds up the wall-clock time spent in ``step_wait``."""

    def __init__(self, venv: VecEnv) -> None:
        super().__init__(venv)
        self.seconds = 0.0

    def reset(self) -> Any:
        return self.venv.reset()

    def step_wait(self) -> tuple:
        start = time.perf_counter()
        out = self.venv.step_wait()
        self.seconds += time.perf_counter() - start
        return out


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--steps", type=int, default=2048, help="timesteps per round and env")
    parser.add_argument("--rounds", type=int, default=6)
    parser.add_argument("--torch-threads", type=int, default=2)
    parser.add_argument("--map", default="gpis")
    args = parser.parse_args(argv)
    import torch

    print(f"OMP_WAIT_POLICY={os.environ.get('OMP_WAIT_POLICY')}")
    torch.set_num_threads(args.torch_threads)
    recipe = load_hyperparams("ppo", args.map)
    n_envs = recipe["n_envs"]
    real = StepTimer(make_training_env(recipe["env_kwargs"], n_envs, seed=0))
    zero = StepTimer(ZeroCostVecEnv(n_envs, real.observation_space, real.action_space))
    models = {
        name: new_model(algorithm_class("ppo"), recipe, env, seed=0)
        for name, env in (("environment", real), ("zero-cost", zero))
    }
    rollout = recipe["n_steps"] * n_envs
    for model in models.values():  # warm-up: first rollout and update, excluded
        model.learn(total_timesteps=rollout)
    rates: dict[str, list[float]] = {name: [] for name in models}
    env_share: list[float] = []
    work_share: list[float] = []  # of step_wait: the episodes' own work, GIL released
    batch = getattr(real.unwrapped, "_batch", None)
    print(
        f"PPO {args.map} recipe: {n_envs} envs, {rollout} steps per rollout, "
        f"torch threads {args.torch_threads}; {args.steps} steps per round"
    )
    for round_index in range(args.rounds):
        for name, model in models.items():
            timer = real if name == "environment" else zero
            timer.seconds = 0.0
            done = model.num_timesteps
            inside = getattr(batch, "parallel_seconds", float("nan"))
            start = time.perf_counter()
            model.learn(total_timesteps=args.steps, reset_num_timesteps=False)
            elapsed = time.perf_counter() - start
            rates[name].append((model.num_timesteps - done) / elapsed)
            if name == "environment":
                env_share.append(timer.seconds / elapsed)
                inside = getattr(batch, "parallel_seconds", float("nan")) - inside
                work_share.append(inside / timer.seconds)
            print(f"  round {round_index} {name:>11}: {rates[name][-1]:6.0f} steps/s", flush=True)
    env_rate = statistics.median(rates["environment"])
    zero_rate = statistics.median(rates["zero-cost"])
    share = statistics.median(env_share)
    print(
        f"median steps/s: environment {env_rate:.0f}, zero-cost {zero_rate:.0f}; "
        f"ratio {env_rate / zero_rate:.2f} (target >= 0.85)\n"
        f"step_wait share of the environment's training time {share:.1%}: "
        f"ratio from it {1 - share:.2f}"
    )
    work = statistics.median(work_share)
    if work == work:  # the batch reports its work time (not NaN)
        print(
            f"of step_wait, {work:.0%} is the episodes' own work (physics, touch, GPIS, map "
            f"encoding; GIL released) and {1 - work:.0%} the rest (conversion, copies, infos, "
            f"bookkeeping): with that rest at zero the ratio would be "
            f"{(1 - share) / (1 - share + share * work):.2f}"
        )


if __name__ == "__main__":
    main()
