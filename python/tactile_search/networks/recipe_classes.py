"""The classes a training recipe names by dotted path, imported: its ``policy`` and the
classes in its ``policy_kwargs``; and SB3's ``custom_objects`` that load a model with them.

A recipe is YAML and holds no classes, so it names them as ``module.Class``. A
``model.zip`` pickles the same references, by the module each class was in when the model
was trained; such a model does not load where that module is not importable (the
repository's ``agents`` package, outside the repository) or has moved. ``load_objects``
hands SB3 the classes of the run's recipe, imported at their present place
(``MOVED_MODULES``), in place of the pickled ones, so every published model loads from the
installed package alone.
"""

from __future__ import annotations

import importlib
from typing import Any

#: The keys of a recipe's ``policy_kwargs`` whose values are classes named by dotted path.
CLASS_KEYS = ("features_extractor_class", "activation_fn")

#: Modules that earlier runs' recipes name and that have moved since, old -> new. The
#: published models were trained with the networks in the repository's ``agents`` package.
MOVED_MODULES = {
    "agents.encoders": "tactile_search.networks.encoders",
    "agents.sb3.encoders": "tactile_search.networks.encoders",
    "agents.sb3.joint_probe_policy": "tactile_search.networks.joint_probe",
    "agents.sb3.spatial_probe_policy": "tactile_search.networks.spatial_probe",
}


def import_class(name: str, key: str) -> Any:
    """The class (or function) ``name`` (``module.Class``) names, read at its present module
    (``MOVED_MODULES``). ``ValueError`` naming the recipe ``key`` if it does not import."""
    module, _, attribute = name.rpartition(".")
    module = MOVED_MODULES.get(module, module)
    try:
        return getattr(importlib.import_module(module), attribute)
    except (ImportError, AttributeError, ValueError) as err:
        raise ValueError(
            f"{key} must name an importable class as module.Class, got {name!r} "
            f"({type(err).__name__}: {err})"
        ) from err


def policy_class(recipe: dict[str, Any]) -> Any:
    """The recipe's ``policy``: an SB3 alias (``MultiInputPolicy``) as it is, or the class a
    dotted path names (``tactile_search.networks.joint_probe.JointProbePolicy``)."""
    policy = recipe.get("policy")
    if isinstance(policy, str) and "." in policy:
        return import_class(policy, "policy")
    return policy


def policy_kwargs(recipe: dict[str, Any]) -> dict[str, Any]:
    """The recipe's ``policy_kwargs`` with the classes of ``CLASS_KEYS`` imported, and, for
    a policy that reads the map where each probe goes (``needs_probe_points``), the points
    of the probes of the recipe's env (``spatial_probe.probe_points``) unless it names
    them."""
    kwargs = dict(recipe.get("policy_kwargs") or {})
    for key in CLASS_KEYS:
        if isinstance(kwargs.get(key), str):
            kwargs[key] = import_class(kwargs[key], f"policy_kwargs.{key}")
    if getattr(policy_class(recipe), "needs_probe_points", False):
        extractor_kwargs = dict(kwargs.get("features_extractor_kwargs") or {})
        extractor_kwargs.setdefault("probe_points", _probe_points(recipe))
        kwargs["features_extractor_kwargs"] = extractor_kwargs
    return kwargs


def _probe_points(recipe: dict[str, Any]) -> list[list[float]]:
    """The map points of every probe of the recipe's env, from its static geometry."""
    from tactile_search import CupboardSearchEnv
    from tactile_search.networks.spatial_probe import probe_points

    env = CupboardSearchEnv(threads=1, **recipe.get("env_kwargs", {}))
    try:
        return probe_points(env.geometry())
    finally:
        env.close()


def load_objects(recipe: dict[str, Any]) -> dict[str, Any]:
    """SB3's ``custom_objects`` for loading a model trained with ``recipe``: its policy class
    (where the recipe names one by dotted path; an SB3 alias pickles SB3's own class) and
    its ``policy_kwargs`` (``policy_kwargs``), used instead of the pickled ones."""
    objects: dict[str, Any] = {}
    policy = recipe.get("policy")
    if isinstance(policy, str) and "." in policy:
        objects["policy_class"] = policy_class(recipe)
    kwargs = policy_kwargs(recipe)
    if kwargs:
        objects["policy_kwargs"] = kwargs
    return objects
