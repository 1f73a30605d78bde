"""The actions a soak steps its envs with, by kind: ``random`` (uniform in the action
space), ``forward`` (random with the motion into the cupboard: contact-rich),
``out_of_range`` (finite components up to 1e300 and float32's largest: the env clips them,
``info["clipped"]``), ``invalid`` (about one step in ten, ``INVALID_RATE``, is NaN, inf, a
wrong shape, a string, None, a dict or an object array: each must raise the documented
``ValueError`` (or ``TypeError``) and change nothing) and ``oracle``
(``env.unwrapped.oracle_action()``)."""

from __future__ import annotations

from typing import Any

import numpy as np

#: Probability that a step of an ``invalid`` episode is an invalid action.
INVALID_RATE = 0.1


def out_of_range_action(rng: np.random.Generator, shape: tuple[int, ...]) -> np.ndarray:
    """Finite actions, about half their components outside [-1, 1] (up to 1e300), some in
    float32 at its largest or just past 1."""
    if rng.random() < 0.2:
        picks = np.array(
            [np.finfo(np.float32).max, np.nextafter(np.float32(1), np.float32(2)), 0.5],
            dtype=np.float32,
        )
        signs = rng.choice(np.array([-1, 1], dtype=np.float32), shape)
        return signs * rng.choice(picks, shape)
    action = rng.uniform(-1, 1, shape)
    wild = rng.random(shape) < 0.5
    magnitude = 10.0 ** rng.uniform(0, 300, shape)
    return np.where(wild, rng.choice([-1.0, 1.0], shape) * magnitude, action)


def invalid_action(rng: np.random.Generator, num_envs: int | None) -> tuple[str, Any]:
    """A (kind, action) the env must refuse; ``num_envs`` None for the single env."""
    shape = (3,) if num_envs is None else (num_envs, 3)
    valid = rng.uniform(-1, 1, shape)
    kind = str(
        rng.choice(
            ["nan", "inf", "-inf", "short", "long", "extra_dim", "str", "none", "dict", "object"]
        )
    )
    if kind in ("nan", "inf", "-inf"):
        valid[np.unravel_index(rng.integers(valid.size), shape)] = float(kind)
        return kind, valid
    if kind == "short":
        return kind, valid[..., :2]
    if kind == "long":
        return kind, np.zeros((*shape[:-1], 4))
    if kind == "extra_dim":
        return kind, valid[None] if num_envs is None else valid[..., None]
    if kind == "str":
        return kind, "left" if rng.random() < 0.5 else [["a", "b", "c"]] * (num_envs or 1)
    if kind == "none":
        return kind, None
    if kind == "dict":
        return kind, {"dx": 0.1}
    return kind, np.full(shape, None, dtype=object)


def policy_action(
    kind: str, env: Any, shape: tuple[int, ...], rng: np.random.Generator
) -> np.ndarray:
    """A valid (or, for ``out_of_range``, clippable) action of ``kind`` for ``env``; the
    ``invalid`` kind's valid steps are ``random`` ones."""
    if kind == "oracle":
        unwrapped = env.unwrapped
        if hasattr(unwrapped, "oracle_actions"):
            return unwrapped.oracle_actions()
        return unwrapped.oracle_action()
    if kind == "out_of_range":
        return out_of_range_action(rng, shape)
    action = rng.uniform(-1, 1, shape).astype(np.float32)
    if kind == "forward":
        action[..., 1] = np.abs(action[..., 1])
    return action
