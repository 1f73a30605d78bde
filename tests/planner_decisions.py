"""The core planners' decisions on pinned validation layouts, for
``tests/test_probe_planner_core.py``, ``tests/test_identify_planner_core.py`` and
``tests/test_map_planner_core.py``.

``python tests/planner_decisions.py --planner gpis_probe_planner --out
tests/data/probe_planner_decisions.npz`` records the Python reference's actions (the second
of ``agents.scripted.CORE_PLANNERS[planner]``), every one of each episode, on the planner's
pinned layouts and settings (``pinned_episodes``). The tests check that the core's planner
and the reference both still make them. Re-record only for a change of a planner's rules
made on purpose, and say why in the commit.
"""

from __future__ import annotations

import argparse
from collections.abc import Callable
from pathlib import Path
from typing import Any

import gymnasium as gym
import numpy as np

from tactile_search import CupboardSearchEnv

#: Validation layouts (DESIGN §7; the planner's choices were made on this range): the first
#: 16, and the 7 of the next 184 with the longest episodes (5 to 8 probes).
LAYOUTS = (
    *range(1_000_000, 1_000_016),
    *(1_000_046, 1_000_048, 1_000_079, 1_000_101, 1_000_139, 1_000_159, 1_000_189),
)
SETTINGS = {"map": "gpis", "action_mode": "probe"}

IDENTIFY_ID = "tactile_search/IdentifyByTouch-v0"
#: The identify planner's pinned layouts: the first 24 of the validation range (claims of
#: the square jar, wrong claims, inspections and time-outs among them).
IDENTIFY_LAYOUTS = tuple(range(1_000_000, 1_000_024))


def identify_settings() -> dict[str, Any]:
    """The identify id's settings in the planner's action mode."""
    return {**gym.spec(IDENTIFY_ID).kwargs, **SETTINGS}


MAP_ID = "tactile_search/MapByTouch-v0"
#: The mappers' pinned layouts: the first 12 of the validation range.
MAP_LAYOUTS = tuple(range(1_000_000, 1_000_012))


def map_settings(map_mode: str) -> dict[str, Any]:
    """The map id's settings with the map ``map_mode``, in the probe action mode."""
    return {**gym.spec(MAP_ID).kwargs, "map": map_mode, "action_mode": "probe"}


def pinned_episodes(planner: str) -> tuple[tuple[int, ...], dict[str, Any]]:
    """The layouts and settings a planner's decisions are pinned on."""
    return {
        "gpis_probe_planner": (LAYOUTS, SETTINGS),
        "identify_planner": (IDENTIFY_LAYOUTS, identify_settings()),
        "variance_mapper": (MAP_LAYOUTS, map_settings("gpis")),
        "occupancy_mapper": (MAP_LAYOUTS, map_settings("occupancy")),
    }[planner]


def record(
    make_planner: Callable[[], Any], layouts=LAYOUTS, settings=None
) -> dict[str, np.ndarray]:
    """Per layout, every action ``make_planner()`` makes in its episode of ``settings``
    (default ``SETTINGS``): ``actions`` (all episodes' actions in order),
    ``episode_lengths`` and ``layout_seeds``."""
    env = CupboardSearchEnv(**(SETTINGS if settings is None else settings))
    actions, lengths = [], []
    for layout in layouts:
        observation, info = env.reset(seed=layout)
        planner = make_planner()
        planner.reset(env, observation, info)
        done, length = False, 0
        while not done:
            action = np.asarray(planner.act(observation), dtype=np.int64)
            actions.append(action)
            observation, _, terminated, truncated, _ = env.step(action)
            done, length = terminated or truncated, length + 1
        lengths.append(length)
    return {
        "actions": np.stack(actions),
        "episode_lengths": np.array(lengths, dtype=np.int64),
        "layout_seeds": np.array(layouts, dtype=np.int64),
    }


def record_batch(core_class: Any, layouts=LAYOUTS, settings=None) -> dict[str, np.ndarray]:
    """``record`` by one of the core's planner classes planning every layout's episode at
    once (``core_class(config, len(layouts))``, acting on every core)."""
    settings = SETTINGS if settings is None else settings
    envs = [CupboardSearchEnv(threads=1, **settings) for _ in layouts]
    planner = core_class(envs[0].config.core, len(envs))
    observations = [env.reset(seed=layout)[0] for env, layout in zip(envs, layouts, strict=True)]
    for i, observation in enumerate(observations):
        planner.reset(i, observation["map"], observation["proprio"])
    made: list[list[np.ndarray]] = [[] for _ in envs]
    running = [True] * len(envs)
    while any(running):
        actions = planner.act(
            np.stack([o["map"] for o in observations]),
            np.stack([o["proprio"] for o in observations]),
        )
        assert actions.dtype == np.int64 and actions.shape[0] == len(envs)
        for i, env in enumerate(envs):
            if running[i]:
                made[i].append(actions[i])
                observations[i], _, terminated, truncated, _ = env.step(actions[i])
                running[i] = not (terminated or truncated)
    return {
        "actions": np.concatenate([np.stack(episode) for episode in made]),
        "episode_lengths": np.array([len(episode) for episode in made], dtype=np.int64),
        "layout_seeds": np.array(layouts, dtype=np.int64),
    }


def main() -> None:
    from agents.scripted import CORE_PLANNERS

    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--planner", choices=sorted(CORE_PLANNERS), required=True)
    parser.add_argument("--out", type=Path, required=True)
    args = parser.parse_args()
    layouts, settings = pinned_episodes(args.planner)
    np.savez_compressed(args.out, **record(CORE_PLANNERS[args.planner][1], layouts, settings))


if __name__ == "__main__":
    main()
