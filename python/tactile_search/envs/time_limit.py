"""The time limit by Gymnasium's conventions, with one source: the episode's ``max_steps``.

The core truncates an episode at its ``max_steps`` (the step's ``truncated``). Gymnasium
names the limit ``max_episode_steps`` and enforces it with its ``TimeLimit`` wrapper; every
way of making an env gives it one limit, that ``max_steps``:

- The ids are registered without ``max_episode_steps``: a registered value would make
  ``gymnasium.make(id, max_steps=N)`` wrap a ``TimeLimit`` at that value, a second,
  different limit. So ``make(id)`` wraps no ``TimeLimit``, as its spec declares none.
- Each made env declares its limit in its own spec, ``spec.max_episode_steps ==
  max_steps`` (``DeclaredTimeLimit``), where ``TimeAwareObservation`` and RL libraries read
  it. A made env's spec re-makes it: ``gymnasium.make(env.spec)`` wraps ``TimeLimit`` at the
  env's own limit, and ``gymnasium.make_vec(env.spec)`` hands the vector env that limit as
  ``max_episode_steps``, which it takes as ``max_steps`` (``max_steps_of``).
- ``gymnasium.make(id, max_episode_steps=N)`` is ``make(id, max_steps=N)`` under a
  ``TimeLimit`` at N: the same limit, the same episodes. Gymnasium gives N to the wrapper
  alone (the env's spec gets ``max_episode_steps=None``; Gymnasium issue #871 asks for it),
  so the env reads the limit ``make`` wraps from ``make``'s own arguments at the one moment
  ``make`` calls into the env with them on its stack, when it hands the env its spec
  (``limit_make_wraps``). A ``max_steps`` given beside it that differs is a ``ValueError``.
"""

from __future__ import annotations

import dataclasses
import inspect
import warnings
from types import FrameType
from typing import TYPE_CHECKING, Any

from gymnasium.envs import registration
from gymnasium.envs.registration import EnvSpec

from tactile_search._validation import as_count

if TYPE_CHECKING:
    from tactile_search.envs.config import CupboardSearchConfig

#: ``gymnasium.make``'s ``max_episode_steps`` that wraps no ``TimeLimit``.
NO_TIME_LIMIT = -1

#: The names of ``gymnasium.make``'s arguments the limit is read from (gymnasium 1.x).
MAKE_ARGUMENTS = ("max_episode_steps", "env_spec", "kwargs")


class DeclaredTimeLimit:
    """Mixin of the cupboard-search envs: ``spec.max_episode_steps`` is ``config.max_steps``,
    and an env made by ``gymnasium.make`` takes the limit its ``TimeLimit`` wraps as its
    ``max_steps`` (see the module docstring). Put it before ``gymnasium.Env`` /
    ``VectorEnv``."""

    config: CupboardSearchConfig
    _declared_spec: EnvSpec | None = None

    @property
    def spec(self) -> EnvSpec | None:
        """Gymnasium's ``EnvSpec`` of this env (None unless made by ``make``/``make_vec``),
        with ``max_episode_steps`` the episode's ``max_steps``."""
        return self._declared_spec

    @spec.setter
    def spec(self, spec: EnvSpec | None) -> None:
        this_call = inspect.currentframe()
        limit = limit_make_wraps(None if this_call is None else this_call.f_back)
        if limit is not None and limit != self.config.max_steps:
            self._remake_with_max_steps(limit)
        if spec is not None:
            spec = dataclasses.replace(spec, max_episode_steps=self.config.max_steps)
        self._declared_spec = spec

    def _remake_with_max_steps(self, max_steps: int) -> None:
        """Builds the env again with ``max_steps``: the single env's (``gymnasium.make``
        makes no other; ``make_vec`` passes the vector env its limit as an argument)."""
        raise TypeError(
            f"{type(self).__name__} takes its time limit as max_episode_steps or max_steps, "
            "from gymnasium.make_vec"
        )


def limit_make_wraps(caller: FrameType | None) -> int | None:
    """The limit of the ``TimeLimit`` that ``gymnasium.make`` wraps around the env it is
    making, if ``caller`` (the frame that sets the env's spec) is ``make``'s: by ``make``'s own
    rule, its ``max_episode_steps`` argument, else its spec's (None or ``NO_TIME_LIMIT``: no
    wrapper, None here). ``ValueError`` if the same call gives a ``max_steps`` that differs
    (``max_steps_of``). None when ``caller`` is not ``make``."""
    if caller is None or caller.f_code is not registration.make.__code__:
        return None
    arguments = caller.f_locals
    if any(name not in arguments for name in MAKE_ARGUMENTS):
        # Another gymnasium whose make keeps them elsewhere: its TimeLimit alone takes N.
        warnings.warn(
            "this gymnasium's make does not name its arguments "
            f"{', '.join(MAKE_ARGUMENTS)}: a max_episode_steps given to make reaches its "
            "TimeLimit only, not the env's max_steps (give max_steps instead)",
            stacklevel=4,
        )
        return None
    limit = arguments["max_episode_steps"]
    if limit is None:
        limit = arguments["env_spec"].max_episode_steps
    if limit is None or limit == NO_TIME_LIMIT:
        return None
    return max_steps_of(limit, arguments["kwargs"].get("max_steps"))


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
