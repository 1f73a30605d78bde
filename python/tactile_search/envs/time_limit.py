"""The time limit declared the Gymnasium way, with one source: the core's ``max_steps``.

The episode truncates itself at ``max_steps`` (the core reports it as the step's
``truncated``), so the env is registered without ``max_episode_steps``: a registered value
would make ``gymnasium.make`` add a ``TimeLimit`` wrapper, a second limit that could not
follow ``make(..., max_steps=N)``. Instead every env declares its own limit where Gymnasium's
clients read it: when ``make`` or ``make_vec`` gives the env its spec, the spec's
``max_episode_steps`` is set to the env's ``max_steps`` (``TimeAwareObservation`` and RL
libraries read ``env.spec.max_episode_steps``). So a made env's spec re-makes it:
``gymnasium.make(env.spec)`` wraps ``TimeLimit`` at the env's own ``max_steps`` (one limit),
and ``gymnasium.make_vec(vector.spec)`` hands the vector env that limit as
``max_episode_steps``, which it takes as ``max_steps`` (``max_steps_of``).
"""

from __future__ import annotations

import dataclasses
from typing import Any

from tactile_search._validation import as_count


class DeclaredTimeLimit:
    """Mixin of the cupboard-search envs: ``spec.max_episode_steps`` is ``config.max_steps``
    (see the module docstring). Put it before ``gymnasium.Env`` / ``VectorEnv``."""

    config: Any
    _declared_spec: Any = None

    @property
    def spec(self) -> Any:
        """Gymnasium's ``EnvSpec`` of this env (None unless made by ``make``/``make_vec``),
        with ``max_episode_steps`` the episode's ``max_steps``."""
        return self._declared_spec

    @spec.setter
    def spec(self, spec: Any) -> None:
        if spec is not None:
            spec = dataclasses.replace(spec, max_episode_steps=self.config.max_steps)
        self._declared_spec = spec


def max_steps_of(max_episode_steps: Any, max_steps: Any = None) -> int:
    """The ``max_steps`` that gymnasium's ``max_episode_steps`` names (an int >= 1), checked
    against a ``max_steps`` given beside it: ``ValueError`` if they differ."""
    limit = as_count("max_episode_steps", max_episode_steps, minimum=1)
    if max_steps is not None and max_steps != limit:
        raise ValueError(
            f"max_episode_steps ({limit}) and max_steps ({max_steps!r}) name the same time "
            "limit and must agree; give one of them"
        )
    return limit
