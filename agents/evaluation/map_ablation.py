"""Map channels blanked at evaluation: what an agent reads from its map, measured.

``MapChannelsBlanked`` wraps any agent (learned or scripted) so that it sees chosen channels of
its ``observation["map"]`` held at one pixel value, the env itself unchanged: the episode, its
physics and its metrics are the agent's own, only what the agent reads is cut. Blanking the
GPIS ``std`` channel asks whether an agent uses the map's uncertainty (what the GPIS map holds
and an occupancy grid does not); blanking the ``mean`` asks whether it reads the map at all.

A blanking is written ``NAME=VALUE`` (``std=0``: the std channel held at pixel 0, what the
occupancy map's ``empty`` channel always reads; ``std=255``: unknown everywhere), the channel
names those of the core's observation layout for the agent's map mode
(``tactile_search.envs.observation.MAP_CHANNELS``).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np

from agents.evaluation.wrapped_agent import WrappedAgent
from tactile_search.envs.observation import MAP_CHANNELS

PIXEL_RANGE = (0, 255)


def parse_blanking(text: str) -> tuple[str, int]:
    """``"std=0"`` -> ``("std", 0)``; ``ValueError`` naming the expected form otherwise."""
    if not isinstance(text, str):
        raise TypeError(f"a blanking is a string NAME=VALUE, got {type(text).__name__}")
    name, sep, value = text.partition("=")
    if not sep or not name.strip():
        raise ValueError(f"a blanking is NAME=VALUE (such as std=0), got {text!r}")
    try:
        pixel = int(value)
    except ValueError:
        raise ValueError(
            f"a blanking's value is a pixel value, an int in {PIXEL_RANGE}, got {value!r}"
        ) from None
    if not PIXEL_RANGE[0] <= pixel <= PIXEL_RANGE[1]:
        raise ValueError(f"a blanking's value is a pixel value in {PIXEL_RANGE}, got {pixel}")
    return name.strip(), pixel


def channel_indices(map_mode: str, blanked: Mapping[str, int]) -> dict[int, int]:
    """The map channel index -> pixel value of each blanked channel of ``map_mode``;
    ``ValueError`` for a channel the map mode does not have (a map mode without a map has
    none)."""
    known = sorted(name for mode, name in MAP_CHANNELS if mode == map_mode)
    unknown = [name for name in blanked if (map_mode, name) not in MAP_CHANNELS]
    if unknown:
        raise ValueError(
            f"the {map_mode!r} map has the channels {known}; cannot blank {sorted(unknown)}"
        )
    return {MAP_CHANNELS[map_mode, name]: pixel for name, pixel in blanked.items()}


def blanking_label(blanked: Mapping[str, int]) -> str:
    """``{"std": 0}`` -> ``"std=0"`` (names sorted): the suffix of a blanked agent's name."""
    return ", ".join(f"{name}={pixel}" for name, pixel in sorted(blanked.items()))


class MapChannelsBlanked(WrappedAgent):
    """``agent`` reading its map with the ``blanked`` channels (name -> pixel value) held at
    their values; named ``"<agent> [std=0]"``. Works with any agent of ``agents.rollout``'s
    protocol (``reset(env, observation, info)``, ``act(observation)``)."""

    def __init__(self, agent: Any, map_mode: str, blanked: Mapping[str, int]) -> None:
        if not blanked:
            raise ValueError("give at least one channel to blank")
        super().__init__(agent)
        self._channels = channel_indices(map_mode, blanked)
        #: What the agent's name gains: `` [std=0]``.
        self.name_suffix = f" [{blanking_label(blanked)}]"
        self.name += self.name_suffix

    def _blank(self, observation: dict) -> dict:
        blanked_map = np.array(observation["map"], copy=True)
        for channel, pixel in self._channels.items():
            blanked_map[channel] = pixel
        return {**observation, "map": blanked_map}

    def reset(self, env: Any, observation: dict, info: dict) -> None:
        self._agent.reset(env, self._blank(observation), info)

    def act(self, observation: dict) -> np.ndarray:
        return self._agent.act(self._blank(observation))


def blanked_agent(agent: Any, map_mode: str, blankings: Sequence[str]) -> Any:
    """``agent`` as it is when ``blankings`` is empty, else ``MapChannelsBlanked`` with the
    parsed ``NAME=VALUE`` blankings (one per channel)."""
    if not blankings:
        return agent
    parsed = [parse_blanking(text) for text in blankings]
    names = [name for name, _ in parsed]
    if len(set(names)) != len(names):
        raise ValueError(f"blank each channel once, got {list(blankings)}")
    return MapChannelsBlanked(agent, map_mode, dict(parsed))
