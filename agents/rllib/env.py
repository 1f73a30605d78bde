"""``CupboardSearch-v0`` as an RLlib environment: the Rust vector env, one per env runner.

``register()`` registers ``make_env`` with Ray Tune under ``ENV_NAME``; select it with
``PPOConfig().environment(ENV_NAME, env_config={...settings...})`` and
``.env_runners(gym_env_vectorize_mode=gymnasium.VectorizeMode.VECTOR_ENTRY_POINT)``. The env
config holds ``CupboardSearchConfig`` settings (``map``, ``max_steps``, ``grid_shape``, ...);
an unknown setting raises the env's ``TypeError``, a bad value its ``TypeError`` or
``ValueError``.

Each env runner then holds one ``CupboardSearchVectorEnv`` with all its
``num_envs_per_env_runner`` episodes, on one Rust worker thread (``threads=1``: a runner
reserves one CPU, so its env must not take more), drawing training layouts only
(``agents.sb3.training_env.TRAIN_LAYOUT_SEEDS``, disjoint from the held-out layouts of
``tactile_search.seed_ranges``).

Seeding contract (vector-entry-point mode):

- The vector env seeds each sub-env as gymnasium's ``SyncVectorEnv`` does (``seed + i``),
  and each sub-env draws its layouts from its own generator. RLlib resets a runner's env
  with ``config.seed + worker_index`` (evaluation runners + 1e6), so runner ``w``'s sub-env
  ``i`` and runner ``w + 1``'s sub-env ``i - 1`` would share a seed and replay the same
  layouts. ``make_env`` therefore wraps the env in ``RunnerSeeds``, which turns the runner's
  seed into ``num_envs`` seeds spread by numpy's ``SeedSequence``: distinct runners' streams
  are independent (two draws coincide with probability about 2**-63). Later resets pass
  no seed. With ``config.seed=None`` the generators are seeded from the OS.
- Every layout is a training layout: a spread seed is in ``TRAIN_LAYOUT_SEEDS`` or seeds
  the draw from it (the vector env's ``layout_seeds`` rule).
- RLlib's offsets are additive, so runs seeded ``s`` and ``s + 1`` share streams between
  runners (run ``s + 1``'s runner ``w`` is run ``s``'s runner ``w + 1``): space independent
  runs' seeds by more than ``num_env_runners + 1``.

The single-env paths (``gym_env_vectorize_mode`` SYNC or ASYNC) are refused with a
``ValueError``. There RLlib builds every sub-env from the same context (``vector_index``
0) and gymnasium seeds sub-env ``i`` with ``seed + i``, so runner ``w``'s env ``i`` and
runner ``w + 1``'s env ``i - 1`` would get the same seed and replay the same layouts. No
index that tells the sub-envs apart reaches the env creator (a per-process counter fails
under ASYNC, where every sub-env is built in its own process), so the overlap cannot be
undone there; and one Rust batch per sub-env is slower than the one batch of the vector env.
RLlib passes ``num_envs`` to the creator only in vector-entry-point mode, so a call without
it is the single-env path.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np
from gymnasium.vector import VectorWrapper

from agents.sb3.training_env import TRAIN_LAYOUT_SEEDS
from tactile_search.envs.vector import CupboardSearchVectorEnv

#: The name ``register()`` gives the env in Ray Tune's registry.
ENV_NAME = "tactile_search-CupboardSearch-rllib-v0"


#: Arguments of the vector env that ``make_env`` sets itself (not settings of the env).
FIXED_KEYS = ("threads", "layout_seeds", "copy")


VECTORIZE_HINT = (
    "build it with config.env_runners(gym_env_vectorize_mode="
    "gymnasium.VectorizeMode.VECTOR_ENTRY_POINT), which passes num_envs"
)


class RunnerSeeds(VectorWrapper):
    """A runner's vector env whose ``reset(seed=s)`` seeds its sub-envs with ``num_envs``
    seeds spread from ``s`` by ``SeedSequence`` instead of ``s + i`` (see the module
    docstring); a list of seeds or None passes through."""

    def reset(self, *, seed: Any = None, options: dict[str, Any] | None = None) -> Any:
        return self.env.reset(seed=spread_seeds(seed, self.num_envs), options=options)


def spread_seeds(seed: Any, count: int) -> Any:
    """``count`` independent seeds from an int ``seed``; anything else unchanged."""
    if isinstance(seed, (int, np.integer)) and not isinstance(seed, bool):
        state = np.random.SeedSequence(int(seed)).generate_state(count, np.uint64)
        return [int(value) for value in state]
    return seed


def make_env(env_config: Mapping[str, Any]) -> RunnerSeeds:
    """The vector env of one env runner from RLlib's env config (see the module docstring).

    Args:
        env_config: an ``EnvContext`` or dict of ``CupboardSearchConfig`` settings, plus
            ``num_envs`` (which RLlib adds in vector-entry-point mode).

    Raises:
        TypeError: ``env_config`` is not a mapping, or a setting is unknown or of the
            wrong type (the env's error).
        ValueError: no ``num_envs`` (the single-env path), a key ``make_env`` fixes itself,
            or a setting out of range (the env's error).
    """
    if not isinstance(env_config, Mapping):
        raise TypeError(
            f"env_config must be a mapping of CupboardSearchConfig settings, "
            f"got {type(env_config).__name__}: {env_config!r}"
        )
    settings = dict(env_config)
    if "num_envs" not in settings:
        raise ValueError(
            f"{ENV_NAME} is a vector env: RLlib's single-env path (SYNC/ASYNC "
            f"gym_env_vectorize_mode) would seed runners' sub-envs with overlapping seeds "
            f"and replay the same layouts; {VECTORIZE_HINT}. Got env_config {settings!r}"
        )
    num_envs = settings.pop("num_envs")
    fixed = sorted(key for key in settings if key in FIXED_KEYS)
    if fixed:
        raise ValueError(
            f"env_config must hold only CupboardSearchConfig settings; {fixed} are set by "
            f"make_env (threads=1, layout_seeds={TRAIN_LAYOUT_SEEDS}, copy=True)"
        )
    return RunnerSeeds(
        CupboardSearchVectorEnv(
            num_envs=num_envs, threads=1, layout_seeds=TRAIN_LAYOUT_SEEDS, **settings
        )
    )


def register() -> str:
    """Registers ``make_env`` with Ray Tune as ``ENV_NAME`` and returns the name."""
    from ray.tune import register_env

    register_env(ENV_NAME, make_env)
    return ENV_NAME
