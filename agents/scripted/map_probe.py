"""Scripted baselines for the map task (``tactile_search/MapByTouch-v0``) in the probe action
mode: random probes, greedy mappers on the observed map, and the map oracle.

The greedy mappers the agents run are faces of the core's (``agents.scripted.core_mappers``,
``env_core/src/planner/map_planner.rs``); their rules here in Python (``BeliefVarianceMapper``,
``BeliefOccupancyMapper``) are the reference the core's are pinned to
(``tests/test_map_planner_core.py``), and ``GreedyMapper`` the map oracle's base.

The mappers share the GPIS probe planner's machinery (``BeliefProbePlanner``): its belief of
the finger's swept cells and touched jars, and its candidate probes, those of the core's
grid the wrist and arm can make without coming near a cell that may hold a jar
(``agents.scripted.clearance``). What differs is the weight a probe is chosen by: the sum of
a per-cell weight over the cells within ``PATH_HALF_WIDTH`` of the finger's path (straight
in along the lane, then the turn), cells the finger already swept without touching counted
as nothing (a probe that touched nothing is not chosen again for the same cells), and a
probe once chosen never chosen again (its touch, if any, is already evidence).

- ``BeliefVarianceMapper`` (``map="gpis"``): the GPIS standard deviation, the paper's
  suggestion.
- ``BeliefOccupancyMapper`` (``map="occupancy"``): how unknown each cell of the occupancy grid
  is (1 at P(occupied) = 0.5, 0 at 0 or 1).
- ``MapOracle`` reads the ground truth (``render_state``): per probe, the first point of a
  true jar its finger would meet, worth the score GPIS's error (``score_mean``'s distance
  from zero, capped) summed over the true outline near it.
- ``RandomMapAgent``: uniform probes of the grid, seeded per episode from its first
  observation.
"""

from __future__ import annotations

import zlib
from collections.abc import Callable
from typing import Any, ClassVar

import numpy as np

from agents.scripted.belief_planner import BeliefProbePlanner, Pose, Probe
from agents.scripted.geometry import Geometry
from agents.scripted.search_map import SearchMap
from tactile_search import CupboardSearchEnv

# Half width of the band around the finger's path whose cells a probe's weight sums, m.
PATH_HALF_WIDTH = 0.01
# Occupancy: a cell counts as a jar above this probability and as free below 1 minus it.
OCCUPIED = 0.55


class RandomMapAgent:
    """Uniform probes of the core's grid (lane, depth, sweep), from a generator seeded per
    episode by the first observation's bytes (an episode's probes do not depend on what
    came before it or which slot of a vector env plays it)."""

    name = "random_map"
    env_kwargs: ClassVar[dict[str, str]] = {"action_mode": "probe"}

    def __init__(self, seed: int = 0) -> None:
        self.seed = seed
        self._rng = np.random.default_rng(seed)
        self._sizes: np.ndarray | None = None

    def reset(self, env: CupboardSearchEnv, observation: dict, info: dict) -> None:
        if env.config.action_mode != "probe":
            raise ValueError(
                f"RandomMapAgent needs action_mode='probe', got {env.config.action_mode!r}"
            )
        geometry = env.geometry()
        self._sizes = np.array(
            [len(geometry[k]) for k in ("probe_lanes", "probe_depths", "probe_yaws")]
        )
        digest = zlib.crc32(np.ascontiguousarray(observation["proprio"]).tobytes())
        if "map" in observation:
            digest = zlib.crc32(np.ascontiguousarray(observation["map"]).tobytes(), digest)
        self._rng = np.random.default_rng([self.seed, digest])

    def act(self, observation: dict) -> np.ndarray:
        if self._sizes is None:
            raise RuntimeError("call reset before act")
        return self._rng.integers(0, self._sizes).astype(np.int64)


class GreedyMapper(BeliefProbePlanner):
    """The probe planner's belief and candidates, choosing the probe with the most
    ``cell_weight`` along its finger's path; see the module docstring. Subclasses give
    ``cell_weight`` and the map mode."""

    name = "greedy_mapper"
    map_mode: ClassVar[str] = "gpis"
    env_kwargs: ClassVar[dict[str, str]] = {"map": "gpis", "action_mode": "probe"}

    def __init__(self, cost_offset: float | None = None) -> None:
        """``cost_offset``: None picks the largest weight; a number picks the largest weight
        per (motions + ``cost_offset``)."""
        super().__init__()
        self.cost_offset = cost_offset
        self._tried: set[tuple[int, int, int]] = set()
        self._raw: dict[str, np.ndarray] = {}

    def reset(self, env: CupboardSearchEnv, observation: dict, info: dict) -> None:
        if env.config.map != self.map_mode or "map" not in observation:
            raise ValueError(f"{type(self).__name__} needs map={self.map_mode!r}")
        if env.config.action_mode != "probe":
            raise ValueError(
                f"{type(self).__name__} needs action_mode='probe', got {env.config.action_mode!r}"
            )
        self.geometry = Geometry.from_env(env)
        self._decode_map = self._belief_decoder(env.decode_map)
        self._decode_proprio = env.decode_proprio
        self.belief = SearchMap(self.geometry, self._decode_map(observation["map"]))
        self._probe_motions = env.probe_motions
        self._chosen = None
        self._last_finger = None
        self._tried = set()
        self._remember_touch(self._pose(observation["proprio"]))

    def _belief_decoder(
        self, decode: Callable[[np.ndarray], dict[str, np.ndarray]]
    ) -> Callable[[np.ndarray], dict[str, np.ndarray]]:
        """The decoder the belief reads (GPIS mean and std, m); keeps the raw decoding."""

        def decoded(image: np.ndarray) -> dict[str, np.ndarray]:
            self._raw = decode(image)
            return self._raw

        return decoded

    def cell_weight(self) -> np.ndarray:
        """Per map cell, what a finger passing it is worth, (H, W) >= 0."""
        raise NotImplementedError

    def _path_cells(self, probe: Probe, cells: np.ndarray) -> np.ndarray:
        """Which of ``cells`` lie within ``PATH_HALF_WIDTH`` of the finger's path."""
        return self._covers(probe, cells, PATH_HALF_WIDTH)

    def probe_scores(self, pose: Pose) -> list[tuple[tuple[int, int, int], float]]:
        """Every candidate probe not yet tried and its score."""
        weight = np.where(self.belief.swept, 0.0, self.cell_weight())
        mask = weight > 0
        cells = np.c_[self.belief.xs[mask], self.belief.ys[mask]]
        weights = weight[mask]
        scores = []
        for indices, probe, motions in self._candidates(pose):
            if indices in self._tried:
                continue
            score = float(weights[self._path_cells(probe, cells)].sum())
            if self.cost_offset is not None:
                score /= motions + self.cost_offset
            scores.append((indices, score))
        return scores

    def _choose(self, pose: Pose) -> tuple[int, int, int]:
        best, best_score = None, 0.0
        for indices, score in self.probe_scores(pose):
            if score > best_score:
                best, best_score = indices, score
        if best is None:
            best = self._fallback(pose)
        self._tried.add(best)
        return best

    def _fallback(self, pose: Pose) -> tuple[int, int, int]:
        """Nothing left worth a probe: the first candidate not yet tried, else straight in
        at the middle lane's opening."""
        for indices, _, _ in self._candidates(pose):
            if indices not in self._tried:
                return indices
        g = self.geometry
        return (len(g.probe_lanes) // 2, 0, len(g.probe_yaws) // 2)


class BeliefVarianceMapper(GreedyMapper):
    """Probes where the GPIS standard deviation along the finger's path sums largest."""

    name = "belief_variance_mapper"

    def cell_weight(self) -> np.ndarray:
        return np.asarray(self._raw["std"], dtype=float)


class BeliefOccupancyMapper(GreedyMapper):
    """Probes where the occupancy grid's unknown cells along the finger's path sum largest;
    its belief reads the grid as a map of signed distance (a cell above ``OCCUPIED`` a jar,
    one below 1 - ``OCCUPIED`` free, the rest unknown)."""

    name = "belief_occupancy_mapper"
    map_mode: ClassVar[str] = "occupancy"
    env_kwargs: ClassVar[dict[str, str]] = {"map": "occupancy", "action_mode": "probe"}

    def _belief_decoder(
        self, decode: Callable[[np.ndarray], dict[str, np.ndarray]]
    ) -> Callable[[np.ndarray], dict[str, np.ndarray]]:
        def decoded(image: np.ndarray) -> dict[str, np.ndarray]:
            self._raw = decode(image)
            p = self._raw["occupied"]
            known = np.abs(p - 0.5) >= OCCUPIED - 0.5
            mean = np.where(p >= OCCUPIED, -0.01, np.where(known, 0.03, 0.01))
            std = np.where(known, 0.0, 0.05)
            return {"mean": mean, "std": std}

        return decoded

    def cell_weight(self) -> np.ndarray:
        return 1.0 - 2.0 * np.abs(np.asarray(self._raw["occupied"], dtype=float) - 0.5)


# The oracle: outline points per metre of a true outline, the reach of a touch along it (m),
# and the cap on the score GPIS's error an outline point counts (m).
OUTLINE_SPACING = 0.003
TOUCH_REACH = 0.02
ERROR_CAP = 0.02


class MapOracle(GreedyMapper):
    """Reads the ground truth (``render_state``): each candidate probe (the probe planner's,
    kept clear of jars by the GPIS map) is worth the score GPIS's error summed over the true
    outline within ``TOUCH_REACH`` of the first point of a true jar its finger would meet
    (0 when it meets none); it picks the most per motion. The upper reference."""

    name = "map_oracle"

    def __init__(self, cost_offset: float | None = 15.0) -> None:
        super().__init__(cost_offset=cost_offset)
        self._env: Any = None

    def reset(self, env: CupboardSearchEnv, observation: dict, info: dict) -> None:
        self._env = env
        super().reset(env, observation, info)

    def probe_scores(self, pose: Pose) -> list[tuple[tuple[int, int, int], float]]:
        state = self._env.render_state()
        jars = state["jars"]
        outline = np.concatenate([_outline(jar) for jar in jars])
        g = self.geometry
        # The score GPIS's error at each true outline point (nearest cell).
        j = np.clip(((outline[:, 0] + 0.5 * g.width) / g.cell).astype(int), 0, g.grid_shape[1] - 1)
        i = np.clip((outline[:, 1] / g.cell).astype(int), 0, g.grid_shape[0] - 1)
        error = np.minimum(np.abs(state["score_mean"][i, j]), ERROR_CAP)
        scores = []
        for indices, probe, motions in self._candidates(pose):
            if indices in self._tried:
                continue
            hit = _first_contact(g, probe, jars)
            score = 0.0
            if hit is not None:
                score = float(error[np.hypot(*(outline - hit).T) <= TOUCH_REACH].sum())
            if self.cost_offset is not None:
                score /= motions + self.cost_offset
            scores.append((indices, score))
        return scores


def _outline(jar: dict[str, Any]) -> np.ndarray:
    """Points on a jar's true outline (its footprint at the map's plane), (n, 2)."""
    centre = np.array([jar["x"], jar["y"]])
    h = jar["half_width"]
    if jar["shape"] == "round":
        n = max(8, int(2 * np.pi * h / OUTLINE_SPACING))
        t = np.linspace(0, 2 * np.pi, n, endpoint=False)
        return centre + h * np.c_[np.cos(t), np.sin(t)]
    n = max(2, int(2 * h / OUTLINE_SPACING))
    s = np.linspace(-h, h, n, endpoint=False)
    local = np.concatenate(
        [np.c_[s, -h + 0 * s], np.c_[h + 0 * s, s], np.c_[-s, h + 0 * s], np.c_[-h + 0 * s, -s]]
    )
    c, si = np.cos(jar["yaw"]), np.sin(jar["yaw"])
    return centre + local @ np.array([[c, si], [-si, c]])


def _inside(points: np.ndarray, jar: dict[str, Any], pad: float) -> np.ndarray:
    d = points - np.array([jar["x"], jar["y"]])
    h = jar["half_width"] + pad
    if jar["shape"] == "round":
        return np.hypot(d[:, 0], d[:, 1]) <= h
    c, s = np.cos(jar["yaw"]), np.sin(jar["yaw"])
    lx = c * d[:, 0] + s * d[:, 1]
    ly = -s * d[:, 0] + c * d[:, 1]
    return (np.abs(lx) <= h) & (np.abs(ly) <= h)


def _first_contact(g: Geometry, probe: Probe, jars: list[dict[str, Any]]) -> np.ndarray | None:
    """The first point of a true jar the finger meets along ``probe``'s path (in along the
    lane from outside, then the turn), or None."""
    along = np.linspace(g.joint_offset, g.reach, 12)
    ys = np.arange(g.probe_outside, probe.y + 1e-9, 0.5 * g.cell)
    yaws = -probe.side * np.arange(0.0, probe.angle + 1e-9, g.probe_sweep_rate)
    poses = [(probe.x, y, 0.0) for y in ys] + [(probe.x, probe.y, yaw) for yaw in yaws[1:]]
    pose = np.array(poses)  # (P, 3)
    fx = pose[:, :1] - np.sin(pose[:, 2:]) * along  # (P, A)
    fy = pose[:, 1:2] + np.cos(pose[:, 2:]) * along
    points = np.c_[fx.ravel(), fy.ravel()]
    hit = np.zeros(len(points), dtype=bool)
    for jar in jars:
        hit |= _inside(points, jar, g.finger_half_thickness)
    if not hit.any():
        return None
    return points[int(np.argmax(hit))]  # pose by pose, joint to tip
