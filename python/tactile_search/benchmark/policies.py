"""Policies named on the command line: ``module:callable`` or a stable-baselines3 ``model.zip``.

``module:callable`` imports ``module`` and takes its attribute ``callable``: a function (or
any callable object) from observation to action is the policy; a class is instantiated with
no arguments first. A path ending in ``.zip`` is an SB3 model, loaded with the algorithm
``--algo`` names (the ``agents`` extra); its policy's mode is the action, with a recurrent
policy's state carried through the episode and cleared at its reset.

Security: an SB3 ``model.zip`` and a named module both run code of their choosing when
loaded. Load only what you trust.
"""

from __future__ import annotations

import importlib
from pathlib import Path
from typing import Any

import numpy as np

#: SB3 algorithms a model.zip may hold, by the name ``--algo`` takes: (module, class).
SB3_ALGORITHMS: dict[str, tuple[str, str]] = {
    "ppo": ("stable_baselines3", "PPO"),
    "a2c": ("stable_baselines3", "A2C"),
    "dqn": ("stable_baselines3", "DQN"),
    "sac": ("stable_baselines3", "SAC"),
    "td3": ("stable_baselines3", "TD3"),
    "recurrent_ppo": ("sb3_contrib", "RecurrentPPO"),
}


def load_policy(spec: str, algo: str = "ppo") -> Any:
    """The policy ``spec`` names (see the module docstring)."""
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


class Sb3Policy:
    """An SB3 model as a policy: its mode, with a recurrent model's state per episode."""

    def __init__(self, path: Path, algo: str) -> None:
        if algo not in SB3_ALGORITHMS:
            raise ValueError(f"algo must be one of {sorted(SB3_ALGORITHMS)}, got {algo!r}")
        if not path.is_file():
            raise ValueError(f"{path} is not a file")
        module_name, class_name = SB3_ALGORITHMS[algo]
        try:
            module = importlib.import_module(module_name)
        except ModuleNotFoundError as error:
            raise ModuleNotFoundError(
                f"loading a {algo} model.zip needs {module_name}, which is not installed: "
                "pip install 'tactile_search[agents]'",
                name=error.name,
            ) from error
        self.name = f"{algo} ({path})"
        self.model = getattr(module, class_name).load(path, device="cpu")
        self._actions = EpisodeActions(self.model, recurrent=algo == "recurrent_ppo")

    def reset(self, observation: dict, info: dict) -> None:
        self._actions.reset()

    def __call__(self, observation: dict) -> np.ndarray:
        return self._actions.predict(observation, deterministic=True)


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

    def predict(self, observation: dict, deterministic: bool) -> np.ndarray:
        """The model's action for ``observation``: its mode, or a sample from it."""
        if not self._recurrent:
            action, _ = self.model.predict(observation, deterministic=deterministic)
            return action
        action, self._state = self.model.predict(
            observation,
            state=self._state,
            episode_start=self._episode_start,
            deterministic=deterministic,
        )
        self._episode_start = np.zeros((1,), dtype=bool)
        return action


def from_sb3(model: Any, deterministic: bool = True) -> Sb3ModelPolicy:
    """A loaded stable-baselines3 (or sb3-contrib) model as ``evaluate``'s policy::

        evaluate(from_sb3(PPO.load("model.zip")), action_mode="probe", map="gpis")

    Its action is ``model.predict(observation, deterministic=deterministic)[0]``; a
    recurrent model (``RecurrentPPO``) gets its LSTM state carried from step to step and
    cleared at each episode's start (``reset``). Nothing is imported from SB3: any object
    with that ``predict`` will do. Evaluate it in the action mode it was trained in."""
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
    model and starts its own episode state."""

    def __init__(self, model: Any, deterministic: bool = True) -> None:
        self.model = model
        self.deterministic = deterministic
        self.name = type(model).__name__
        self._actions = EpisodeActions(model, recurrent=_recurrent(model))

    def __deepcopy__(self, memo: dict) -> Sb3ModelPolicy:
        return Sb3ModelPolicy(self.model, self.deterministic)

    def reset(self, observation: dict, info: dict) -> None:
        self._actions.reset()

    def __call__(self, observation: dict) -> np.ndarray:
        return self._actions.predict(observation, deterministic=self.deterministic)
