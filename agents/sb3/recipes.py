"""The training recipes: ``agents/hyperparams/<algo>.yml``, keyed by env id and map mode,
and the SB3 algorithm and its arguments they name (classes by dotted path)."""

from __future__ import annotations

import copy
from pathlib import Path
from typing import Any

import yaml

from agents.run_dir import ALGORITHMS
from tactile_search import ENV_ID
from tactile_search.networks.recipe_classes import policy_class, policy_kwargs

HYPERPARAMS_DIR = Path(__file__).parents[1] / "hyperparams"


# Recipe keys that configure the run rather than the algorithm.
RUN_KEYS = (
    "n_timesteps",
    "max_minutes",
    "n_envs",
    "policy",
    "env_kwargs",
    "deterministic_evaluation",
    "anchor_weight",
    "anchor_decay_timesteps",
    "imitation",
    "bfloat16_updates",
)


def algorithm_class(algo: str) -> type:
    """The SB3 class of ``algo`` (``ppo`` or ``recurrent_ppo``)."""
    if algo == "ppo":
        from stable_baselines3 import PPO

        return PPO
    if algo == "recurrent_ppo":
        from sb3_contrib import RecurrentPPO

        return RecurrentPPO
    raise ValueError(f"algo must be one of {ALGORITHMS}, got {algo!r}")


def training_class(algo: str, recipe: dict[str, Any]) -> type:
    """The class ``recipe`` trains ``algo`` with: ``algorithm_class(algo)``, its update under
    bfloat16 autocast where the CPU computes bfloat16 natively if the recipe's
    ``bfloat16_updates`` is true (``agents.sb3.bfloat16``)."""
    from agents.sb3.bfloat16 import bfloat16_update_class, learner_precision

    cls = algorithm_class(algo)
    if learner_precision(recipe) == "float32":
        return cls
    return bfloat16_update_class(cls, native=True)


def load_hyperparams(
    algo: str, map_mode: str, env_id: str = ENV_ID, path: Path | None = None
) -> dict[str, Any]:
    """The recipe for ``algo`` on ``env_id`` with ``map_mode`` from its YAML file, its
    ``env_kwargs`` over the id's own settings (``id_settings``)."""
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
    recipe["env_kwargs"] = {**id_settings(env_id), **recipe.get("env_kwargs", {})}
    recipe["env_kwargs"]["map"] = map_mode
    return recipe


def id_settings(env_id: str) -> dict[str, Any]:
    """The settings registered id ``env_id`` makes its env with
    (``gymnasium.spec(env_id).kwargs``: its task and tier), under a recipe's own
    ``env_kwargs``: the envs a run trains, imitates and is evaluated in are the id's. Pairs
    are lists (a run's ``config.yml`` is plain YAML)."""
    import gymnasium

    return {
        key: list(value) if isinstance(value, tuple) else value
        for key, value in gymnasium.spec(env_id).kwargs.items()
    }


def run_recipe(
    algo: str,
    map_mode: str,
    env_id: str = ENV_ID,
    path: Path | None = None,
    *,
    timesteps: int | None = None,
    n_envs: int | None = None,
    max_minutes: float | None = None,
) -> dict[str, Any]:
    """The recipe a fresh run trains and records in its ``config.yml`` (``hyperparams``):
    ``load_hyperparams``' with ``timesteps``, ``n_envs`` and ``max_minutes``, where given,
    over the recipe's ``n_timesteps``, ``n_envs`` and ``max_minutes`` (the imitation
    section as the YAML has it; the run records the section its clone stage ran)."""
    recipe = load_hyperparams(algo, map_mode, env_id, path)
    if timesteps is not None:
        recipe["n_timesteps"] = int(timesteps)
    if n_envs is not None:
        recipe["n_envs"] = int(n_envs)
    if max_minutes is not None:
        recipe["max_minutes"] = float(max_minutes)
    return recipe


#: Arguments a recipe may give as a schedule, rl-baselines3-zoo's ``lin_<value>``: from
#: the value at the start of the run to 0 at its last timestep.
SCHEDULED_KEYS = ("learning_rate", "clip_range")


def schedule(key: str, value: Any) -> Any:
    """``value`` of argument ``key`` as SB3 takes it: a number as it is; rl-zoo3's
    ``"lin_<value>"`` as SB3's linear schedule from that value to 0 over the run (progress
    1 to 0); ``ValueError`` naming the forms for anything else."""
    if not isinstance(value, str):
        return value
    prefix, _, number = value.partition("_")
    try:
        start = float(number)
    except ValueError:
        start = float("nan")
    if prefix != "lin" or not start > 0:
        raise ValueError(
            f"{key} must be a number or 'lin_<value>' (linear from a positive value to 0, "
            f"rl-zoo3's form), got {value!r}"
        )
    from stable_baselines3.common.utils import LinearSchedule

    return LinearSchedule(start=start, end=0.0, end_fraction=1.0)


def algorithm_kwargs(recipe: dict[str, Any], make_schedules: bool = True) -> dict[str, Any]:
    """The recipe's arguments for the SB3 algorithm: every key but ``RUN_KEYS``, with its
    ``policy_kwargs``' classes imported (``tactile_search.networks.recipe_classes``: a
    module that has since moved is read at its new place) and, with ``make_schedules``,
    ``SCHEDULED_KEYS`` given as ``lin_<value>`` made schedules (``schedule``; rl-zoo3 makes
    its own from the strings)."""
    kwargs = {key: value for key, value in recipe.items() if key not in RUN_KEYS}
    for key in SCHEDULED_KEYS:
        if key in kwargs:
            made = schedule(key, kwargs[key])  # checked either way
            if make_schedules:
                kwargs[key] = made
    kwargs.pop("policy_kwargs", None)
    classes = policy_kwargs(recipe)
    if classes:
        kwargs["policy_kwargs"] = classes
    return kwargs


def new_model(cls: type, recipe: dict[str, Any], env: Any, seed: int) -> Any:
    """A fresh ``cls`` model (on the CPU) of ``recipe`` on ``env`` (``policy_class``)."""
    return cls(policy_class(recipe), env, seed=seed, device="cpu", **algorithm_kwargs(recipe))
