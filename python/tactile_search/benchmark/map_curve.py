"""The map task's outline distance against the motions spent, per episode: the row's
``map_score_curve``, from which a figure draws each agent's score against motions.

An episode's trace is its distance after the reset (0 motions) and after each step (the
motions so far, the time limit's count). The curve reads it at ``MAP_CURVE_POINTS`` budgets
evenly spaced over ``[0, max_steps]``: at each, the distance after the last step within that
budget (a probe moves many motions at once, so the curve is a step function; an episode that
ended early keeps its final distance). It is written as text, millimetres separated by
spaces, so that it fits a CSV cell and a JSON string alike; empty outside the map task.
"""

from __future__ import annotations

from typing import Any

import numpy as np

#: Budgets the curve is read at: 0 %, 5 %, ..., 100 % of the episode's motions.
MAP_CURVE_POINTS = 21


class MapScoreTrace:
    """One episode's (motions, outline distance) pairs, as its steps come."""

    def __init__(self, info: dict[str, Any]) -> None:
        """Starts at the reset's ``info``."""
        self.motions = [0]
        self.distances = [float(info["map_score_mm"])]

    def step(self, info: dict[str, Any]) -> None:
        """Adds a step's ``info`` (its ``steps``: the motions so far)."""
        self.motions.append(int(info["steps"]))
        self.distances.append(float(info["map_score_mm"]))

    def curve(self, max_steps: int) -> str:
        """The distance at each of ``MAP_CURVE_POINTS`` budgets over ``[0, max_steps]``,
        as text (see the module docstring)."""
        budgets = np.linspace(0.0, float(max_steps), MAP_CURVE_POINTS)
        last_within = np.searchsorted(np.asarray(self.motions), budgets, side="right") - 1
        return " ".join(repr(self.distances[int(i)]) for i in last_within)


def parse_map_curve(text: str) -> np.ndarray:
    """A row's ``map_score_curve`` as ``MAP_CURVE_POINTS`` floats (mm); ``ValueError`` for
    text of another length (an empty curve: the row is not the map task's)."""
    values = np.array([float(value) for value in text.split()])
    if values.shape != (MAP_CURVE_POINTS,):
        raise ValueError(
            f"a map score curve has {MAP_CURVE_POINTS} values, got {len(values)} ({text!r:.60})"
        )
    return values
