"""The training recipes: ``agents/hyperparams/<algo>.yml``, keyed by env id and map mode,
and the SB3 algorithm and its arguments they name (classes by dotted path)."""

from __future__ import annotations

import copy
import importlib
from pathlib import Path
from typing import Any

import yaml

from agents.run_dir import ALGORITHMS
from tactile_search import ENV_ID
from tactile_search._validation import as_bool

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
    bfloat16 autocast where the CPU has AMX if the recipe's ``bfloat16_updates`` is true
    (``agents.sb3.bfloat16``)."""
    cls = algorithm_class(algo)
    if not as_bool("bfloat16_updates", recipe.get("bfloat16_updates", False)):
        return cls
    from agents.sb3.bfloat16 import bfloat16_update_class

    return bfloat16_update_class(cls)


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


# A recipe names classes in its policy_kwargs by dotted path (YAML holds no classes).
CLASS_KEYS = ("features_extractor_class", "activation_fn")


# Modules that recipes of earlier runs name and that have moved since, old -> new: the
# published models' config.yml and model.zip name the encoders at ``agents.encoders``.
MOVED_MODULES = {"agents.encoders": "agents.sb3.encoders"}


def algorithm_kwargs(recipe: dict[str, Any]) -> dict[str, Any]:
    """The recipe's arguments for the SB3 algorithm: every key but ``RUN_KEYS``, with the
    classes that ``policy_kwargs`` names by dotted path (``features_extractor_class:
    agents.sb3.encoders.ImpalaMapExtractor``) imported; a module that has since moved
    (``MOVED_MODULES``: the path a published model's ``config.yml`` recorded) is read at
    its new place."""
    kwargs = {key: value for key, value in recipe.items() if key not in RUN_KEYS}
    policy_kwargs = dict(kwargs.get("policy_kwargs") or {})
    for key in CLASS_KEYS:
        name = policy_kwargs.get(key)
        if isinstance(name, str):
            module, _, attribute = name.rpartition(".")
            module = MOVED_MODULES.get(module, module)
            try:
                policy_kwargs[key] = getattr(importlib.import_module(module), attribute)
            except (ImportError, AttributeError, ValueError) as err:
                raise ValueError(
                    f"policy_kwargs.{key} must name an importable class as module.Class, "
                    f"got {name!r} ({type(err).__name__}: {err})"
                ) from err
    if getattr(policy_class(recipe), "needs_probe_points", False):
        extractor_kwargs = dict(policy_kwargs.get("features_extractor_kwargs") or {})
        extractor_kwargs.setdefault("probe_points", _probe_points(recipe))
        policy_kwargs["features_extractor_kwargs"] = extractor_kwargs
    if policy_kwargs:
        kwargs["policy_kwargs"] = policy_kwargs
    return kwargs


def _probe_points(recipe: dict[str, Any]) -> list[list[float]]:
    """The map points of every probe of the recipe's env (``spatial_probe_policy``), from
    its static geometry."""
    from agents.sb3.spatial_probe_policy import probe_points
    from tactile_search import CupboardSearchEnv

    env = CupboardSearchEnv(**recipe.get("env_kwargs", {}))
    try:
        return probe_points(env.geometry())
    finally:
        env.close()


def policy_class(recipe: dict[str, Any]) -> Any:
    """The recipe's ``policy``: an SB3 alias (``MultiInputPolicy``) as it is, or the class a
    dotted path names (``agents.sb3.joint_probe_policy.JointProbePolicy``)."""
    policy = recipe.get("policy")
    if isinstance(policy, str) and "." in policy:
        module, _, attribute = policy.rpartition(".")
        try:
            return getattr(importlib.import_module(module), attribute)
        except (ImportError, AttributeError, ValueError) as err:
            raise ValueError(
                f"policy must be an SB3 alias or an importable class as module.Class, got "
                f"{policy!r} ({type(err).__name__}: {err})"
            ) from err
    return policy


def new_model(cls: type, recipe: dict[str, Any], env: Any, seed: int) -> Any:
    """A fresh ``cls`` model (on the CPU) of ``recipe`` on ``env`` (``policy_class``)."""
    return cls(policy_class(recipe), env, seed=seed, device="cpu", **algorithm_kwargs(recipe))


def load_objects(recipe: dict[str, Any]) -> dict[str, Any]:
    """SB3's ``custom_objects`` for loading a model trained with ``recipe``: its
    ``policy_kwargs`` with their classes imported (``algorithm_kwargs``), used instead of the
    pickled ones in ``model.zip``, which name each class by the module it was in at training
    time (a model trained before a module moved still loads)."""
    policy_kwargs = algorithm_kwargs(recipe).get("policy_kwargs")
    return {} if policy_kwargs is None else {"policy_kwargs": policy_kwargs}
