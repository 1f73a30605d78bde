"""The statistics of an evaluation: the Wilson interval of a success rate, the interval of
a mean (the map task's scores) and one agent's summary row (success, steps to success,
displacement, tips, IoU, the map scores)."""

from __future__ import annotations

import math
import statistics
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

# The z of a two-sided 95 % interval.
Z_95 = 1.959963984540054


@dataclass(frozen=True)
class Summary:
    """One agent's results over the held-out episodes."""

    agent: str
    map_mode: str
    episodes: int
    successes: int
    success_low: float
    success_high: float
    steps_median: float
    steps_q1: float
    steps_q3: float
    displacement_mm: float
    # Mean over the successful episodes alone (NaN without one): measured per episode, not
    # the episode mean divided by the success rate.
    success_displacement_mm: float
    max_displacement_mm: float
    tip_rate: float
    iou: float
    # The share of episodes that ended with a wrong claim (the identify task; 0 elsewhere).
    wrong_claim_rate: float = 0.0
    # The map task's means over episodes (0 elsewhere): the final outline distance (mm),
    # the final IoU and the distance's mean over the budget (mm, the area under the curve).
    map_score_mm: float = 0.0
    map_score_iou: float = 0.0
    map_score_area: float = 0.0
    # The 95 % intervals of the map task's two distances (``mean_interval``; NaN with fewer
    # than two episodes).
    map_score_mm_low: float = 0.0
    map_score_mm_high: float = 0.0
    map_score_area_low: float = 0.0
    map_score_area_high: float = 0.0

    @property
    def success_rate(self) -> float:
        return self.successes / self.episodes


def wilson_interval(successes: int, n: int, z: float = Z_95) -> tuple[float, float]:
    """The Wilson score interval of a binomial proportion (95 % by default)."""
    if n <= 0:
        raise ValueError(f"n must be positive, got {n}")
    if not 0 <= successes <= n:
        raise ValueError(f"successes must be in [0, {n}], got {successes}")
    p = successes / n
    denominator = 1 + z * z / n
    centre = (p + z * z / (2 * n)) / denominator
    half = z * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / denominator
    # The interval always holds p (at p = 0 or 1 rounding could leave it a hair outside).
    return max(0.0, min(p, centre - half)), min(1.0, max(p, centre + half))


def mean_interval(values: Sequence[float], z: float = Z_95) -> tuple[float, float]:
    """The 95 % interval (by default) of the mean of ``values``, by the normal approximation
    (mean +- z standard errors, the sample's standard deviation): 2.5 % narrower than
    Student's t interval from 50 values, under 1 % from 200. NaN with fewer than two
    values."""
    if len(values) < 2:
        return math.nan, math.nan
    mean = statistics.fmean(values)
    half = z * statistics.stdev(values) / math.sqrt(len(values))
    return mean - half, mean + half


def summarize(agent: str, map_mode: str, episodes: Sequence[dict[str, Any]]) -> Summary:
    """The table row of one agent's per-episode results (``run_episodes`` dicts)."""
    n = len(episodes)
    successes = sum(bool(e["success"]) for e in episodes)
    low, high = wilson_interval(successes, n)
    steps = sorted(e["steps"] for e in episodes if e["success"])
    if len(steps) >= 2:
        q1, median, q3 = statistics.quantiles(steps, n=4, method="inclusive")
    elif steps:
        q1 = median = q3 = float(steps[0])
    else:
        q1 = median = q3 = math.nan
    succeeded = [e["jar_displacement"] for e in episodes if e["success"]]
    map_mm = [float(e.get("map_score_mm", 0.0)) for e in episodes]
    map_area = [float(e.get("map_score_area", 0.0)) for e in episodes]
    map_mm_low, map_mm_high = mean_interval(map_mm)
    map_area_low, map_area_high = mean_interval(map_area)
    return Summary(
        agent=agent,
        map_mode=map_mode,
        episodes=n,
        successes=successes,
        success_low=low,
        success_high=high,
        steps_median=median,
        steps_q1=q1,
        steps_q3=q3,
        displacement_mm=1000 * statistics.fmean(e["jar_displacement"] for e in episodes),
        success_displacement_mm=1000 * statistics.fmean(succeeded) if succeeded else math.nan,
        max_displacement_mm=1000 * statistics.fmean(e["max_jar_displacement"] for e in episodes),
        tip_rate=statistics.fmean(e["tips"] > 0 for e in episodes),
        iou=statistics.fmean(e["iou"] for e in episodes),
        wrong_claim_rate=statistics.fmean(bool(e.get("wrong_claim", False)) for e in episodes),
        map_score_mm=statistics.fmean(map_mm),
        map_score_iou=statistics.fmean(e.get("map_score_iou", 0.0) for e in episodes),
        map_score_area=statistics.fmean(map_area),
        map_score_mm_low=map_mm_low,
        map_score_mm_high=map_mm_high,
        map_score_area_low=map_area_low,
        map_score_area_high=map_area_high,
    )
