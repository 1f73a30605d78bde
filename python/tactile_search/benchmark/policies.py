"""Policies named on the command line: ``module:callable`` or a stable-baselines3 ``model.zip``.

``module:callable`` imports ``module`` and takes its attribute ``callable``: a function (or
any callable object) from observation to action is the policy; a class is instantiated with
no arguments first. A path ending in ``.zip`` is an SB3 model (the ``agents`` extra),
evaluated as it was trained: the run's ``config.yml`` beside it, when there is one, gives
its algorithm (recurrent or not), the env id and settings it was trained in (``RunConfig``)
and whether its actions are the policy's mode or sampled; a recurrent policy's state is
carried through the episode and cleared at its reset.

Security: an SB3 ``model.zip`` and a named module both run code of their choosing when
loaded. Load only what you trust. A model file with its digest recorded beside it
(``model.digest``, ``tactile_search.benchmark.model_digest``) is checked against it before
it is unpickled, and refused if it changed; one without a record loads with an
``UnverifiedModelWarning``.
"""

from __future__ import annotations

import copy
import dataclasses
import importlib
import os
import warnings
from pathlib import Path
from typing import Any

import numpy as np

from tactile_search import ENV_ID, ENV_IDS
from tactile_search.benchmark.checks import action_mode
from tactile_search.benchmark.model_digest import (
    UnverifiedModelWarning,
    digest_path,
    model_digest,
    verified_digest,
)
from tactile_search.envs.config import REWARD_KEYS

#: SB3 algorithms a model.zip may hold, by the name ``--algo`` takes: (module, class).
SB3_ALGORITHMS: dict[str, tuple[str, str]] = {
    "ppo": ("stable_baselines3", "PPO"),
    "a2c": ("stable_baselines3", "A2C"),
    "dqn": ("stable_baselines3", "DQN"),
    "sac": ("stable_baselines3", "SAC"),
    "td3": ("stable_baselines3", "TD3"),
    "recurrent_ppo": ("sb3_contrib", "RecurrentPPO"),
}


#: The file beside a model.zip that says how its run was trained (``agents.run_dir``).
RUN_CONFIG_FILE = "config.yml"


def evaluation_settings(config: dict[str, Any]) -> dict[str, Any]:
    """The settings of the env a run is evaluated in, from its ``config.yml`` (a mapping):
    its recipe's ``env_kwargs`` and ``map`` without the reward terms (every agent is scored
    in the environment's default reward)."""
    recipe = config.get("hyperparams") or {}
    settings = {**(recipe.get("env_kwargs") or {}), "map": config["map"]}
    return {key: value for key, value in settings.items() if key not in REWARD_KEYS}


@dataclasses.dataclass(frozen=True)
class RunConfig:
    """How a model was trained, from the ``config.yml`` of its run: its algorithm, the env
    id, the env settings it is evaluated in (its recipe's ``env_kwargs`` and ``map`` without
    the reward terms: every agent is scored in the environment's default reward), whether
    its actions are the policy's mode (``deterministic_evaluation``, default true) and the
    recipe (``hyperparams``), whose classes the model loads with
    (``tactile_search.networks.recipe_classes.load_objects``)."""

    algo: str
    env_id: str
    env_settings: dict[str, Any]
    deterministic: bool
    recipe: dict[str, Any]

    @classmethod
    def beside(cls, model: Path) -> RunConfig | None:
        """The run config next to ``model``, or None where there is none. ``ValueError``
        naming the file if it is not a run config."""
        path = model.parent / RUN_CONFIG_FILE
        if not path.is_file():
            return None
        try:
            import yaml
        except ModuleNotFoundError as error:
            raise ModuleNotFoundError(
                f"reading {path} needs pyyaml: pip install 'tactile_search[agents]'",
                name=error.name,
            ) from error
        try:
            config = yaml.safe_load(path.read_text())
            recipe = config.get("hyperparams") or {}
            return cls(
                algo=str(config["algo"]),
                env_id=str(config.get("env_id", ENV_ID)),
                env_settings=evaluation_settings(config),
                deterministic=bool(recipe.get("deterministic_evaluation", True)),
                recipe=dict(recipe),
            )
        except (yaml.YAMLError, AttributeError, KeyError, TypeError) as error:
            raise ValueError(
                f"{path} is not a run's config (a mapping with algo, map and hyperparams): "
                f"{type(error).__name__}: {error}"
            ) from None


def load_policy(spec: str | os.PathLike[str], algo: str | None = None) -> Any:
    """The policy ``spec`` names (see the module docstring): for a ``model.zip``, an
    ``Sb3Policy`` that ``evaluate`` runs in the settings its run was trained in. ``algo``
    overrides a model's run config only where they agree (``ValueError`` otherwise)."""
    if not isinstance(spec, (str, os.PathLike)):
        raise TypeError(
            f"policy must be 'module:callable' or a path to an SB3 model.zip, got {spec!r}"
        )
    spec = os.fspath(spec)
    if spec.endswith(".zip"):
        return Sb3Policy(Path(spec), algo)
    module_name, sep, attribute = spec.partition(":")
    if not sep or not module_name or not attribute:
        raise ValueError(
            f"policy must be 'module:callable' or a path to an SB3 model.zip, got {spec!r}"
        )
    module = importlib.import_module(module_name)
    try:
        policy = getattr(module, attribute)
    except AttributeError:
        raise ValueError(f"module {module_name!r} has no attribute {attribute!r}") from None
    if isinstance(policy, type):
        policy = policy()
    if not callable(policy):
        raise TypeError(f"{spec} must be callable (observation -> action), got {policy!r}")
    return policy


def from_sb3(model: Any, deterministic: bool = True) -> Sb3ModelPolicy:
    """A loaded stable-baselines3 (or sb3-contrib) model as ``evaluate``'s policy::

        evaluate(from_sb3(PPO.load("model.zip")), action_mode="probe", map="gpis")

    Its action is ``model.predict(observation, deterministic=deterministic)[0]``; a
    recurrent model (``RecurrentPPO``) gets its LSTM state carried from step to step and
    cleared at each episode's start (``reset``). Nothing is imported from SB3: any object
    with that ``predict`` and an ``action_space`` will do. ``evaluate`` runs it in the
    action mode of its action space (``env_settings``); name the map it was trained on."""
    if not callable(getattr(model, "predict", None)):
        raise TypeError(
            f"from_sb3 takes a loaded SB3 model (an object with .predict), got {model!r}"
        )
    return Sb3ModelPolicy(model, deterministic)


def _recurrent(model: Any) -> bool:
    """An sb3-contrib recurrent model, by duck typing (its policy holds the actor's LSTM)."""
    policy = getattr(model, "policy", None)
    return hasattr(policy, "lstm_actor") or "Recurrent" in type(model).__name__


class Sb3ModelPolicy:
    """``from_sb3``'s policy. A deep copy (``evaluate`` gives each slot one) shares the
    model (its weights are read, never written) and starts its own episode state."""

    def __init__(self, model: Any, deterministic: bool = True) -> None:
        self.model = model
        self.deterministic = deterministic
        self.name = type(model).__name__
        self._actions = EpisodeActions(model, recurrent=_recurrent(model))

    def __deepcopy__(self, memo: dict[int, Any]) -> Sb3ModelPolicy:
        twin = copy.copy(self)
        twin._actions = EpisodeActions(self.model, recurrent=_recurrent(self.model))
        return twin

    @property
    def env_settings(self) -> dict[str, Any]:
        """The settings the model runs in as far as it says: its action space's mode (none
        for a stand-in without an ``action_space``)."""
        space = getattr(self.model, "action_space", None)
        return {} if space is None else {"action_mode": action_mode(space)}

    def check_fits(self, settings: dict[str, Any]) -> None:
        """``ValueError`` when an env of ``settings`` gives observations or takes actions of
        other spaces than the model's (a map the model never saw, another action mode); a
        space the model does not state is not compared."""
        from tactile_search.envs.cupboard_search import CupboardSearchEnv

        env = CupboardSearchEnv(threads=1, **settings)  # starts no episode
        for what, ours, theirs in (
            ("observations", env.observation_space, getattr(self.model, "observation_space", None)),
            ("actions", env.action_space, getattr(self.model, "action_space", None)),
        ):
            if theirs is not None and ours != theirs:
                given = ", ".join(f"{k}={v!r}" for k, v in settings.items()) or "the defaults"
                raise ValueError(
                    f"the model cannot run under {given}: it was trained on {what} {theirs}, "
                    f"and this env's are {ours}"
                )

    def reset(self, observation: dict[str, np.ndarray], info: dict[str, Any]) -> None:
        self._actions.reset()

    def __call__(self, observation: dict[str, np.ndarray]) -> np.ndarray:
        return self._actions.predict(observation, deterministic=self.deterministic)


class Sb3Policy(Sb3ModelPolicy):
    """An SB3 ``model.zip`` as a policy, as its run config says it was trained
    (``RunConfig``; the policy's mode and ``algo``, default ``ppo``, without one): ``run``
    holds it, ``deterministic`` says how its actions are chosen, and a recurrent model's
    state is carried through each episode (``Sb3ModelPolicy``). Before anything of it is
    unpickled, the file is checked against the digest recorded beside it (``ValueError``
    if it changed; an ``UnverifiedModelWarning`` if there is no record): ``digest`` is its
    digest (hex), ``verified`` whether it was checked."""

    def __init__(self, path: Path, algo: str | None = None) -> None:
        if not path.is_file():
            raise ValueError(f"{path} is not a file")
        recorded = verified_digest(path)
        if recorded is None:
            warnings.warn(
                UnverifiedModelWarning(
                    f"{path} has no recorded digest ({digest_path(path).name} beside it): "
                    "loading it unverified; a model file can run code when loaded, so load "
                    "only one from a source you trust"
                ),
                stacklevel=3,
            )
        self.run = RunConfig.beside(path)
        if self.run is not None:
            if self.run.env_id not in ENV_IDS:
                raise ValueError(
                    f"{path} was trained on {self.run.env_id!r} (its {RUN_CONFIG_FILE}); "
                    f"this benchmark evaluates the registered ids {list(ENV_IDS)}"
                )
            if algo is not None and algo != self.run.algo:
                raise ValueError(
                    f"{path} was trained with {self.run.algo} (its {RUN_CONFIG_FILE}), got "
                    f"--algo {algo}: leave --algo out to use the run's"
                )
            algo = self.run.algo
        algo = algo or "ppo"
        if algo not in SB3_ALGORITHMS:
            raise ValueError(f"algo must be one of {sorted(SB3_ALGORITHMS)}, got {algo!r}")
        self.algo = algo
        module_name, class_name = SB3_ALGORITHMS[algo]
        importlib.import_module("tactile_search.networks")  # sets OMP_WAIT_POLICY before torch
        try:
            module = importlib.import_module(module_name)
        except ModuleNotFoundError as error:
            raise ModuleNotFoundError(
                f"loading a {algo} model.zip needs {module_name}, which is not installed: "
                "pip install 'tactile_search[agents]'",
                name=error.name,
            ) from error
        custom_objects = None if self.run is None else self._recipe_objects(self.run, path)
        try:
            model = getattr(module, class_name).load(
                path, device="cpu", custom_objects=custom_objects
            )
        except ModuleNotFoundError as error:
            raise ModuleNotFoundError(
                f"{path} needs the module {error.name!r} to load (its policy's classes): put "
                f"its run's {RUN_CONFIG_FILE} beside it, or install that module",
                name=error.name,
            ) from None
        except Exception as error:  # SB3 raises assertion, key, pickle and zip errors alike
            raise ValueError(
                f"{path} does not load as a {algo} model ({type(error).__name__}: {error})"
            ) from None
        super().__init__(model, self.run.deterministic if self.run is not None else True)
        self.name = f"{algo} ({path})"
        self.verified = recorded is not None
        self.digest = recorded if recorded is not None else model_digest(path).hex()

    @staticmethod
    def _recipe_objects(run: RunConfig, path: Path) -> dict[str, Any]:
        """SB3's ``custom_objects``: the classes of the run's recipe, imported from the
        installed package, in place of those the model pickled (which may name the
        repository's ``agents`` package, or a module that has moved)."""
        from tactile_search.networks.recipe_classes import load_objects

        try:
            return load_objects(run.recipe)
        except ValueError as error:
            raise ValueError(f"{path.parent / RUN_CONFIG_FILE}: {error}") from None

    @property
    def env_id(self) -> str:
        """The registered id the model was trained on (its run config's, else ``ENV_ID``)."""
        return ENV_ID if self.run is None else self.run.env_id

    @property
    def env_settings(self) -> dict[str, Any]:
        """The env settings the model was trained in: its run config's, else its action
        space's mode."""
        return super().env_settings if self.run is None else dict(self.run.env_settings)


class EpisodeActions:
    """An SB3 model's actions through one episode at a time: a recurrent model's state is
    carried from step to step and cleared by ``reset`` (the episode's start)."""

    def __init__(self, model: Any, recurrent: bool) -> None:
        self.model = model
        self._recurrent = recurrent
        self.reset()

    def reset(self) -> None:
        self._state: Any = None
        self._episode_start = np.ones((1,), dtype=bool)

    def predict(self, observation: dict[str, np.ndarray], deterministic: bool) -> np.ndarray:
        """The model's action for ``observation``: its mode, or a sample from it."""
        if not self._recurrent:
            action, _ = self.model.predict(observation, deterministic=deterministic)
            return np.asarray(action)  # typed: SB3's model reaches here as Any
        action, self._state = self.model.predict(
            observation,
            state=self._state,
            episode_start=self._episode_start,
            deterministic=deterministic,
        )
        self._episode_start = np.zeros((1,), dtype=bool)
        return np.asarray(action)
