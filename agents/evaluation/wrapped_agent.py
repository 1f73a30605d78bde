"""An agent around another one, for evaluation-time variants of an agent (its map blanked,
its way of acting changed): the wrapper's ``name`` starts as the wrapped agent's, and any
attribute the wrapper does not set (a learned agent's ``config``, ``env_kwargs``,
``map_mode``) is the wrapped agent's."""

from __future__ import annotations

from typing import Any


class WrappedAgent:
    """Holds ``agent`` and hands it every attribute the subclass does not set; subclasses
    override ``reset`` and ``act`` as they need."""

    def __init__(self, agent: Any) -> None:
        self._agent = agent
        self.name: str = agent.name

    def __getattr__(self, attribute: str) -> Any:
        # Before ``_agent`` is set (``copy.deepcopy`` builds a copy without ``__init__``),
        # asking for it must not look for it on itself again.
        if attribute == "_agent":
            raise AttributeError(attribute)
        return getattr(self._agent, attribute)

    def reset(self, env: Any, observation: dict, info: dict) -> None:
        self._agent.reset(env, observation, info)

    def act(self, observation: dict) -> Any:
        return self._agent.act(observation)
