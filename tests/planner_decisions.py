"""The GPIS probe planner's decisions on pinned validation layouts, for
``tests/test_probe_planner_core.py``.

``python tests/planner_decisions.py --out tests/data/probe_planner_decisions.npz`` records
the Python reference's (``agents.scripted.belief_planner.BeliefProbePlanner``) probes, every
one of each episode, on ``LAYOUTS``. The test checks that the core's planner and the
reference both still make them. Re-record only for a change of the planner's rules made on
purpose, and say why in the commit.
"""

from __future__ import annotations

import argparse
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np

from tactile_search import CupboardSearchEnv

#: Validation layouts (DESIGN §7; the planner's choices were made on this range): the first
#: 16, and the 7 of the next 184 with the longest episodes (5 to 8 probes).
LAYOUTS = (
    *range(1_000_000, 1_000_016),
    *(1_000_046, 1_000_048, 1_000_079, 1_000_101, 1_000_139, 1_000_159, 1_000_189),
)
SETTINGS = {"map": "gpis", "action_mode": "probe"}


def record(make_planner: Callable[[], Any], layouts=LAYOUTS) -> dict[str, np.ndarray]:
    """Per layout, every probe ``make_planner()`` makes in its episode: ``actions`` (all
    episodes' probes in order), ``episode_lengths`` and ``layout_seeds``."""
    env = CupboardSearchEnv(**SETTINGS)
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


def main() -> None:
    from agents.scripted import BeliefProbePlanner

    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", type=Path, required=True)
    args = parser.parse_args()
    np.savez_compressed(args.out, **record(BeliefProbePlanner))


if __name__ == "__main__":
    main()
