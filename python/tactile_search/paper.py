"""The paper's figures (Figs. 3-9) and a reconstruction table, from the simulated cupboard.

Everything here runs the real scene (``tactile_search._core.Scene``: rapier3d physics, ray-cast
depth camera, compliant finger) and the real GPIS (``tactile_search.Gpis``); nothing is
synthetic except the Fig. 9 timing rows, which are random points as in
``benchmarks/gpis_append.py``.

- Depth: the first look's noisy 2D slice (value rows, f = 0, noise = the camera's sigma),
  without the points on the cupboard's walls (within ``WALL_CLEARANCE`` of them).
- Touch: a scripted surface-following finger (the paper's re-orienting motion, Fig. 4). For
  each jar and each side, the wrist comes in along a clear lane beside the jar, presses the
  finger's long edge against the jar's side, then turns and moves so that the finger stays
  tangent to the jar while the tangent direction sweeps round it: the contact point slides
  over the surface. The plan uses the true layout (as the paper's scripted trajectories do);
  the readings are the simulator's finger contacts (points, outward normals, with noise).
  Sweeps stop before the wrist or the arm would reach another jar or a wall.
- Priors: a constant mean (0 or positive), the paper's circle prior (four contacts on a
  circle of 0.03 m or 0.2 m diameter) at each depth cluster, and depth free-space points.
  Circle centres: the slice is split into clusters (single linkage, 12 mm); each cluster's
  centroid is pushed away from the camera along the camera ray by the circle's radius, so
  the circle's front lies on the seen surface; the centre is clamped so the circle fits in
  the map.
- Metrics (on the map grid, square cells, over the cupboard interior in the slice plane):
  IoU of the interior (mean < 0) against the true footprints (cell centres inside a jar at
  reset), and the mean distance from the true outlines (64 samples per jar, every jar,
  hidden ones included) to the zero level set of the mean (marching-squares segments with
  linear interpolation), each sample capped at ``MISS_DISTANCE`` (a map with no zero level
  set scores the cap). As that direction does not see spurious surfaces, the table also gives
  the reverse: the mean distance from the zero level set to the nearest true outline.

CLI: ``python -m tactile_search.paper --out docs/paper [--seeds N] [--tiny]``.
"""

from __future__ import annotations

import argparse
import csv
import statistics
import time
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from tactile_search import Gpis
from tactile_search._core import Scene
from tactile_search.demo import Jar

# Hand geometry at the scene's defaults (env_core/src/scene/hand.rs and config.rs).
WRIST_HALF = 0.015
JOINT_OFFSET = 0.017  # wrist centre to finger joint
FINGER_LENGTH = 0.10
FINGER_HALF_THICKNESS = 0.003
ARM_LENGTH = 0.40
HAND_START_Y = -0.125

CELL = 0.005  # grid cell side (m) of the table's maps
MISS_DISTANCE = 0.05  # cap of one outline sample's distance (m)
OUTLINE_SAMPLES = 64
DEPTH_NOISE_LEVELS = (0.001, 0.002, 0.005)
DEFAULT_DEPTH_NOISE = 0.002
TOUCH_NOISE_STD = 0.0005
TOUCH_NORMAL_NOISE_STD = 0.05
TOUCH_SPACING = 0.003  # contacts on one jar closer than this are thinned out
POSITIVE_MEAN = 0.01
FREE_SPACE_OFFSET = 0.01
SHAPES = ("round", "square")
# Depth points this close to the side and back walls are the walls (jars keep 8 mm off them);
# the map is of the jars, so they are dropped.
WALL_CLEARANCE = 0.005


# --------------------------------------------------------------------------------------------
# Priors


@dataclass(frozen=True)
class PriorOption:
    """How a map is started: a constant mean, circle priors, depth free-space points."""

    name: str
    prior_mean: float = 0.0
    circle_diameter: float | None = None
    free_space: bool = False


PRIOR_OPTIONS = (
    PriorOption("mean 0"),
    PriorOption(f"mean +{POSITIVE_MEAN:g}", prior_mean=POSITIVE_MEAN),
    PriorOption(f"mean +{5 * POSITIVE_MEAN:g}", prior_mean=5 * POSITIVE_MEAN),
    PriorOption("circle 0.03", circle_diameter=0.03),
    PriorOption("circle 0.2", circle_diameter=0.2),
    PriorOption(f"circle 0.03 + mean +{POSITIVE_MEAN:g}", POSITIVE_MEAN, 0.03),
    PriorOption(f"free space + mean +{POSITIVE_MEAN:g}", POSITIVE_MEAN, None, True),
)


def cluster_points(points: NDArray[np.float64], link: float = 0.012) -> list[NDArray[np.int64]]:
    """Single-linkage clusters of ``(N, 2)`` points (neighbours closer than ``link``)."""
    n = len(points)
    parent = np.arange(n)

    def root(i: int) -> int:
        while parent[i] != i:
            parent[i] = parent[parent[i]]
            i = parent[i]
        return i

    if n:
        d = np.linalg.norm(points[:, None, :] - points[None, :, :], axis=-1)
        for i, j in zip(*np.nonzero(np.triu(d < link, k=1)), strict=True):
            parent[root(i)] = root(j)
    roots = np.array([root(i) for i in range(n)], dtype=np.int64)
    return [np.flatnonzero(roots == r) for r in np.unique(roots)]


def circle_centres(
    slice_points: NDArray[np.float64],
    camera_xy: NDArray[np.float64],
    diameter: float,
    bounds: tuple[tuple[float, float], tuple[float, float]],
    min_points: int = 3,
) -> NDArray[np.float64]:
    """One circle-prior centre per depth cluster: the centroid pushed back by the radius."""
    radius = 0.5 * diameter
    (x0, x1), (y0, y1) = bounds
    margin = radius + 1e-4
    centres = []
    for members in cluster_points(slice_points):
        if len(members) < min_points:
            continue
        centroid = slice_points[members].mean(axis=0)
        ray = centroid - camera_xy
        centre = centroid + radius * ray / np.linalg.norm(ray)
        centre = np.array(
            [
                np.clip(centre[0], x0 + margin, x1 - margin),
                np.clip(centre[1], y0 + margin, y1 - margin),
            ]
        )
        centres.append(centre)
    return np.array(centres).reshape(-1, 2)


def start_map(
    option: PriorOption,
    depth: NDArray[np.float64],
    depth_noise: float,
    camera_xy: NDArray[np.float64],
    bounds: tuple[tuple[float, float], tuple[float, float]],
    shape: tuple[int, int],
) -> Gpis:
    """The depth-only map (the prior) under ``option``."""
    gpis = Gpis(bounds, shape, prior_mean=option.prior_mean)
    depth = depth[in_bounds(depth, bounds, WALL_CLEARANCE)]
    gpis.add_values(depth, noise_std=max(depth_noise, 1e-3))
    if option.circle_diameter is not None:
        for centre in circle_centres(depth, camera_xy, option.circle_diameter, bounds):
            gpis.add_circle_prior(centre, diameter=option.circle_diameter)
    if option.free_space:
        towards = camera_xy - depth
        towards /= np.linalg.norm(towards, axis=-1, keepdims=True)
        free = depth + FREE_SPACE_OFFSET * towards
        keep = in_bounds(free, bounds)
        gpis.add_values(
            free[keep],
            np.full(int(keep.sum()), FREE_SPACE_OFFSET),
            noise_std=2 * max(depth_noise, 1e-3),
        )
    return gpis


def in_bounds(
    points: NDArray[np.float64],
    bounds: tuple[tuple[float, float], tuple[float, float]],
    wall_clearance: float = 0.0,
) -> NDArray[np.bool_]:
    """Points strictly inside ``bounds``, and at least ``wall_clearance`` from the side and
    back walls (x0, x1, y1; the front y0 is the open side)."""
    (x0, x1), (y0, y1) = bounds
    c = wall_clearance
    return (
        (points[:, 0] > x0 + c)
        & (points[:, 0] < x1 - c)
        & (points[:, 1] > y0)
        & (points[:, 1] < y1 - c)
    )


def add_touch(gpis: Gpis, touch: dict[str, NDArray]) -> int:
    """Adds the (thinned) contacts; returns the number of rows added."""
    points, normals = touch["points"], touch["normals"]
    keep = in_bounds(points, gpis.bounds)
    if not keep.any():
        return 0
    return gpis.add_contacts(
        points[keep],
        normals[keep],
        noise_std=TOUCH_NOISE_STD,
        normal_noise_std=TOUCH_NORMAL_NOISE_STD,
    )


# --------------------------------------------------------------------------------------------
# Metrics


def jars_of(scene: Scene) -> list[Jar]:
    """The scene's jar footprints at reset as ``demo.Jar`` outlines (square: side, yaw)."""
    jars = scene.jars
    out = []
    for shape, position, half, yaw in zip(
        jars["shapes"], jars["positions"], jars["half_widths"], jars["yaws"], strict=True
    ):
        out.append(
            Jar(
                (float(position[0]), float(position[1])),
                2 * float(half),
                shape == "square",
                float(yaw),
            )
        )
    return out


def footprint_mask(centres: NDArray[np.float64], jars: Sequence[Jar]) -> NDArray[np.bool_]:
    """True where a point of ``(..., 2)`` lies inside any jar."""
    flat = centres.reshape(-1, 2)
    inside = np.zeros(len(flat), dtype=bool)
    for jar in jars:
        inside |= jar.signed_distance(flat) < 0.0
    return inside.reshape(centres.shape[:-1])


def interior_iou(mean: NDArray[np.float64], truth: NDArray[np.bool_]) -> float:
    """IoU of ``mean < 0`` against the boolean ``truth`` (same shape); 1 if both are empty."""
    estimate = mean < 0.0
    union = np.count_nonzero(estimate | truth)
    return np.count_nonzero(estimate & truth) / union if union else 1.0


def zero_level_segments(
    mean: NDArray[np.float64], centres: NDArray[np.float64]
) -> NDArray[np.float64]:
    """The zero level set of the grid ``mean`` as ``(S, 2, 2)`` line segments (marching
    squares with linear interpolation, by ``contourpy``); ``centres`` is ``(H, W, 2)``."""
    import contourpy

    generator = contourpy.contour_generator(
        centres[..., 0], centres[..., 1], mean, line_type=contourpy.LineType.Separate
    )
    segments = [
        np.stack([line[:-1], line[1:]], axis=1) for line in generator.lines(0.0) if len(line) > 1
    ]
    return np.concatenate(segments) if segments else np.zeros((0, 2, 2))


def distance_to_segments(
    points: NDArray[np.float64], segments: NDArray[np.float64]
) -> NDArray[np.float64]:
    """Distance from each of ``(N, 2)`` points to the nearest of ``(S, 2, 2)`` segments."""
    best = np.full(len(points), np.inf)
    for chunk in np.array_split(segments, len(segments) // 1024 + 1):
        if not len(chunk):
            continue
        a, b = chunk[:, 0], chunk[:, 1]
        ab = b - a
        length2 = np.maximum(np.einsum("sk,sk->s", ab, ab), 1e-30)
        ap = points[:, None, :] - a[None]
        t = np.clip(np.einsum("nsk,sk->ns", ap, ab) / length2, 0.0, 1.0)
        nearest = a[None] + t[..., None] * ab[None]
        best = np.minimum(best, np.linalg.norm(points[:, None] - nearest, axis=-1).min(axis=1))
    return best


def outline_distance(
    mean: NDArray[np.float64],
    centres: NDArray[np.float64],
    jars: Sequence[Jar],
    samples: int = OUTLINE_SAMPLES,
    cap: float = MISS_DISTANCE,
) -> float:
    """Mean over true outline samples of the distance to the zero level set (each capped)."""
    outline = np.concatenate([jar.outline(samples) for jar in jars])
    segments = zero_level_segments(mean, centres)
    if len(segments) == 0:
        return cap
    return float(np.mean(np.minimum(distance_to_segments(outline, segments), cap)))


def spurious_distance(
    mean: NDArray[np.float64],
    centres: NDArray[np.float64],
    jars: Sequence[Jar],
    cap: float = MISS_DISTANCE,
) -> float:
    """The reverse direction: mean over the zero level set's segment midpoints of the distance
    to the nearest true outline (each capped); ``cap`` if there is no zero level set."""
    segments = zero_level_segments(mean, centres)
    if len(segments) == 0:
        return cap
    mid = segments.mean(axis=1)
    d = np.min([np.abs(jar.signed_distance(mid)) for jar in jars], axis=0)
    return float(np.mean(np.minimum(d, cap)))


# --------------------------------------------------------------------------------------------
# The scripted surface-following finger


def support(jar: Jar, normal: NDArray[np.float64]) -> float:
    """Support distance of the jar's footprint along a unit ``normal`` (from its centre)."""
    if not jar.square:
        return 0.5 * jar.size
    c, s = np.cos(jar.yaw), np.sin(jar.yaw)
    u, v = np.array([c, s]), np.array([-s, c])
    return 0.5 * jar.size * (abs(normal @ u) + abs(normal @ v))


def hand_clear(
    pose: tuple[float, float, float],
    jars: Sequence[Jar],
    skip: int,
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
    # Points along the arm's and the finger's centre lines, 2.5 mm apart.
    arm = wrist - np.linspace(-WRIST_HALF, ARM_LENGTH + WRIST_HALF, 173)[:, None] * d
    finger = wrist + np.linspace(JOINT_OFFSET, JOINT_OFFSET + FINGER_LENGTH, 41)[:, None] * d
    if interior is not None:
        inside = arm[arm[:, 1] > -WRIST_HALF * np.sqrt(2.0)]
        reach = WRIST_HALF * np.sqrt(2.0) + margin
        if len(inside) and (
            np.max(np.abs(inside[:, 0])) > 0.5 * interior[0] - reach
            or np.max(inside[:, 1]) > interior[1] - reach
        ):
            return False
    for k, jar in enumerate(jars):
        if np.min(jar.signed_distance(arm)) < WRIST_HALF * np.sqrt(2.0) + margin:
            return False
        if k != skip and np.min(jar.signed_distance(finger)) < FINGER_HALF_THICKNESS + margin:
            return False
    return True


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
    jar: Jar, side: int, phi: float, press: float, lever: float
) -> tuple[float, float, float]:
    """Wrist pose that keeps the finger's long edge tangent to ``jar`` (pressed by ``press``)
    with outward normal at angle ``phi`` from the jar's ``side`` (+1 right, -1 left)."""
    n = np.array([side * np.cos(phi), np.sin(phi)])
    d = np.array([-side * np.sin(phi), np.cos(phi)])  # finger direction, into the cupboard
    line = np.asarray(jar.centre) + (support(jar, n) + FINGER_HALF_THICKNESS - press) * n
    wrist = line - (JOINT_OFFSET + lever) * d
    return float(wrist[0]), float(wrist[1]), float(side * phi)


def follow_surfaces(
    scene: Scene,
    jar_indices: Iterable[int] | None = None,
    press: float = 0.003,
    levers: Sequence[float] = (0.06, 0.04, 0.08, 0.025),
    back_degrees: float = 75.0,
    front_degrees: float = 30.0,
    step_degrees: float = 5.0,
) -> tuple[dict[str, NDArray], TouchLog]:
    """Runs the scripted surface-following finger over the jars' sides; returns its contacts.

    For each jar (front to back) and side: retreat out of the cupboard, line up with a clear
    lane beside the jar, reach in to the tangent pose at the jar's side, then re-orient
    through tangent poses sweeping the contact towards the back (up to ``back_degrees``),
    return, sweep towards the front (``front_degrees``), return, and retreat. A sweep stops at
    the first pose whose wrist or arm would come near a jar or whose finger would run into
    another jar, or when a wall blocks the motion. Returns the raw readings (points, normals,
    jars) and the log.
    """
    jars = jars_of(scene)
    interior = (scene.cupboard["width"], scene.cupboard["depth"])
    log = TouchLog()
    order = sorted(
        jar_indices if jar_indices is not None else range(len(jars)),
        key=lambda j: jars[j].centre[1],
    )
    out_y = HAND_START_Y
    for j in order:
        jar = jars[j]
        for side in (1, -1):
            start = sweep_pose(jar, side, 0.0, press, levers[0])
            lane_x = start[0] + side * (press + 0.004)
            lane = (lane_x, start[1], 0.0)
            if not hand_clear(lane, jars, skip=-1) or not hand_clear(start, jars, skip=j):
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
                    poses = [sweep_pose(jar, side, float(phi), press, lv) for lv in levers]
                    pose = next(
                        (p for p in poses if hand_clear(p, jars, skip=j, interior=interior)), None
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


# --------------------------------------------------------------------------------------------
# Experiments


def scene_config(shape: str, depth_noise: float) -> dict[str, object]:
    """All-round or all-square jars (the target too), with the given depth noise."""
    return {
        "round_fraction": 1.0 if shape == "round" else 0.0,
        "target_shape": shape,
        "depth_noise_std": depth_noise,
    }


def map_bounds(scene: Scene) -> tuple[tuple[float, float], tuple[float, float]]:
    """The cupboard interior in the slice plane."""
    c = scene.cupboard
    return (-0.5 * c["width"], 0.5 * c["width"]), (0.0, c["depth"])


def grid_shape(
    bounds: tuple[tuple[float, float], tuple[float, float]], cell: float
) -> tuple[int, int]:
    """(H, W) of a grid of square cells of side ``cell`` over ``bounds``."""
    (x0, x1), (y0, y1) = bounds
    return round((y1 - y0) / cell), round((x1 - x0) / cell)


@dataclass
class Episode:
    """One seed and jar shape: the scene after touching, its touch data and depth slices."""

    seed: int
    shape: str
    scene: Scene
    jars: list[Jar]
    touch: dict[str, NDArray]
    raw_touch_count: int
    log: TouchLog
    slices: dict[float, NDArray[np.float64]]
    camera_xy: NDArray[np.float64]


def run_episode(
    seed: int, shape: str, noise_levels: Sequence[float], jar_limit: int | None = None
) -> Episode:
    """Builds the scene at each depth-noise level (same layout) and touches it once."""
    scene = Scene(seed=seed, **scene_config(shape, DEFAULT_DEPTH_NOISE))
    positions = scene.jars["positions"].copy()
    slices = {}
    for noise in noise_levels:
        other = scene if noise == DEFAULT_DEPTH_NOISE else Scene(seed, **scene_config(shape, noise))
        if not np.array_equal(other.jars["positions"], positions):
            raise RuntimeError(f"seed {seed}: the layout changed with the depth noise")
        slices[noise] = other.slice_points
    jars = jars_of(scene)
    indices = None if jar_limit is None else range(min(jar_limit, len(jars)))
    touch, log = follow_surfaces(scene, indices)
    return Episode(
        seed=seed,
        shape=shape,
        scene=scene,
        jars=jars,
        touch=touch,
        raw_touch_count=sum(len(p) for p in log.points),
        log=log,
        slices=slices,
        camera_xy=np.asarray(scene.camera["position"][:2], dtype=float),
    )


def maps_for(episode: Episode, option: PriorOption, noise: float, cell: float) -> tuple[Gpis, Gpis]:
    """(depth only, depth + touch) maps of ``episode`` under ``option``."""
    bounds = map_bounds(episode.scene)
    shape = grid_shape(bounds, cell)
    depth = episode.slices[noise]
    prior = start_map(option, depth, noise, episode.camera_xy, bounds, shape)
    touched = start_map(option, depth, noise, episode.camera_xy, bounds, shape)
    add_touch(touched, episode.touch)
    return prior, touched


def evaluate(
    episodes: Sequence[Episode], noise_levels: Sequence[float], cell: float
) -> list[dict[str, object]]:
    """One row per (episode, noise, prior option, data): IoU and outline distance."""
    rows = []
    for episode in episodes:
        for noise in noise_levels:
            for option in PRIOR_OPTIONS:
                for data, gpis in zip(
                    ("depth only", "depth + touch"),
                    maps_for(episode, option, noise, cell),
                    strict=True,
                ):
                    centres = gpis.cell_centres
                    truth = footprint_mask(centres, episode.jars)
                    rows.append(
                        {
                            "seed": episode.seed,
                            "shape": episode.shape,
                            "depth_noise": noise,
                            "prior": option.name,
                            "data": data,
                            "iou": interior_iou(gpis.mean, truth),
                            "outline_distance": outline_distance(gpis.mean, centres, episode.jars),
                            "spurious_distance": spurious_distance(
                                gpis.mean, centres, episode.jars
                            ),
                            "rows": gpis.n_rows,
                            "contacts": len(episode.touch["points"]),
                            "jar_displacement": float(np.mean(episode.scene.jars["displacement"])),
                        }
                    )
    return rows


def summarise(rows: Sequence[dict[str, object]]) -> list[dict[str, object]]:
    """Mean and standard deviation over seeds for each (noise, shape, prior, data)."""
    groups: dict[tuple, list[dict[str, object]]] = {}
    for row in rows:
        key = (row["depth_noise"], row["shape"], row["prior"], row["data"])
        groups.setdefault(key, []).append(row)
    out = []
    for (noise, shape, prior, data), members in groups.items():
        iou = [float(m["iou"]) for m in members]
        dist = [float(m["outline_distance"]) for m in members]
        spurious = [float(m["spurious_distance"]) for m in members]
        out.append(
            {
                "depth_noise": noise,
                "shape": shape,
                "prior": prior,
                "data": data,
                "seeds": len(members),
                "iou_mean": statistics.fmean(iou),
                "iou_std": statistics.pstdev(iou),
                "outline_mm_mean": 1e3 * statistics.fmean(dist),
                "outline_mm_std": 1e3 * statistics.pstdev(dist),
                "spurious_mm_mean": 1e3 * statistics.fmean(spurious),
                "rows_mean": statistics.fmean(float(m["rows"]) for m in members),
            }
        )
    return out


def choose_default(summary: Sequence[dict[str, object]]) -> str:
    """The prior with the best depth + touch IoU at the default noise, averaged over shapes
    (ties broken by the smaller outline distance)."""
    scores: dict[str, list[tuple[float, float]]] = {}
    for row in summary:
        if row["data"] == "depth + touch" and row["depth_noise"] == DEFAULT_DEPTH_NOISE:
            scores.setdefault(str(row["prior"]), []).append(
                (float(row["iou_mean"]), float(row["outline_mm_mean"]))
            )
    return max(
        scores,
        key=lambda p: (
            statistics.fmean(s[0] for s in scores[p]),
            -statistics.fmean(s[1] for s in scores[p]),
        ),
    )


def write_csv(rows: Sequence[dict[str, object]], path: Path) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    with path.open("w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=list(rows[0]))
        writer.writeheader()
        for row in rows:
            writer.writerow({k: f"{v:.6g}" if isinstance(v, float) else v for k, v in row.items()})


def markdown_table(summary: Sequence[dict[str, object]]) -> str:
    """The summary as a markdown table, one line per (noise, shape, prior), depth-only and
    depth + touch side by side."""
    by_key: dict[tuple, dict[str, dict[str, object]]] = {}
    for row in summary:
        by_key.setdefault((row["depth_noise"], row["shape"], row["prior"]), {})[
            str(row["data"])
        ] = row
    lines = [
        "| depth noise (mm) | jars | prior | IoU depth only | IoU depth + touch "
        "| outline dist. depth only (mm) | outline dist. depth + touch (mm) "
        "| zero set to truth, depth + touch (mm) | seeds |",
        "|---:|---|---|---:|---:|---:|---:|---:|---:|",
    ]
    for (noise, shape, prior), pair in by_key.items():
        d, t = pair["depth only"], pair["depth + touch"]
        lines.append(
            f"| {1e3 * float(noise):g} | {shape} | {prior} "
            f"| {d['iou_mean']:.3f} +- {d['iou_std']:.3f} "
            f"| {t['iou_mean']:.3f} +- {t['iou_std']:.3f} "
            f"| {d['outline_mm_mean']:.1f} +- {d['outline_mm_std']:.1f} "
            f"| {t['outline_mm_mean']:.1f} +- {t['outline_mm_std']:.1f} "
            f"| {t['spurious_mm_mean']:.1f} | {d['seeds']} |"
        )
    return "\n".join(lines) + "\n"


# --------------------------------------------------------------------------------------------
# Fig. 9 timing (the method of benchmarks/gpis_append.py)


def timing_map(n: int, grid: int, max_rows: int, seed: int = 0) -> Gpis:
    """A map with exactly ``n`` rows: random value points plus about 10 % contact rows."""
    rng = np.random.default_rng(seed + n)
    bounds = ((-0.3, 0.3), (0.0, 0.3))

    def points(count: int) -> NDArray[np.float64]:
        return np.column_stack([rng.uniform(-0.3, 0.3, count), rng.uniform(0.0, 0.3, count)])

    g = Gpis(bounds, (grid, grid), max_rows=max_rows)
    n_contacts = n // 30
    g.add_values(points(n - 3 * n_contacts), noise_std=0.002)
    angles = rng.uniform(0.0, 2.0 * np.pi, n_contacts)
    g.add_contacts(points(n_contacts), np.column_stack([np.cos(angles), np.sin(angles)]))
    while g.n_rows < n:
        g.add_values(points(n - g.n_rows), noise_std=0.002)
    return g


def time_updates(
    sizes: Sequence[int], grid: int, repeats: int, full_repeats: int
) -> list[dict[str, float]]:
    """Median time (ms) of appending one contact and of the full recompute, per n."""
    out = []
    for n in sizes:
        appends = []
        g = None
        while len(appends) < repeats:
            if g is None or g.free_rows < 3:
                g = timing_map(n, grid, max_rows=n + 3 * max(1, n // 150))
            start = time.perf_counter()
            g.add_contacts(np.array([[0.031, 0.137]]), np.array([[0.6, -0.8]]))
            appends.append(time.perf_counter() - start)
        g = timing_map(n, grid, max_rows=max(4096, n + 3))
        fulls = []
        for _ in range(full_repeats):
            start = time.perf_counter()
            g.recompute_from_scratch()
            fulls.append(time.perf_counter() - start)
        out.append(
            {
                "n": n,
                "append_ms": 1e3 * statistics.median(appends),
                "full_ms": 1e3 * statistics.median(fulls),
            }
        )
    return out


# --------------------------------------------------------------------------------------------
# Figures


def _pyplot():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def _outlines(ax, jars: Sequence[Jar]) -> None:
    for jar in jars:
        outline = jar.outline(120)
        outline = np.vstack([outline, outline[:1]])
        ax.plot(outline[:, 0], outline[:, 1], color="magenta", lw=1.0)


def _frame(ax, bounds) -> None:
    (x0, x1), (y0, y1) = bounds
    ax.set_xlim(x0, x1)
    ax.set_ylim(y0, y1)
    ax.set_aspect("equal")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m, into the cupboard)")


def _map_panels(fig, axes, gpis: Gpis, jars, depth, touch, title: str) -> None:
    """Mean with zero level set, truth and measurements; then the variance."""
    (x0, x1), (y0, y1) = gpis.bounds
    extent = (x0, x1, y0, y1)
    mean = gpis.mean
    limit = max(float(np.abs(mean).max()), 1e-9)
    ax = axes[0]
    image = ax.imshow(mean, origin="lower", extent=extent, cmap="RdBu", vmin=-limit, vmax=limit)
    centres = gpis.cell_centres
    if (mean < 0).any() and (mean >= 0).any():
        ax.contour(centres[..., 0], centres[..., 1], mean, levels=[0.0], colors="k")
    _outlines(ax, jars)
    depth = depth[in_bounds(depth, gpis.bounds, WALL_CLEARANCE)]
    ax.scatter(*depth.T, s=3, c="tab:green", label="depth")
    if touch is not None and len(touch["points"]):
        ax.scatter(*touch["points"].T, s=9, c="orange", edgecolors="k", lw=0.3, label="touch")
    ax.set_title(f"{title}: mean (zero level black, truth magenta)", fontsize=8)
    ax.legend(loc="upper right", fontsize=6)
    fig.colorbar(image, ax=ax, fraction=0.025)
    ax = axes[1]
    image = ax.imshow(gpis.variance, origin="lower", extent=extent, cmap="jet")
    ax.set_title(f"{title}: variance", fontsize=8)
    fig.colorbar(image, ax=ax, fraction=0.025)
    for ax in axes:
        _frame(ax, gpis.bounds)


def fig3(scene: Scene, out: Path) -> None:
    """Depth image, back-projected cloud, slice, noisy slice."""
    plt = _pyplot()
    look = scene.first_look
    fig = plt.figure(figsize=(11, 7.5))
    ax = fig.add_subplot(2, 2, 1)
    image = ax.imshow(look["depth"], cmap="viridis")
    fig.colorbar(image, ax=ax, fraction=0.03, label="depth (m)")
    ax.set_title("depth image")
    ax = fig.add_subplot(2, 2, 2, projection="3d")
    cloud = look["cloud"]
    step = max(1, len(cloud) // 6000)
    c = cloud[::step]
    ax.scatter(c[:, 0], c[:, 1], c[:, 2], s=0.5, c=c[:, 2], cmap="viridis")
    ax.set_title("back-projected 3D cloud")
    ax.set_xlabel("x")
    ax.set_ylabel("y")
    ax.set_zlabel("z")
    bounds = map_bounds(scene)
    for k, (key, title) in enumerate(
        (("slice_clean", "2D slice at the map height"), ("slice", "slice with sensor noise"))
    ):
        ax = fig.add_subplot(2, 2, 3 + k)
        ax.scatter(*look[key].T, s=4, c="tab:green")
        _outlines(ax, jars_of(scene))
        _frame(ax, bounds)
        ax.set_title(title)
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    plt.close(fig)


def fig4(episodes: dict[str, Episode], out: Path) -> None:
    """Tactile and visual measurements on square (left) and round (right) jars."""
    plt = _pyplot()
    fig, axes = plt.subplots(1, 2, figsize=(12, 3.6))
    for ax, shape in zip(axes, ("square", "round"), strict=True):
        ep = episodes[shape]
        _outlines(ax, ep.jars)
        ax.scatter(*ep.slices[DEFAULT_DEPTH_NOISE].T, s=4, c="tab:green", label="depth slice")
        p, n = ep.touch["points"], ep.touch["normals"]
        ax.quiver(*p.T, *n.T, color="tab:red", scale=40, width=0.002)
        ax.scatter(*p.T, s=4, c="tab:red", label=f"touch ({len(p)} kept)")
        _frame(ax, map_bounds(ep.scene))
        ax.set_title(f"{shape} jars, seed {ep.seed}: {ep.log.sweeps} sweeps, {ep.log.steps} steps")
        ax.legend(loc="upper right", fontsize=7)
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    plt.close(fig)


def fig_maps(panels: Sequence[tuple[Gpis, Episode, bool, str]], out: Path) -> None:
    """One row (mean, variance) per (map, episode, with touch, title)."""
    plt = _pyplot()
    fig, axes = plt.subplots(len(panels), 2, figsize=(12, 3.3 * len(panels)), squeeze=False)
    for row, (gpis, ep, with_touch, title) in zip(axes, panels, strict=True):
        depth = ep.slices[DEFAULT_DEPTH_NOISE]
        _map_panels(fig, row, gpis, ep.jars, depth, ep.touch if with_touch else None, title)
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    plt.close(fig)


def fig9(timings: Sequence[dict[str, float]], out: Path) -> None:
    plt = _pyplot()
    fig, ax = plt.subplots(figsize=(6.0, 4.0))
    n = [t["n"] for t in timings]
    ax.plot(n, [t["full_ms"] for t in timings], "o-", label="full recompute (paper)")
    ax.plot(n, [t["append_ms"] for t in timings], "s-", label="incremental append, one contact")
    ax.set_yscale("log")
    ax.set_xlabel("number of GP rows n (measurements)")
    ax.set_ylabel("time per update (ms, median)")
    ax.set_title("GPIS update time vs number of measurements")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend()
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    plt.close(fig)


# --------------------------------------------------------------------------------------------
# Driver

TABLE_START = "<!-- paper-table:start -->"
TABLE_END = "<!-- paper-table:end -->"


@dataclass
class Settings:
    seeds: int = 20
    noise_levels: tuple[float, ...] = DEPTH_NOISE_LEVELS
    table_cell: float = CELL
    figure_cell: float = 0.004
    timing_sizes: tuple[int, ...] = (100, 250, 500, 1000, 2000)
    timing_grid: int = 64
    timing_repeats: int = 9
    timing_full_repeats: int = 3
    jar_limit: int | None = None

    @classmethod
    def tiny(cls) -> Settings:
        return cls(
            seeds=2,
            noise_levels=(0.001, DEFAULT_DEPTH_NOISE),
            table_cell=0.01,
            figure_cell=0.01,
            timing_sizes=(30, 90),
            timing_grid=16,
            timing_repeats=3,
            timing_full_repeats=1,
            jar_limit=3,
        )


def headline(summary: Sequence[dict[str, object]], default: str) -> str:
    """Averages at the default depth noise, per prior, shape and data."""
    lines = [
        f"Averages over seeds at the default depth noise ({1e3 * DEFAULT_DEPTH_NOISE:g} mm).",
        "",
        "| prior | jars | IoU depth only | IoU depth + touch | outline dist. depth only (mm) "
        "| outline dist. depth + touch (mm) | zero set to truth, depth + touch (mm) |",
        "|---|---|---:|---:|---:|---:|---:|",
    ]
    pairs: dict[tuple, dict[str, dict[str, object]]] = {}
    for row in summary:
        if row["depth_noise"] == DEFAULT_DEPTH_NOISE:
            pairs.setdefault((row["prior"], row["shape"]), {})[str(row["data"])] = row
    for (prior, shape), pair in pairs.items():
        d, t = pair["depth only"], pair["depth + touch"]
        lines.append(
            f"| {prior} | {shape} | {d['iou_mean']:.3f} | {t['iou_mean']:.3f} "
            f"| {d['outline_mm_mean']:.1f} | {t['outline_mm_mean']:.1f} "
            f"| {t['spurious_mm_mean']:.1f} |"
        )
    lines += ["", f"Chosen default prior (best depth + touch IoU, both shapes): **{default}**."]
    return "\n".join(lines) + "\n"


def run(out: Path, settings: Settings, paper_md: Path | None = None) -> dict[str, object]:
    """Runs everything and writes the figures, ``table.csv``, ``table_seeds.csv`` and
    ``table.md`` into ``out``; updates the table block of ``paper_md`` if given."""
    out.mkdir(parents=True, exist_ok=True)
    started = time.perf_counter()
    episodes = [
        run_episode(seed, shape, settings.noise_levels, settings.jar_limit)
        for seed in range(settings.seeds)
        for shape in SHAPES
    ]
    simulated = time.perf_counter() - started
    rows = evaluate(episodes, settings.noise_levels, settings.table_cell)
    summary = summarise(rows)
    default = choose_default(summary)
    write_csv(rows, out / "table_seeds.csv")
    write_csv(summary, out / "table.csv")
    table = headline(summary, default) + "\n" + markdown_table(summary)
    (out / "table.md").write_text(table)

    first = {ep.shape: ep for ep in episodes if ep.seed == 0}
    fig3(first["round"].scene, out / "fig3_depth.png")
    fig4(first, out / "fig4_measurements.png")
    option = next(o for o in PRIOR_OPTIONS if o.name == default)
    maps = {
        shape: maps_for(first[shape], option, DEFAULT_DEPTH_NOISE, settings.figure_cell)
        for shape in SHAPES
    }
    fig_maps(
        [(maps[s][0], first[s], False, f"{s} jars, depth only ({default})") for s in SHAPES],
        out / "fig5_prior.png",
    )
    fig_maps(
        [(maps["round"][1], first["round"], True, f"round, depth + touch ({default})")],
        out / "fig6_round.png",
    )
    fig_maps(
        [(maps["square"][1], first["square"], True, f"square, depth + touch ({default})")],
        out / "fig7_square.png",
    )
    fig8_options = [o for o in PRIOR_OPTIONS if o.name in ("circle 0.2", "circle 0.03")] + [
        next(
            o
            for o in PRIOR_OPTIONS
            if o.prior_mean > 0 and o.circle_diameter is None and not o.free_space
        )
    ]
    fig_maps(
        [
            (
                maps_for(first["square"], o, DEFAULT_DEPTH_NOISE, settings.figure_cell)[1],
                first["square"],
                True,
                f"square, depth + touch, {o.name}",
            )
            for o in fig8_options
        ],
        out / "fig8_priors.png",
    )
    timings = time_updates(
        settings.timing_sizes,
        settings.timing_grid,
        settings.timing_repeats,
        settings.timing_full_repeats,
    )
    write_csv(timings, out / "fig9_timing.csv")
    fig9(timings, out / "fig9_timing.png")

    if paper_md is not None and paper_md.exists():
        text = paper_md.read_text()
        if TABLE_START in text and TABLE_END in text:
            head, rest = text.split(TABLE_START, 1)
            _, tail = rest.split(TABLE_END, 1)
            paper_md.write_text(f"{head}{TABLE_START}\n{table}{TABLE_END}{tail}")
    return {
        "default": default,
        "summary": summary,
        "timings": timings,
        "seconds_simulating": simulated,
        "seconds_total": time.perf_counter() - started,
        "touch_steps": sum(ep.log.steps for ep in episodes),
        "contacts_kept": [len(ep.touch["points"]) for ep in episodes],
        "mean_jar_displacement_mm": 1e3
        * statistics.fmean(float(np.mean(ep.scene.jars["displacement"])) for ep in episodes),
    }


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=Path("docs/paper"))
    parser.add_argument("--seeds", type=int, default=None, help="seeds per jar shape (20)")
    parser.add_argument("--tiny", action="store_true", help="2 seeds, coarse grids (a smoke run)")
    parser.add_argument(
        "--paper-md",
        type=Path,
        default=None,
        help="markdown file whose table block is replaced (default: PAPER.md beside --out)",
    )
    args = parser.parse_args(argv)
    settings = Settings.tiny() if args.tiny else Settings()
    if args.seeds is not None:
        if args.seeds < 1:
            parser.error("--seeds must be at least 1")
        settings.seeds = args.seeds
    paper_md = args.paper_md if args.paper_md is not None else args.out.parent / "PAPER.md"
    result = run(args.out, settings, paper_md)
    print((args.out / "table.md").read_text())
    print(
        f"default prior: {result['default']}; touch steps {result['touch_steps']}, "
        f"contacts kept per episode {result['contacts_kept']}, mean jar displacement "
        f"{result['mean_jar_displacement_mm']:.2f} mm; simulation "
        f"{result['seconds_simulating']:.1f} s, total {result['seconds_total']:.1f} s"
    )
    for t in result["timings"]:
        print(f"n={t['n']:>5}: append {t['append_ms']:.3f} ms, full {t['full_ms']:.2f} ms")


if __name__ == "__main__":
    main()
