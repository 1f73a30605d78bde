"""The scripted surface-following finger (the paper's re-orienting motion, its Fig. 4).

For each jar and each side, the wrist comes in along a clear lane beside the jar, presses
the finger's long edge against the jar's side, then turns and moves so that the finger stays
tangent to the jar while the tangent direction sweeps round it: the contact point slides
over the surface. The plan uses the true layout (as the paper's scripted trajectories do);
the readings are the simulator's finger contacts (points, outward normals, with noise).
Sweeps stop before the wrist or the arm would reach another jar or a wall.

The hand's sizes come from the core (``_core.hand_geometry`` of the scene's configuration,
the joint offset included) and the jars' footprints from the core
(``_core.jar_signed_distance``, ``_core.jar_support``).
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray

from tactile_search import _core
from tactile_search._core import Scene

TOUCH_SPACING = 0.003  # contacts on one jar closer than this are thinned out


@dataclass(frozen=True)
class Hand:
    """The hand's sizes the planner needs, m (from the core)."""

    wrist_half: float
    joint_offset: float
    finger_length: float
    finger_half_thickness: float
    arm_length: float
    start_y: float

    @classmethod
    def of(cls, scene: Scene) -> Hand:
        g = _core.hand_geometry(scene.config)
        return cls(
            wrist_half=g["wrist_half_extent"],
            joint_offset=g["joint_offset"],
            finger_length=g["finger_length"],
            finger_half_thickness=g["finger_half_thickness"],
            arm_length=g["arm_length"],
            start_y=g["hand_start"][1],
        )


def hand_clear(
    pose: tuple[float, float, float],
    jars: dict[str, Any],
    skip: int,
    hand: Hand,
    margin: float = 0.003,
    interior: tuple[float, float] | None = None,
) -> bool:
    """Whether the wrist and arm (and, for jars other than ``skip``, the finger) at ``pose``
    keep ``margin`` from every jar footprint (exact footprints, sampled along the links) and,
    if ``interior = (width, depth)`` is given, the wrist and arm from the side and back walls.
    """
    x, y, yaw = pose
    d = np.array([-np.sin(yaw), np.cos(yaw)])
    wrist = np.array([x, y])
    w = hand.wrist_half
    # Points along the arm's and the finger's centre lines, 2.5 mm apart.
    arm = wrist - np.linspace(-w, hand.arm_length + w, 173)[:, None] * d
    tip = hand.joint_offset + hand.finger_length
    finger = wrist + np.linspace(hand.joint_offset, tip, 41)[:, None] * d
    corner = w * np.sqrt(2.0)
    if interior is not None:
        inside = arm[arm[:, 1] > -corner]
        reach = corner + margin
        if len(inside) and (
            np.max(np.abs(inside[:, 0])) > 0.5 * interior[0] - reach
            or np.max(inside[:, 1]) > interior[1] - reach
        ):
            return False
    if np.min(_core.jar_signed_distance(jars, arm)) < corner + margin:
        return False
    to_finger = _core.jar_signed_distance(jars, finger).min(axis=1)
    others = np.arange(len(to_finger)) != skip
    return not np.any(to_finger[others] < hand.finger_half_thickness + margin)


@dataclass
class TouchLog:
    """Contacts gathered by the finger, and what the run did."""

    points: list[NDArray[np.float64]] = field(default_factory=list)
    normals: list[NDArray[np.float64]] = field(default_factory=list)
    jars: list[NDArray[np.int64]] = field(default_factory=list)
    steps: int = 0
    blocked: int = 0
    sweeps: int = 0

    def record(self, scene: Scene) -> None:
        c = scene.contacts
        if len(c["points"]):
            self.points.append(c["points"])
            self.normals.append(c["normals"])
            self.jars.append(c["jars"])

    def arrays(self) -> dict[str, NDArray]:
        if not self.points:
            return {
                "points": np.zeros((0, 2)),
                "normals": np.zeros((0, 2)),
                "jars": np.zeros(0, dtype=np.int64),
            }
        return {
            "points": np.concatenate(self.points),
            "normals": np.concatenate(self.normals),
            "jars": np.concatenate(self.jars),
        }


def move_to(
    scene: Scene,
    goal: tuple[float, float, float],
    log: TouchLog,
    max_translation: float = 0.005,
    max_yaw: float = 0.05,
) -> bool:
    """Steps the wrist to ``goal`` in bounded steps, recording contacts; False if blocked."""
    x, y, yaw = scene.hand_pose
    delta = np.array(goal) - np.array([x, y, yaw])
    n = int(
        np.ceil(
            max(
                abs(delta[0]) / max_translation,
                abs(delta[1]) / max_translation,
                abs(delta[2]) / max_yaw,
                1e-9,
            )
        )
    )
    for _ in range(n):
        hx, hy, hyaw = scene.hand_pose
        rest = np.array(goal) - np.array([hx, hy, hyaw])
        k = max(
            1.0,
            abs(rest[0]) / max_translation,
            abs(rest[1]) / max_translation,
            abs(rest[2]) / max_yaw,
        )
        report = scene.step(*(rest / k))
        log.steps += 1
        log.record(scene)
        if report["blocked"] is not None:
            log.blocked += 1
            return False
    return True


def sweep_pose(
    jars: dict[str, Any],
    j: int,
    side: int,
    phi: float,
    press: float,
    lever: float,
    hand: Hand,
) -> tuple[float, float, float]:
    """Wrist pose that keeps the finger's long edge tangent to jar ``j`` (pressed by
    ``press``) with outward normal at angle ``phi`` from the jar's ``side`` (+1 right,
    -1 left)."""
    n = np.array([side * np.cos(phi), np.sin(phi)])
    d = np.array([-side * np.sin(phi), np.cos(phi)])  # finger direction, into the cupboard
    support = float(_core.jar_support(jars, n)[j])
    centre = np.asarray(jars["positions"])[j, :2]
    line = centre + (support + hand.finger_half_thickness - press) * n
    wrist = line - (hand.joint_offset + lever) * d
    return float(wrist[0]), float(wrist[1]), float(side * phi)


def follow_surfaces(
    scene: Scene,
    jars: dict[str, Any],
    jar_indices: Iterable[int] | None = None,
    press: float = 0.003,
    levers: Sequence[float] = (0.06, 0.04, 0.08, 0.025),
    back_degrees: float = 75.0,
    front_degrees: float = 30.0,
    step_degrees: float = 5.0,
) -> tuple[dict[str, NDArray], TouchLog]:
    """Runs the scripted surface-following finger over the sides of ``jars`` (the scene's
    jars at reset, ``Scene.jars``); returns its contacts (thinned) and the log.

    For each jar (front to back) and side: retreat out of the cupboard, line up with a clear
    lane beside the jar, reach in to the tangent pose at the jar's side, then re-orient
    through tangent poses sweeping the contact towards the back (up to ``back_degrees``),
    return, sweep towards the front (``front_degrees``), return, and retreat. A sweep stops at
    the first pose whose wrist or arm would come near a jar or whose finger would run into
    another jar, or when a wall blocks the motion.
    """
    hand = Hand.of(scene)
    interior = (scene.cupboard["width"], scene.cupboard["depth"])
    log = TouchLog()
    positions = np.asarray(jars["positions"])
    order = sorted(
        jar_indices if jar_indices is not None else range(len(positions)),
        key=lambda j: positions[j, 1],
    )
    out_y = hand.start_y
    for j in order:
        for side in (1, -1):
            start = sweep_pose(jars, j, side, 0.0, press, levers[0], hand)
            lane_x = start[0] + side * (press + 0.004)
            lane = (lane_x, start[1], 0.0)
            if not hand_clear(lane, jars, -1, hand) or not hand_clear(start, jars, j, hand):
                continue
            # Retreat, line up, reach in along the lane.
            hx, _, _ = scene.hand_pose
            if not move_to(scene, (hx, out_y, 0.0), log, 0.01, 0.1):
                continue
            if not move_to(scene, (lane_x, out_y, 0.0), log, 0.01, 0.1):
                continue
            if not move_to(scene, lane, log, 0.01, 0.1):
                move_to(scene, (lane_x, out_y, 0.0), log, 0.01, 0.1)
                continue
            move_to(scene, start, log, 0.002)
            log.sweeps += 1
            for limit in (back_degrees, -front_degrees):
                sign = 1.0 if limit > 0 else -1.0
                phis = np.radians(np.arange(step_degrees, abs(limit) + 1e-9, step_degrees)) * sign
                reached = [start]
                for phi in phis:
                    # The contact may slide along the finger: the first clear lever wins.
                    poses = [
                        sweep_pose(jars, j, side, float(phi), press, lv, hand) for lv in levers
                    ]
                    pose = next(
                        (p for p in poses if hand_clear(p, jars, j, hand, interior=interior)),
                        None,
                    )
                    if pose is None:
                        break
                    if not move_to(scene, pose, log, 0.003, 0.05):
                        break
                    reached.append(pose)
                for pose in reversed(reached):  # retrace to the start pose
                    move_to(scene, pose, log, 0.003, 0.05)
            move_to(scene, lane, log, 0.005, 0.05)
            move_to(scene, (lane_x, out_y, 0.0), log, 0.01, 0.1)
    return thin_contacts(log.arrays()), log


def thin_contacts(touch: dict[str, NDArray], spacing: float = TOUCH_SPACING) -> dict[str, NDArray]:
    """Greedy thinning: keeps a reading only if no kept reading on the same jar is closer than
    ``spacing`` (the raw stream repeats itself from step to step)."""
    keep: list[int] = []
    points, jars = touch["points"], touch["jars"]
    for i in range(len(points)):
        same = [k for k in keep if jars[k] == jars[i]]
        if same and np.min(np.linalg.norm(points[same] - points[i], axis=1)) < spacing:
            continue
        keep.append(i)
    idx = np.array(keep, dtype=np.int64)
    return {key: value[idx] for key, value in touch.items()}
