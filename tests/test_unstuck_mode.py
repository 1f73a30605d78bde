"""The mode until a probe changes nothing, then a sample (agents.evaluation.unstuck_mode)."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from agents.evaluation.unstuck_mode import UnstuckMode, unchanged_but_the_clock
from tactile_search.envs.observation import PROPRIO, PROPRIO_LEN


def observation(clock: float, x: float = 0.0, cell: int = 0) -> dict[str, np.ndarray]:
    proprio = np.zeros(PROPRIO_LEN, dtype=np.float32)
    proprio[PROPRIO["time_left"]] = clock
    proprio[PROPRIO["x"]] = x
    grid = np.zeros((2, 4, 4), dtype=np.uint8)
    grid[0, 0, 0] = cell
    return {"proprio": proprio, "map": grid}


class ModeOrSample:
    """Stands in for a LearnedAgent: reports which way it was asked to act."""

    name = "stand-in"

    def __init__(self) -> None:
        self.deterministic = True
        self.ways: list[str] = []
        self.resets = 0

    def reset(self, env: Any, observation: dict, info: dict) -> None:
        self.resets += 1
        assert self.deterministic is False  # the sampling stream is seeded at every reset

    def act(self, observation: dict) -> np.ndarray:
        self.ways.append("mode" if self.deterministic else "sample")
        return np.zeros(3)


def test_only_the_clock_moving_counts_as_unchanged():
    assert unchanged_but_the_clock(observation(0.9), observation(0.8))
    assert not unchanged_but_the_clock(observation(0.9), observation(0.8, x=0.1))
    assert not unchanged_but_the_clock(observation(0.9), observation(0.8, cell=1))
    assert not unchanged_but_the_clock({"proprio": np.zeros(PROPRIO_LEN)}, observation(0.8))


def test_the_agent_samples_exactly_after_a_probe_that_changed_nothing():
    inner = ModeOrSample()
    agent = UnstuckMode(inner)
    agent.reset(None, observation(1.0), {})
    for step in [
        observation(1.0),
        observation(0.9),
        observation(0.8, x=0.5),
        observation(0.7, x=0.5),
    ]:
        agent.act(step)
    # first step: nothing before it; then unchanged; then the hand moved; then unchanged again
    assert inner.ways == ["mode", "sample", "mode", "sample"]
    agent.reset(None, observation(1.0), {})  # a new episode forgets the last observation
    agent.act(observation(1.0, x=0.5))
    assert inner.ways[-1] == "mode"
    assert agent.name == "stand-in" and inner.resets == 2


def test_unstuck_rows_are_kept_apart_from_the_modes(tmp_path: Path):
    from agents.evaluation.fingerprints import code_fingerprints
    from tests.recipes import train_with_recipe

    run = str(train_with_recipe(tmp_path, "none"))
    mode = code_fingerprints([run], "mode")[run]
    assert code_fingerprints([run], "mode_unstuck")[run] != mode
    assert code_fingerprints([run], "sample")[run] != mode
