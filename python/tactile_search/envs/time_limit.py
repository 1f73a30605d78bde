"""The time limit declared the Gymnasium way, with one source: the core's ``max_steps``.

The episode truncates itself at ``max_steps`` (the core reports it as the step's
``truncated``), so the env is registered without ``max_episode_steps``: a registered value
would make ``gymnasium.make`` add a ``TimeLimit`` wrapper, a second limit that could not
follow ``make(..., max_steps=N)``. Instead every env declares its own limit where Gymnasium's
clients read it: when ``make`` or ``make_vec`` gives the env its spec, the spec's
``max_episode_steps`` becomes the env's ``max_steps`` (``TimeAwareObservation`` and RL
libraries read ``env.spec.max_episode_steps``).
"""

from __future__ import annotations

import dataclasses
from typing import Any


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
