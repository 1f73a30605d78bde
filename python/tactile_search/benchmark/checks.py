"""What ``evaluate`` refuses, in the policy's own terms: a policy that is not one (an SB3
model object, a ``model.predict`` that returns SB3's ``(action, state)`` tuple) and an
action that does not fit the env's action space.

The rule for actions: **every** action the policy returns is checked against the action
space of one env before it is stepped, and one that does not fit raises instead of being
clipped or cast. In the ``wrist`` mode (``Box(-1, 1, (3,))``) an action is 3 finite real
numbers in [-1, 1] (any real dtype; the core would clip the rest, scoring a different
policy); in the ``probe`` mode (``MultiDiscrete([lanes, depths, sweeps])``) it is 3 integers
(an integer dtype) with ``0 <= a < nvec``. Checking every action, not only each episode's
first, catches a policy whose first actions happen to fit (probe indices of 0 and 1 are
wrist motions too). Its cost, measured on 2 busy cores: 1.2 us per action (np.asarray alone:
0.07 us) against 220-360 us for one step of a 2-env vector env, so about 1 % of a step at
most, less with the policy's own time. Duck typing only: nothing here imports
stable-baselines3.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from gymnasium import spaces


def check_policy(policy: Any) -> None:
    """``TypeError`` unless ``policy`` is a callable from observation to action; a model
    object with ``predict`` (an SB3 model) is told to be wrapped with ``from_sb3``."""
    if callable(policy):
        return
    if callable(getattr(policy, "predict", None)):
        raise TypeError(
            f"policy must be callable (observation -> action), got a {type(policy).__name__} "
            "model object: wrap it, evaluate(from_sb3(model), ...) with "
            "`from tactile_search.benchmark import from_sb3` (its deterministic action, a "
            "recurrent model's state carried through each episode)"
        )
    raise TypeError(f"policy must be callable (observation -> action), got {policy!r}")


def action_mode(space: spaces.Space[Any]) -> str:
    """The env's ``action_mode`` from its single action space."""
    return "probe" if isinstance(space, spaces.MultiDiscrete) else "wrist"


#: The entries of an action, by action mode: the claim entry comes 4th where the task
#: claims (``task="identify"``).
ENTRIES = {"wrist": ("dx", "dy", "dyaw", "claim"), "probe": ("lane", "depth", "sweep", "claim")}


def _entries(space: spaces.Space[Any]) -> str:
    """The names of the entries of an action of ``space``: ``dx, dy, dyaw`` and so on."""
    return ", ".join(ENTRIES[action_mode(space)][: int(np.prod(space.shape or ()))])


def _describe(space: spaces.Space[Any]) -> str:
    if isinstance(space, spaces.MultiDiscrete):
        return f"MultiDiscrete({space.nvec}) (action_mode='probe': {_entries(space)} indices)"
    return f"Box(-1, 1, {space.shape}) (action_mode='wrist': {_entries(space)})"


def _shown(action: np.ndarray) -> str:
    return np.array2string(action, precision=4, threshold=12)


class ActionCheck:
    """Checks each of a policy's actions against ``space`` (one env's action space) and
    returns it as an array; see the module docstring for the rule."""

    def __init__(self, space: spaces.Space[Any]) -> None:
        self.space = space
        self.mode = action_mode(space)
        self.shape = tuple(space.shape or ())
        # Bounds as Python numbers: comparing 3 of them in Python is cheaper than numpy calls.
        self._bounds: list[tuple[float, float]]
        if isinstance(space, spaces.MultiDiscrete):
            self._nvec = np.asarray(space.nvec)
            self._bounds = [(0, int(n) - 1) for n in space.nvec]
        elif not isinstance(space, spaces.Box):
            raise TypeError(
                f"an action space must be a MultiDiscrete or a Box, got {type(space).__name__}"
            )
        else:
            self._bounds = [
                (float(lo), float(hi)) for lo, hi in zip(space.low, space.high, strict=True)
            ]

    def __call__(self, returned: Any) -> np.ndarray:
        if isinstance(returned, tuple) and len(returned) == 2 and _sb3_pair(returned):
            raise TypeError(
                "the policy returned a tuple of 2, like stable-baselines3's "
                "model.predict(observation) -> (action, state): return the action alone, "
                "model.predict(observation)[0], or pass from_sb3(model) as the policy "
                "(`from tactile_search.benchmark import from_sb3`), which also carries a "
                "recurrent model's state"
            )
        try:
            action = np.asarray(returned)
        except ValueError as error:
            raise TypeError(
                f"the policy returned {type(returned).__name__} {returned!r}, not an array "
                f"of shape {self.shape}: this env's action space is {_describe(self.space)}"
            ) from error
        if action.shape != self.shape:
            raise ValueError(
                f"the policy returned shape {action.shape} for one observation; this env's "
                f"action space is {_describe(self.space)}: return one action of shape "
                f"{self.shape} per call (the observation is one env's, not a batch)"
            )
        kind = action.dtype.kind
        if self.mode == "probe":
            if kind not in "iu":
                raise TypeError(
                    f"action_mode='probe' takes integer indices ({_entries(self.space)}) of "
                    f"MultiDiscrete({self._nvec}); the policy returned {action.dtype} values "
                    f"{_shown(action)}. Wrist motions in [-1, 1] need action_mode='wrist'; "
                    "indices held as floats need .astype(int)"
                )
            if not self._inside(action):
                raise ValueError(
                    f"action_mode='probe' takes indices 0 <= a < {self._nvec}; the policy "
                    f"returned {_shown(action)} (refused, not clipped)"
                )
            return action
        if kind not in "iuf":
            raise TypeError(
                f"action_mode='wrist' takes {len(self._bounds)} real numbers in [-1, 1] "
                f"({_entries(self.space)}); the policy returned {action.dtype} values "
                f"{_shown(action)}"
            )
        if not self._inside(action):  # NaN too: its comparisons are False
            hint = (
                " Integer indices like these are probe actions: pass action_mode='probe'."
                if kind in "iu"
                else ""
            )
            raise ValueError(
                f"action_mode='wrist' takes {len(self._bounds)} finite numbers in [-1, 1] "
                f"({_entries(self.space)}); the policy returned {_shown(action)} (refused, "
                f"not clipped: the env would clip it and score a different policy).{hint}"
            )
        return action

    def _inside(self, action: np.ndarray) -> bool:
        return all(lo <= a <= hi for a, (lo, hi) in zip(action.tolist(), self._bounds, strict=True))


def _sb3_pair(returned: tuple[Any, ...]) -> bool:
    """``(action, state)`` as SB3's ``predict`` returns it: an array and None or a tuple."""
    first, second = returned
    return isinstance(first, np.ndarray) and (
        second is None or isinstance(second, tuple | np.ndarray)
    )
