"""The identify planner's rules in Python, on ``BeliefProbePlanner``'s belief: the reference
the core's identify planner (``tactile_search._core.IdentifyPlanner``, which
``agents.scripted.identify_planner`` runs) is checked against: the two make the same
actions (``tests/test_probe_planner_core.py``, ``benchmarks.planner_agreement --task
identify``). The strategy and every rule are documented in
``env_core/src/planner/identify_planner.rs``; the constants below are those, chosen on
validation layouts (the first 100 from 1,000,000).

It reads only the observation (the map and proprio, decoded by the core) and the static
settings (geometry, jar sizes), never the ground truth.
"""

from __future__ import annotations

import dataclasses
from typing import ClassVar

import numpy as np

from agents.scripted.belief_planner import BeliefProbePlanner, Pose, Probe, _forward
from tactile_search import CupboardSearchEnv
from tactile_search.envs.observation import PROPRIO

# Two contacts closer than this are one jar's if their estimated centres are, m.
SAME_JAR = 0.03
# A pair of contacts judges the shape only this far apart, m.
MIN_SEPARATION = 0.004
# Flat: the normals turn by less than this share of a round jar's smallest turn.
FLAT_FRACTION = 0.4
# ...and the second contact lies at most this far along the first's normal, m.
FLAT_OFFSET = 0.0025
# Curved: the normals turn by more than this share of a round jar's smallest turn.
CURVED_FRACTION = 0.6
# A round jar fits two contacts when the centres they give it, at its best radius, are
# this close, m.
ROUND_FIT = 0.004
# A contact between these distances along the finger from its joint is on its side, m.
SIDE_CONTACT = (0.04, 0.092)
# A side contact whose normal is this far from perpendicular to the finger (|n . direction|)
# met a corner; one this close to it lay tangent to a smooth surface.
CORNER_TANGENCY = 0.15
SMOOTH_TANGENCY = 0.06
# A clipped contact offset is solved from the other component only where the finger's
# direction has at least this much of it.
WELL_CONDITIONED = 0.3
# Adjacent faces of a square: normals this close to a right angle (rad).
CORNER_TOLERANCE = 0.25
# Inspection probes aim this far (m) from the contacts the jar has, at least...
AIM_MIN = 0.006
# ...and at most.
AIM_MAX = 0.03
# A probe surely touches a jar if its finger comes this far inside the smallest round
# radius of the jar's estimated centre, m.
SURE_MARGIN = 0.004
# The inspected jar's surroundings the finger may enter beyond its largest radius, m.
INSIDE_REACH = 0.01
# Inspection probes aim to touch this far along the finger from its joint (its side), m.
SIDE_AIM = (0.045, 0.085)
# Probes spent on one candidate before moving on.
MAX_INSPECTIONS = 4
# A candidate's estimated centre is at least this much shallower than target_min_depth, m.
DEPTH_SLACK = 0.02
# ...and at least this far behind the nearest surface the camera saw on its ray, m.
SHADOW_DEPTH = 0.01
# With this share of the time left or less, a candidate being touched is claimed.
LAST_CHANCE = 0.06


@dataclasses.dataclass
class JarTrack:
    """The contacts collected on one touched jar, and what they say of its shape."""

    centre: np.ndarray
    points: list[np.ndarray] = dataclasses.field(default_factory=list)
    normals: list[np.ndarray] = dataclasses.field(default_factory=list)
    candidate: bool = False
    inspections: int = 0
    verdict: str | None = None  # "square", "round" or "unknown"
    tangency: list[float | None] = dataclasses.field(default_factory=list)
    tried: set = dataclasses.field(default_factory=set)


def pair_evidence(
    p1: np.ndarray, n1: np.ndarray, p2: np.ndarray, n2: np.ndarray, radii: tuple[float, float]
) -> str | None:
    """What two contacts (points and outward normals) on one jar say of its shape:
    ``"flat"``, ``"curved"`` or None (too close together, or neither). ``radii``: the
    smallest and largest radius of a round jar."""
    d = float(np.hypot(*(p2 - p1)))
    if d < MIN_SEPARATION:
        return None
    turn = float(np.arccos(np.clip(n1 @ n2, -1.0, 1.0)))
    # The least turn a round jar gives for two contacts d apart.
    round_turn = 2.0 * np.arcsin(min(1.0, 0.5 * d / radii[1]))
    # How far apart the centres the two contacts put a round jar at, at its best radius.
    r = np.linspace(radii[0], radii[1], 11)[:, None]
    spread = float(np.min(np.hypot(*((p1 - r * n1) - (p2 - r * n2)).T)))
    mean_normal = (n1 + n2) / max(float(np.hypot(*(n1 + n2))), 1e-9)
    if turn < FLAT_FRACTION * round_turn and abs(float((p2 - p1) @ mean_normal)) < FLAT_OFFSET:
        return "flat"  # one face
    if abs(turn - 0.5 * np.pi) < CORNER_TOLERANCE and spread > 2.0 * ROUND_FIT:
        return "flat"  # adjacent faces, where no round jar fits both contacts
    if turn > CURVED_FRACTION * round_turn and spread <= ROUND_FIT:
        return "curved"
    return None


def shape_verdict(
    points: list[np.ndarray],
    normals: list[np.ndarray],
    tangency: list[float | None],
    radii: tuple[float, float],
) -> str:
    """What a jar's contacts (points, outward normals, and for each made on the finger's
    side its tangency ``|normal . finger direction|``, else None) say of its shape:
    ``"square"`` when a side contact met a corner (tangency above ``CORNER_TANGENCY``) or a
    pair is flat, and no pair is curved; ``"round"`` when a pair is curved, or a side contact
    lay tangent (below ``SMOOTH_TANGENCY``) and nothing says square; else ``"unknown"``."""
    flat = curved = 0
    for i in range(len(points)):
        for j in range(i + 1, len(points)):
            evidence = pair_evidence(points[i], normals[i], points[j], normals[j], radii)
            flat += evidence == "flat"
            curved += evidence == "curved"
    corner = sum(t is not None and t > CORNER_TANGENCY for t in tangency)
    tangent = sum(t is not None and t < SMOOTH_TANGENCY for t in tangency)
    if (corner or flat) and not curved:
        return "square"
    if curved or tangent:
        return "round" if not (corner or flat) else "unknown"
    return "unknown"


class BeliefIdentifyPlanner(BeliefProbePlanner):
    """The identify task's planner in Python; see the module docstring."""

    name = "belief_identify_planner"
    env_kwargs: ClassVar[dict[str, str]] = {"map": "gpis", "action_mode": "probe"}

    def reset(self, env: CupboardSearchEnv, observation: dict, info: dict) -> None:
        if env.config.task != "identify":
            raise ValueError(
                f"BeliefIdentifyPlanner needs task='identify', got {env.config.task!r}"
            )
        self.jars: list[JarTrack] = []
        self._radii = (0.5 * env.config.round_diameter[0], 0.5 * env.config.round_diameter[1])
        self._mean_radius = 0.25 * float(sum(env.config.round_diameter))
        self._sure_radius = 0.5 * float(env.config.round_diameter[0]) - SURE_MARGIN
        self._current: JarTrack | None = None
        super().reset(env, observation, info)

    def act(self, observation: dict) -> np.ndarray:
        pose = self._observe(observation)
        jar = self._record(pose)
        time_left = float(observation["proprio"][PROPRIO["time_left"]])
        if jar is not None and jar.candidate:
            if jar.verdict == "square" or (time_left <= LAST_CHANCE and jar.verdict != "round"):
                return np.array([*self._wait_indices(pose), 1], dtype=np.int64)
        inspect = self._inspection(pose)
        self._chosen = inspect if inspect is not None else self._choose(pose)
        return np.array([*self._chosen, 0], dtype=np.int64)

    # -- the touched jars -------------------------------------------------------------

    def _pose(self, proprio: np.ndarray) -> Pose:
        """As ``BeliefProbePlanner._pose``, but a contact whose offset the observation clipped
        is put back on the finger's side that touches (half its thickness from its centre
        line, against the jar's normal), solved from the unclipped component. Where that
        component says little of the distance along the finger (the finger nearly across
        it), the contact's point is unsure (``self._contact_sure`` False)."""
        pose = super()._pose(proprio)
        self._contact_sure = pose.contact is not None
        if pose.contact is None:
            return pose
        g = self.geometry
        q = self._decode_proprio(proprio)
        offset = np.array([q["contact_dx"], q["contact_dy"]])
        clipped = np.abs(offset) >= 0.999 * g.finger_length
        if not clipped.any():
            return pose
        axis = int(np.flatnonzero(~clipped)[0]) if not clipped.all() else 0
        direction = _forward(pose.yaw + pose.deflection)
        if clipped.all() or abs(direction[axis]) < WELL_CONDITIONED:
            self._contact_sure = False
            return pose
        wrist = np.array([pose.x, pose.y])
        joint = wrist + g.joint_offset * _forward(pose.yaw)
        side = -g.finger_half_thickness * pose.normal
        along = (wrist[axis] + offset[axis] - joint[axis] - side[axis]) / direction[axis]
        along = float(np.clip(along, 0.0, g.finger_length))
        contact = joint + along * direction + side
        return dataclasses.replace(pose, contact=contact)

    def _record(self, pose: Pose) -> JarTrack | None:
        """Adds the observation's contact to its jar's track (a new one for a new jar) and
        judges the jar's shape; the jar, or None without a contact."""
        if pose.contact is None:
            return None
        centre = pose.contact - pose.normal * self._mean_radius
        jar = next(
            (t for t in self.jars if np.hypot(*(t.centre - centre)) <= SAME_JAR),
            None,
        )
        if jar is None:
            jar = JarTrack(centre=centre, candidate=self._may_be_hidden(centre))
            self.jars.append(jar)
        if self._contact_sure:  # an unsure point only names the jar
            jar.points.append(pose.contact)
            jar.normals.append(pose.normal)
            jar.tangency.append(self._tangency(pose))
        jar.verdict = shape_verdict(jar.points, jar.normals, jar.tangency, self._radii)
        self._current = jar
        return jar

    def _tangency(self, pose: Pose) -> float | None:
        """``|normal . finger direction|`` of a contact on the finger's side (between
        ``SIDE_CONTACT`` along it), None for one near its ends: a smooth (round) surface
        touches a finger's side tangentially (0), a square's corner at any angle."""
        g = self.geometry
        direction = _forward(pose.yaw + pose.deflection)
        joint = np.array([pose.x, pose.y]) + g.joint_offset * _forward(pose.yaw)
        along = float((pose.contact - joint) @ direction)
        if not SIDE_CONTACT[0] <= along <= SIDE_CONTACT[1]:
            return None
        return abs(float(pose.normal @ direction))

    def _may_be_hidden(self, centre: np.ndarray) -> bool:
        """Whether a jar centred at ``centre`` may be a hidden one: deep enough and in the
        camera's shadow (every jar the camera sees is round)."""
        g, belief = self.geometry, self.belief
        if centre[1] < g.target_min_depth - DEPTH_SLACK:
            return False
        i = int(np.clip(np.searchsorted(belief.ys[:, 0], centre[1]), 0, belief.ys.shape[0] - 1))
        j = int(np.clip(np.searchsorted(belief.xs[0], centre[0]), 0, belief.xs.shape[1] - 1))
        return bool(belief.behind[i, j] >= SHADOW_DEPTH)

    # -- inspecting a candidate --------------------------------------------------------

    def _inspection(self, pose: Pose) -> tuple[int, int, int] | None:
        """The cheapest clear probe not tried on it yet that, on a circle model of the
        candidate last touched, touches it on the finger's side or some millimetres from its
        contacts; None when there is no candidate to inspect (or no such probe)."""
        jar = self._current
        if jar is None or not jar.candidate or jar.verdict in ("square", "round"):
            return None
        if jar.inspections >= MAX_INSPECTIONS:
            return None
        # While the finger touches, a probe in the same lane at the same depth only turns,
        # which the controller does not do into a touch: it would wait.
        candidates = [
            c
            for c in self._reaching(pose, jar)
            if c[0] not in jar.tried
            and not (pose.contact is not None and self._at_depth(pose, c[1]))
        ]
        if not candidates:
            jar.inspections = MAX_INSPECTIONS
            return None
        probes = [probe for _, probe, _ in candidates]
        sure, touches, points, along = self._first_touches(pose, probes, jar.centre)
        if jar.points:
            known = np.array(jar.points)
            gaps = np.min(np.hypot(*(points[:, None, :] - known[None]).transpose(2, 0, 1)), axis=1)
        else:  # only unsure contacts: any touch of it helps
            gaps = np.full(len(candidates), AIM_MIN)
        motions = np.array([m for _, _, m in candidates])
        on_side = (along >= SIDE_AIM[0]) & (along <= SIDE_AIM[1])
        apart = (gaps >= AIM_MIN) & (gaps <= AIM_MAX)
        # In order: a sure touch on the finger's side (its tangency tells the shape by
        # itself), a sure touch some millimetres from the contacts (a pair), a touch on the
        # side if the jar is where its contacts put it.
        for fits in (sure & on_side, sure & apart, touches & on_side, touches & apart):
            if fits.any():
                break
        else:
            jar.inspections = MAX_INSPECTIONS
            return None
        best = candidates[int(np.argmin(np.where(fits, motions, np.inf)))][0]
        jar.inspections += 1
        jar.tried.add(best)
        return best

    def _reaching(
        self, pose: Pose, jar: JarTrack
    ) -> list[tuple[tuple[int, int, int], Probe, float]]:
        """The grid probes the wrist and arm can make from ``pose`` clear of every cell that may
        hold a jar (``BeliefProbePlanner._candidates``), the finger allowed into the jar being
        inspected (it stops at the touch): its indices, the probe and its motions."""
        g, belief = self.geometry, self.belief
        near = np.hypot(belief.xs - jar.centre[0], belief.ys - jar.centre[1])
        return self._clear_probes(pose, belief.solid(0.0) & (near > g.jar_radius[1] + INSIDE_REACH))

    def _first_touches(
        self, pose: Pose, probes: list[Probe], centre: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """For each probe carried out from ``pose`` as the controller drives it (in along the
        lane, then the turn), with the finger undeflected: whether it surely reaches a jar
        centred at ``centre`` (within the smallest round radius less ``SURE_MARGIN`` of it),
        whether it meets the circle of the mean round radius there, where it first does, on
        that circle (NaN where it does not), and how far along the finger from its joint (m)."""
        g = self.geometry
        r_mean, r_sure = self._mean_radius, self._sure_radius
        x = np.array([p.x for p in probes])
        y = np.array([p.y for p in probes])
        side = np.array([p.side for p in probes])
        angle = np.array([p.angle for p in probes])
        same_lane = np.abs(pose.x - x) <= 1e-4
        start = np.where(same_lane, np.minimum(pose.y, y), g.probe_outside)
        points = np.full((len(probes), 2), np.nan)
        sure = np.zeros(len(probes), dtype=bool)
        # In along the lane: the straight finger's line x; its tip meets the circle's front.
        dx = centre[0] - x
        front = centre[1] - np.sqrt(np.maximum(r_mean**2 - dx**2, 0.0))
        enter = (np.abs(dx) < r_mean) & (front <= y + g.reach) & (front >= start + g.reach)
        sure |= (np.abs(dx) < r_sure) & (front <= y + g.reach - (r_mean - r_sure))
        points[enter] = np.c_[x[enter], front[enter]]
        # The turn at the depth.
        steps = np.arange(0.025, g.probe_max_angle + 1e-9, 0.025)
        yaw = -side[:, None] * steps[None, :]
        fx, fy = -np.sin(yaw), np.cos(yaw)
        jx, jy = x[:, None] + g.joint_offset * fx, y[:, None] + g.joint_offset * fy
        t = np.clip((centre[0] - jx) * fx + (centre[1] - jy) * fy, 0.0, g.finger_length)
        cx, cy = jx + t * fx, jy + t * fy
        distance = np.hypot(cx - centre[0], cy - centre[1])
        within = steps[None, :] <= angle[:, None] + 1e-9
        touching = (distance <= r_mean) & within
        sure |= ((distance <= r_sure) & within).any(axis=1)
        first = np.argmax(touching, axis=1)
        turned = touching.any(axis=1) & ~enter
        rows = np.flatnonzero(turned)
        points[rows] = np.c_[cx[rows, first[rows]], cy[rows, first[rows]]]
        along = np.where(enter, g.finger_length, np.nan)
        along[rows] = t[rows, first[rows]]
        # Onto the circle, along the direction from its centre.
        outward = points - centre
        norm = np.maximum(np.hypot(outward[:, 0], outward[:, 1]), 1e-9)
        points = centre + outward * (r_mean / norm)[:, None]
        return sure & (enter | turned), enter | turned, points, along

    @staticmethod
    def _at_depth(pose: Pose, probe: Probe) -> bool:
        return abs(pose.x - probe.x) <= 1e-4 and abs(pose.y - probe.y) <= 1e-4

    def _wait_indices(self, pose: Pose) -> tuple[int, int, int]:
        """Probe indices for the claim's action (a claim makes no motion): the lane, depth
        and sweep nearest the pose."""
        g = self.geometry
        return (
            int(np.argmin(np.abs(g.probe_lanes - pose.x))),
            int(np.argmin(np.abs(g.probe_depths - pose.y))),
            int(np.argmin(np.abs(g.probe_yaws - pose.yaw))),
        )
