"""A scripted searcher that plans on the GPIS map, without ground truth.

Strategy. The target hides in the camera's shadow behind other jars, and touching a jar
that is not the target does not end the episode. The planner keeps a belief
(``SearchMap``): the GPIS mean and std decoded from the observation, the camera's shadows,
the cells its finger swept without contact and the jars it touched. It searches by
*probes*: a lane ``x`` from the opening, a wrist depth ``y`` and a side. A probe moves the
hand outside the cupboard (y < 0) to the lane, goes straight in along it to the depth, then
turns the finger towards the side until it touches something or reaches the largest angle
for which the swinging arm stays clear. The lane must keep the wrist (and, while turning,
the wrist's corners and the arm) clear of every cell that may hold a jar: seen or touched
surfaces (low GPIS mean), touched jars and shadows not yet swept. Each probe is scored by the
hiding weight (the GPIS std over the cells where the target's centre may be: in a jar-wide
shadow, deep enough, not swept, not a touched jar) that its finger passes within a jar
radius of, over its cost in steps. On a contact (a non-target jar, else the episode would
have ended) the jar is remembered and the next probe is planned; before leaving a lane the
hand turns back and backs out, so the wrist and arm only move through space they came in by.

Execution is a small state machine whose phase follows from the pose and the current probe:
``UNTURN`` (yaw back to 0), ``RETREAT`` (back out of the cupboard), ``SHIFT`` (lateral move
outside), ``ENTER`` (straight in along the lane), ``SWEEP`` (turn the finger).
"""

from __future__ import annotations

import dataclasses
import enum
from collections.abc import Callable
from typing import Any

import numpy as np

from agents.scripted.geometry import Geometry
from agents.scripted.search_map import SearchMap, distance_to
from tactile_search import CupboardSearchEnv
from tactile_search.envs.observation import PROPRIO

# Clearance kept between the wrist or arm and a cell that may hold a jar, m.
MARGIN = 0.004
# Yaw per step while sweeping, rad.
SWEEP_RATE = 0.05
# Largest sweep angle, rad.
MAX_SWEEP = 1.0
# Lane spacing and depth spacing of the probes, m.
LANE_STEP = 0.01
DEPTH_STEP = 0.02
# Steps added to every probe's cost (favours probes that cover more at once).
COST_OFFSET = 15.0
# Tolerances on position (m) and yaw (rad) for "arrived".
POSITION_TOL = 1e-4
YAW_TOL = 1e-3
# Extra rows and columns of the clearance field beyond the map (outside the cupboard).
PAD_CELLS = 10


class Phase(enum.Enum):
    UNTURN = "unturn"
    RETREAT = "retreat"
    SHIFT = "shift"
    ENTER = "enter"
    SWEEP = "sweep"


@dataclasses.dataclass(frozen=True)
class Probe:
    """Go in along lane ``x`` to wrist depth ``y``, then turn the finger ``angle`` rad
    towards ``side`` (+1: +x)."""

    x: float
    y: float
    side: float
    angle: float
    score: float = 0.0


@dataclasses.dataclass(frozen=True)
class Pose:
    x: float
    y: float
    yaw: float
    deflection: float
    contact: np.ndarray | None
    normal: np.ndarray | None


class ClearanceField:
    """Distance to the nearest blocked cell on the map padded beyond the cupboard (where the
    side walls block and the space outside the opening is free), by nearest-cell lookup."""

    def __init__(self, belief: SearchMap, blocked: np.ndarray) -> None:
        g = belief.geometry
        h, w = g.grid_shape
        self.cell = g.cell
        self.x0 = -0.5 * g.width - PAD_CELLS * g.cell
        self.y0 = -PAD_CELLS * g.cell
        xs = self.x0 + (np.arange(w + 2 * PAD_CELLS) + 0.5) * g.cell
        ys = self.y0 + (np.arange(h + PAD_CELLS) + 0.5) * g.cell
        gx, gy = np.meshgrid(xs, ys)
        padded = np.zeros(gx.shape, dtype=bool)
        padded[PAD_CELLS:, PAD_CELLS : PAD_CELLS + w] = blocked
        padded |= (np.abs(gx) > 0.5 * g.width) & (gy > 0.0)
        self.distance = distance_to(padded, g.cell)

    def at(self, x: np.ndarray, y: np.ndarray) -> np.ndarray:
        j = np.floor((x - self.x0) / self.cell).astype(int)
        i = np.floor((y - self.y0) / self.cell).astype(int)
        rows, cols = self.distance.shape
        inside = (i >= 0) & (i < rows) & (j >= 0) & (j < cols)
        out = np.full(np.shape(x), np.inf)
        out[inside] = self.distance[i[inside], j[inside]]
        return out


class GpisPlanner:
    """The GPIS-map searcher; see the module docstring."""

    name = "gpis_planner"

    def __init__(self) -> None:
        self.geometry: Geometry | None = None
        self.belief: SearchMap | None = None
        self.probe: Probe | None = None
        self.phase: Phase | None = None
        self._was_in_contact = False
        self._last_finger: tuple[np.ndarray, np.ndarray] | None = None
        self._decode_map: Callable[[np.ndarray], dict[str, np.ndarray]] | None = None
        self._decode_proprio: Callable[[np.ndarray], dict[str, Any]] | None = None

    # -- episode -----------------------------------------------------------------------

    def reset(self, env: CupboardSearchEnv, observation: dict, info: dict) -> None:
        if "map" not in observation:
            raise ValueError("GpisPlanner needs the map observation (map='gpis')")
        self.geometry = Geometry.from_env(env)
        # The core's decoders of this env's observation (its map mode and scales).
        self._decode_map = env.decode_map
        self._decode_proprio = env.decode_proprio
        self.belief = SearchMap(self.geometry, self._decode_map(observation["map"]))
        self.probe = None
        self.phase = None
        self._was_in_contact = False
        self._last_finger = None

    def act(self, observation: dict) -> np.ndarray:
        if self.belief is None or self.geometry is None:
            raise RuntimeError("call reset before act")
        self.belief.update(self._decode_map(observation["map"]))
        pose = self._pose(observation["proprio"])
        self._remember_touch(pose)
        if self.probe is None:
            self.probe = self._plan(pose)
        action, done = self._drive(pose, self.probe)
        if done:
            self.probe = self._plan(pose)
            action, _ = self._drive(pose, self.probe)
        return np.clip(action, -1.0, 1.0).astype(np.float32)

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
        """Adds a touched jar, or the finger's sweep since the last step, to the belief; a
        new contact ends the current probe."""
        g = self.geometry
        heading = pose.yaw + pose.deflection
        joint = np.array([pose.x, pose.y]) + g.joint_offset * _forward(pose.yaw)
        tip = joint + g.finger_length * _forward(heading)
        if pose.contact is not None:
            self.belief.add_touch(pose.contact, pose.normal)
            if not self._was_in_contact:
                self.probe = None
            self._last_finger = None
        else:
            previous = self._last_finger or (joint, tip)
            for t in np.linspace(0.0, 1.0, 4):
                self.belief.sweep_finger(
                    previous[0] + t * (joint - previous[0]), previous[1] + t * (tip - previous[1])
                )
            self._last_finger = (joint, tip)
        self._was_in_contact = pose.contact is not None

    # -- planning ----------------------------------------------------------------------

    def _plan(self, pose: Pose) -> Probe:
        weight = self.belief.hiding_weight()
        if not weight.any():
            weight = self.belief.hiding_weight(relaxed=True)
        field = ClearanceField(self.belief, self.belief.blocked())
        solid = ClearanceField(self.belief, self.belief.solid(0.0))
        best = Probe(self.geometry.start[0], self.geometry.start[1], 1.0, 0.0, -1.0)
        mask = weight > 0
        cells = np.c_[self.belief.xs[mask], self.belief.ys[mask]]
        weights = weight[mask]
        for probe in self._probes(field, solid):
            covered = weights[self._covers(probe, cells)].sum()
            score = covered / (self._cost(pose, probe) + COST_OFFSET)
            if score > best.score:
                best = dataclasses.replace(probe, score=score)
        return best

    def _probes(self, field: ClearanceField, solid: ClearanceField) -> list[Probe]:
        """Every lane, depth and side the wrist and arm can reach without coming near a
        cell that may hold a jar, with the largest safe sweep angle."""
        g = self.geometry
        edge = 0.5 * g.width - g.wrist_half_extent - MARGIN - g.cell
        lanes = np.arange(-edge, edge + 1e-9, LANE_STEP)
        probes = []
        for x in lanes:
            deepest = self._deepest_clear(field, solid, x)
            if deepest is None:
                continue
            depths = np.arange(deepest, 0.0, -DEPTH_STEP)
            for y in depths:
                for side in (-1.0, 1.0):
                    angle = self._safe_angle(field, solid, x, y, side)
                    probes.append(Probe(float(x), float(y), side, angle))
        return probes

    def _deepest_clear(
        self, field: ClearanceField, solid: ClearanceField, x: float
    ) -> float | None:
        """The deepest wrist depth along lane ``x`` the wrist reaches without coming near a
        cell that may hold a jar, the fingertip ahead clear of seen jars; None if the lane is
        blocked at the opening."""
        g = self.geometry
        ys = np.arange(-g.wrist_half_extent, g.depth, 0.5 * g.cell)
        lane = np.full(ys.shape, x)
        wrist_room = g.wrist_half_extent + MARGIN + 0.5 * g.cell
        clear = field.at(lane, ys + g.wrist_half_extent) >= wrist_room
        clear &= field.at(lane, ys) >= wrist_room
        # The fingertip ahead must not run into a seen jar either.
        clear &= solid.at(lane, ys + g.reach) >= 0.5 * g.cell
        stop = len(ys) if clear.all() else int(np.argmin(clear))
        return None if stop == 0 else ys[stop - 1]

    def _safe_angle(
        self, field: ClearanceField, solid: ClearanceField, x: float, y: float, side: float
    ) -> float:
        """Largest turn towards ``side`` at wrist ``(x, y)`` keeping the wrist's corners and
        the arm clear, and stopping where the finger would meet a seen jar."""
        g = self.geometry
        angles = np.arange(SWEEP_RATE, MAX_SWEEP + 1e-9, SWEEP_RATE)
        wrist_radius = np.sqrt(2.0) * g.wrist_half_extent + MARGIN + 0.5 * g.cell
        arm_room = g.arm_half_width + MARGIN + 0.5 * g.cell
        along = np.arange(g.wrist_half_extent, g.wrist_half_extent + g.arm_length, g.cell)
        finger = np.linspace(g.joint_offset + 0.02, g.reach, 8)
        if field.at(np.array([x]), np.array([y]))[0] < wrist_radius:
            return 0.0
        yaws = -side * angles
        forward = np.stack([-np.sin(yaws), np.cos(yaws)])  # (2, A)
        ax = x - forward[0][:, None] * along
        ay = y - forward[1][:, None] * along
        arm_clear = (field.at(ax, ay) >= arm_room) | (ay <= -g.arm_half_width - g.cell)
        arm_ok = arm_clear.all(axis=1)
        fx = x + forward[0][:, None] * finger
        fy = y + forward[1][:, None] * finger
        finger_free = (solid.at(fx, fy) >= 0.5 * g.cell).all(axis=1)
        # The turn stops at the first angle the arm cannot take, or just after the finger
        # meets a seen jar.
        safe = np.cumprod(arm_ok).astype(bool)
        reached = np.cumprod(np.r_[True, finger_free[:-1]]).astype(bool)
        ok = safe & reached
        return float(angles[ok][-1]) if ok.any() else 0.0

    def _covers(self, probe: Probe, cells: np.ndarray, hit: float | None = None) -> np.ndarray:
        """Which candidate centres lie within ``hit`` (default the smallest jar radius) of the
        probe's finger path."""
        g = self.geometry
        hit = g.jar_radius[0] if hit is None else hit
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

    def _cost(self, pose: Pose, probe: Probe) -> float:
        g = self.geometry
        step = g.max_step_translation
        turn = abs(pose.yaw) / SWEEP_RATE + probe.angle / SWEEP_RATE
        if abs(pose.x - probe.x) < 0.5 * LANE_STEP:
            return turn + abs(pose.y - probe.y) / step
        out_y = min(pose.y, g.start[1])
        return (
            turn + (pose.y - out_y) / step + abs(pose.x - probe.x) / step + (probe.y - out_y) / step
        )

    # -- execution ---------------------------------------------------------------------

    def _drive(self, pose: Pose, probe: Probe) -> tuple[np.ndarray, bool]:
        """This step's action towards ``probe`` and whether the probe is finished."""
        g = self.geometry
        step, turn = g.max_step_translation, g.max_step_yaw
        outside = g.start[1]
        at_lane = abs(pose.x - probe.x) <= POSITION_TOL
        at_depth = abs(pose.y - probe.y) <= POSITION_TOL
        if not (at_lane and at_depth):
            if abs(pose.yaw) > YAW_TOL:
                self.phase = Phase.UNTURN
                return np.array([0.0, 0.0, -pose.yaw / turn]), False
            if not at_lane:
                if pose.y > outside + POSITION_TOL:
                    self.phase = Phase.RETREAT
                    return np.array([0.0, (outside - pose.y) / step, 0.0]), False
                self.phase = Phase.SHIFT
                return np.array([(probe.x - pose.x) / step, 0.0, 0.0]), False
            self.phase = Phase.ENTER
            return np.array([0.0, (probe.y - pose.y) / step, 0.0]), False
        self.phase = Phase.SWEEP
        goal = -probe.side * probe.angle
        if abs(goal - pose.yaw) <= YAW_TOL:
            return np.zeros(3), True
        delta = np.clip(goal - pose.yaw, -SWEEP_RATE, SWEEP_RATE)
        return np.array([0.0, 0.0, delta / turn]), False


def _forward(yaw: float) -> np.ndarray:
    """The finger's direction at ``yaw`` (0 points along +y)."""
    return np.array([-np.sin(yaw), np.cos(yaw)])
