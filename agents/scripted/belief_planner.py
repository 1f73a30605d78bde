"""The GPIS probe planner's rules in Python, on a belief kept in numpy: the base of the
identify planner and the map task's mappers, which add their own rules to it, and the
reference the core's planner (``tactile_search._core.ProbePlanner``, which the search
baseline and the teacher, ``agents.scripted.gpis_probe_planner``, run) is checked against:
the two make the same probes (``tests/test_probe_planner_core.py``).

A scripted searcher that plans on the GPIS map, without ground truth, choosing the probes
of the core's probe action mode.

Strategy. The target hides in the camera's shadow behind other jars, and touching a jar
that is not the target does not end the episode. The planner keeps a belief
(``SearchMap``): the GPIS mean and std decoded from the observation, the camera's shadows,
the cells its finger swept without contact and the jars it touched. It runs on an env with
``action_mode="probe"``: each action is a probe of the core's grid, ``(lane, depth, sweep)``
indices (``geometry()``'s ``probe_lanes``, ``probe_depths``, ``probe_yaws``), which the
core's observation-only controller carries out as the learned agents' probes are (back out
and across to change lanes, straight in along the lane, then the turn; a probe that touches
stops there). A gap between this planner and a learned agent is then the choice of probes,
not the controller.

Per probe it sees one observation, after the probe. Its belief learns what the finger swept
from the probe it chose and the pose the probe ended in, and what it touched from the map
and the contact in the observation. It then scores every probe of the grid the wrist and arm
can make without coming near a cell that may hold a jar (``agents.scripted.clearance``:
seen or touched surfaces, touched jars, shadows not yet swept), with a sweep no wider than
the largest safe turn, by the hiding weight (the GPIS std over the cells where the target's
centre may be) its finger passes over per motion the controller will make (the core counts
them: ``probe_motions``).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable
from typing import Any, ClassVar

import numpy as np

from agents.scripted.clearance import ClearanceField, deepest_clear, safe_angle
from agents.scripted.core_planner import probe_indices
from agents.scripted.geometry import Geometry
from agents.scripted.search_map import SearchMap
from tactile_search import CupboardSearchEnv
from tactile_search.envs.observation import PROPRIO

# Motions added to every probe's cost (favours probes that cover more at once).
COST_OFFSET = 15.0
# A pose is at a lane, or has not turned, within these (m, rad).
LANE_TOL = 1e-4
YAW_TOL = 1e-3


@dataclasses.dataclass(frozen=True)
class Probe:
    """Go in along lane ``x`` to wrist depth ``y``, then turn the finger ``angle`` rad
    towards ``side`` (+1: +x)."""

    x: float
    y: float
    side: float
    angle: float


@dataclasses.dataclass(frozen=True)
class Pose:
    x: float
    y: float
    yaw: float
    deflection: float
    contact: np.ndarray | None
    normal: np.ndarray | None


class BeliefProbePlanner:
    """The GPIS-map searcher choosing the core's probes, in Python; see the module
    docstring."""

    name = "belief_probe_planner"
    #: The settings of the env it runs on (an evaluation builds it with these).
    env_kwargs: ClassVar[dict[str, str]] = {"map": "gpis", "action_mode": "probe"}

    def __init__(self) -> None:
        self.geometry: Geometry | None = None
        self.belief: SearchMap | None = None
        self._chosen: tuple[int, int, int] | None = None
        self._last_finger: tuple[np.ndarray, np.ndarray] | None = None
        self._decode_map: Callable[[np.ndarray], dict[str, np.ndarray]] | None = None
        self._decode_proprio: Callable[[np.ndarray], dict[str, Any]] | None = None

    # -- episode -----------------------------------------------------------------------

    def reset(self, env: CupboardSearchEnv, observation: dict, info: dict) -> None:
        if "map" not in observation:
            raise ValueError("BeliefProbePlanner needs the map observation (map='gpis')")
        if env.config.action_mode != "probe":
            raise ValueError(
                f"BeliefProbePlanner needs action_mode='probe', got {env.config.action_mode!r}"
            )
        self.geometry = Geometry.from_env(env)
        # The core's decoders of this env's observation (its map mode and scales).
        self._decode_map = env.decode_map
        self._decode_proprio = env.decode_proprio
        self.belief = SearchMap(self.geometry, self._decode_map(observation["map"]))
        # The core's count of the controller's motions per probe (from the settings alone).
        self._probe_motions = env.probe_motions
        self._chosen = None
        self._last_finger = None
        self._remember_touch(self._pose(observation["proprio"]))

    def act(self, observation: dict) -> np.ndarray:
        pose = self._observe(observation)
        self._chosen = self._choose(pose)
        return np.array(self._chosen, dtype=np.int64)

    def _observe(self, observation: dict) -> Pose:
        """Takes ``observation`` into the belief (the map, the last probe's swept path, the
        touch) and returns the wrist's pose."""
        if self.belief is None or self.geometry is None:
            raise RuntimeError("call reset before act")
        self.belief.update(self._decode_map(observation["map"]))
        pose = self._pose(observation["proprio"])
        if self._chosen is not None:
            self._sweep_probe_path(self._chosen, pose)
        # Only the finger where it is now: the path since the last observation is swept above.
        self._last_finger = None
        self._remember_touch(pose)
        return pose

    def follow(self, action: np.ndarray) -> None:
        """Takes ``action``, not the probe ``act`` just chose, as the probe the env carries
        out next: the planner then labels states another agent visits (DAgger), its belief
        learning from the probes that agent made. Raises ``ValueError`` for an action that is
        not a probe of the grid."""
        if self.geometry is None:
            raise RuntimeError("call reset before follow")
        g = self.geometry
        sizes = (len(g.probe_lanes), len(g.probe_depths), len(g.probe_yaws))
        self._chosen = probe_indices(action, sizes)

    # -- observation -------------------------------------------------------------------

    def _pose(self, proprio: np.ndarray) -> Pose:
        q = self._decode_proprio(proprio)  # physical quantities, decoded by the core
        x, y, deflection = q["x"], q["y"], q["deflection"]
        # The heading in float32 from the observed (unscaled) sin and cos, as the planner's
        # constants were chosen with on the validation layouts; the core's q["yaw"] is the
        # same angle in f64 and differs in the last bits, which moves one planner episode of
        # 50 by micrometres.
        yaw = float(np.arctan2(proprio[PROPRIO["sin_yaw"]], proprio[PROPRIO["cos_yaw"]]))
        contact = normal = None
        if q["in_contact"]:
            offset = np.array([q["contact_dx"], q["contact_dy"]])
            contact = self._contact_point(x, y, yaw + deflection, yaw, offset)
            normal = np.array([q["normal_x"], q["normal_y"]])
        return Pose(x, y, yaw, deflection, contact, normal)

    def _contact_point(
        self, x: float, y: float, heading: float, yaw: float, offset: np.ndarray
    ) -> np.ndarray:
        """The contact point from its offset to the wrist (m). The observation clips the
        offset at the finger length, which cuts off contacts near the fingertip; those are put
        back on the finger from the unclipped component."""
        g = self.geometry
        point = np.array([x, y]) + offset
        clipped = np.abs(offset) >= 0.999 * g.finger_length
        if not clipped.any():
            return point
        joint = np.array([x, y]) + g.joint_offset * _forward(yaw)
        direction = _forward(heading)
        along = g.finger_length
        for axis in (0, 1):
            if not clipped[axis] and abs(direction[axis]) > 0.3:
                along = float(np.clip((point[axis] - joint[axis]) / direction[axis], 0.0, along))
                break
        return joint + along * direction

    def _remember_touch(self, pose: Pose) -> None:
        """Adds a touched jar, or the finger's sweep since the last observation, to the
        belief."""
        g = self.geometry
        heading = pose.yaw + pose.deflection
        joint = np.array([pose.x, pose.y]) + g.joint_offset * _forward(pose.yaw)
        tip = joint + g.finger_length * _forward(heading)
        if pose.contact is not None:
            self.belief.add_touch(pose.contact, pose.normal)
            self._last_finger = None
        else:
            previous = self._last_finger or (joint, tip)
            for t in np.linspace(0.0, 1.0, 4):
                self.belief.sweep_finger(
                    previous[0] + t * (joint - previous[0]), previous[1] + t * (tip - previous[1])
                )
            self._last_finger = (joint, tip)

    # -- what the last probe swept -----------------------------------------------------

    def _sweep_probe_path(self, chosen: tuple[int, int, int], after: Pose) -> None:
        """Marks as swept what the finger passed on its way through probe ``chosen`` to
        ``after``, as the core's controller drives it: straight along the lane
        to the depth the probe ended at, then the turn from straight to where it ended. The
        cells are those the probe's score counts (``_covers`` at ``sweep_radius``), so a
        probe that touched nothing leaves nothing it was chosen for."""
        g = self.geometry
        lane_x = float(g.probe_lanes[chosen[0]])
        if abs(after.x - lane_x) > LANE_TOL:
            return  # stopped before reaching its lane (the hand blocked): nothing known
        side = 1.0 if after.yaw < 0.0 else -1.0  # a negative yaw turns towards +x
        done = Probe(lane_x, after.y, side, abs(after.yaw))
        xs, ys = self.belief.xs, self.belief.ys
        cells = np.c_[xs.ravel(), ys.ravel()]
        self.belief.mark_swept(
            self._covers(done, cells, self.belief.sweep_radius()).reshape(xs.shape)
        )

    # -- choosing the next probe -------------------------------------------------------

    def _choose(self, pose: Pose) -> tuple[int, int, int]:
        """The grid probe with the most hiding weight under its finger per motion: where the
        target may hide by the strict conditions, or, when no probe the hand can make
        covers any of that, by the relaxed ones (``SearchMap.hiding_weight``)."""
        g = self.geometry
        candidates = self._candidates(pose)
        # Count what a probe that touches nothing clears from the belief (the cells its
        # sweep marks), not the wider ring within a jar radius of the finger: that ring
        # is never cleared, and counting it made a probe worth repeating, one depth up
        # and down the same lane, until the time ran out.
        hit = self.belief.sweep_radius()
        for relaxed in (False, True):
            weight = self.belief.hiding_weight(relaxed=relaxed)
            mask = weight > 0
            cells = np.c_[self.belief.xs[mask], self.belief.ys[mask]]
            weights = weight[mask]
            best, best_score = None, 0.0
            for indices, probe, motions in candidates:
                covered = weights[self._covers(probe, cells, hit)].sum()
                score = covered / (motions + COST_OFFSET)
                if score > best_score:
                    best, best_score = indices, score
            if best is not None:
                return best
        # Nothing left to cover: straight in at the middle lane's opening.
        return (len(g.probe_lanes) // 2, 0, len(g.probe_yaws) // 2)

    def _candidates(self, pose: Pose) -> list[tuple[tuple[int, int, int], Probe, float]]:
        """Every grid probe the wrist and arm can make from ``pose`` without coming near a
        cell that may hold a jar, its sweep no wider than the largest safe turn, except a
        wait: its indices, the probe and the controller's motions to make it."""
        return self._clear_probes(pose, self.belief.solid(0.0))

    def _clear_probes(
        self, pose: Pose, solid_cells: np.ndarray
    ) -> list[tuple[tuple[int, int, int], Probe, float]]:
        """``_candidates`` with the cells the finger must not sweep into given
        (``solid_cells``, a mask of the belief's grid): every grid probe clear of them and of
        every cell that may hold a jar for the wrist and arm, except a wait."""
        g = self.geometry
        field = ClearanceField(self.belief, self.belief.blocked())
        solid = ClearanceField(self.belief, solid_cells)
        reachable = []
        for lane, x in enumerate(g.probe_lanes):
            deepest = deepest_clear(g, field, solid, float(x))
            if deepest is None:
                continue
            for depth, y in enumerate(g.probe_depths):
                if y > deepest + 1e-9:
                    break
                safe = {
                    side: safe_angle(g, field, solid, float(x), float(y), side)
                    for side in (-1.0, 1.0)
                }
                for sweep, yaw in enumerate(g.probe_yaws):
                    side = 1.0 if yaw < 0.0 else -1.0  # a negative yaw turns towards +x
                    angle = abs(float(yaw))
                    if angle > safe[side] + 1e-9:
                        continue
                    probe = Probe(float(x), float(y), side, angle)
                    if self._is_here(pose, probe, float(yaw)):
                        continue  # a wait: the scene does not change while the hand waits
                    reachable.append(((lane, depth, sweep), probe))
        if not reachable:
            return []
        indices = np.array([index for index, _ in reachable], dtype=np.int64)
        motions = self._probe_motions((pose.x, pose.y, pose.yaw), indices)
        return [
            (index, probe, float(count))
            for (index, probe), count in zip(reachable, motions, strict=True)
        ]

    @staticmethod
    def _is_here(pose: Pose, probe: Probe, yaw: float) -> bool:
        """Whether the wrist is already at ``probe``'s end pose."""
        return (
            abs(pose.x - probe.x) <= LANE_TOL
            and abs(pose.y - probe.y) <= LANE_TOL
            and abs(pose.yaw - yaw) <= YAW_TOL
        )

    def _covers(self, probe: Probe, cells: np.ndarray, hit: float) -> np.ndarray:
        """Which candidate centres lie within ``hit`` of the probe's finger path (straight in
        along the lane, then the turn)."""
        g = self.geometry
        dx = (cells[:, 0] - probe.x) * probe.side
        dy = cells[:, 1] - probe.y
        straight = (np.abs(dx) <= hit) & (dy <= g.reach + hit)
        rho = np.hypot(dx, dy)
        phi = np.arctan2(dx, dy)
        beyond = np.clip(phi - np.clip(phi, 0.0, probe.angle), -np.pi / 2, np.pi / 2)
        off_ray = rho * np.sin(np.abs(beyond))
        along_ray = rho * np.cos(beyond)
        swept = (off_ray <= hit) & (along_ray >= g.joint_offset) & (rho <= g.reach + hit)
        return straight | swept


def _forward(yaw: float) -> np.ndarray:
    """The finger's direction at ``yaw`` (0 points along +y)."""
    return np.array([-np.sin(yaw), np.cos(yaw)])
