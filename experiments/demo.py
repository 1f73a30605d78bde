"""Demo: reconstruct a synthetic shelf cross-section from depth, then from depth and touch.

Three jar outlines (two round, one square) stand in the slice plane of a cupboard 0.6 m wide
and 0.3 m deep. A depth camera in front of the opening sees only their front faces; its
noisy points build the GPIS prior exactly as the environment builds it (``_core.depth_prior``:
f = 0 on each hit, f = +d a little in front of it along the ray, thinned, at the
environment's default settings). A handful of contacts on the hidden sides (point + outward
normal) then update the map with the environment's contact noise. The cupboard's size, the
camera's place and the depth and touch noise are the core's defaults
(``_core.EpisodeConfig.settings()``, read through ``experiments.maps.env_settings``); the
shelf, the ray fan, the grid and the seed are the demo's own. The demo prints the IoU of
the map's interior (mean < 0) against the true jar footprints for both maps (the
environment's ``info["iou"]``, ``_core.interior_iou``) and writes a figure of mean, standard
deviation and zero level set against the true outlines. The jars' geometry (signed distance,
outlines) is the core's (``_core.jar_signed_distance``, ``_core.jar_outlines``).

Run: ``python -m experiments.demo --out results/demo_gpis.png`` (``make demo`` does this).
"""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from experiments.maps import add_touch, env_settings, start_map
from tactile_search import Gpis, _core

_DEFAULTS = env_settings()
#: The map's bounds: the cupboard's interior in the slice plane (x centred, open front y = 0).
BOUNDS = (
    (-_DEFAULTS["cupboard_width"] / 2, _DEFAULTS["cupboard_width"] / 2),
    (0.0, _DEFAULTS["cupboard_depth"]),
)
#: The depth camera's optical centre in the slice plane.
CAMERA = np.array(_DEFAULTS["camera_position"][:2])
#: Noise of each depth point's coordinates and of each contact's, m.
DEPTH_NOISE_STD = _DEFAULTS["depth_noise_std"]
CONTACT_NOISE_STD = _DEFAULTS["touch_point_noise_std"]
#: The demo's own choices: camera rays, contacts per jar, outline samples, the ray fan's half
#: angle (that of the opening's edge seen from ``FAN_SETBACK`` m behind the camera: 45
#: degrees at the defaults) and the grid (finer than the environment's, for the figure).
RAYS = 240
CONTACTS_PER_JAR = 5
OUTLINE_SAMPLES = 200
FAN_SETBACK = 0.05
GRID = (64, 128)

# The shelf in the format of ``Scene.jars``: the last jar, behind the other two, is the
# hidden target. Half widths are radii (round) or half sides (square).
SHELF: dict[str, Any] = {
    "shapes": ["round", "square", "round"],
    "positions": np.array([[-0.06, 0.09], [0.03, 0.10], [-0.02, 0.17]]),
    "half_widths": np.array([0.025, 0.024, 0.026]),
    "yaws": np.array([0.0, 0.35, 0.0]),
}


def subset(jars: dict[str, Any], keep: list[int]) -> dict[str, Any]:
    """The jars ``keep`` of a jars dict."""
    return {
        "shapes": [jars["shapes"][k] for k in keep],
        "positions": np.asarray(jars["positions"])[keep],
        "half_widths": np.asarray(jars["half_widths"])[keep],
        "yaws": np.asarray(jars["yaws"])[keep],
    }


def scene_distance(points: NDArray[np.float64], jars: dict[str, Any]) -> NDArray[np.float64]:
    """Signed distance to the nearest jar (the core's footprints)."""
    return _core.jar_signed_distance(jars, points).min(axis=0)


def outward_normals(points: NDArray[np.float64], jars: dict[str, Any]) -> NDArray[np.float64]:
    """Unit gradient of the scene's signed distance (central differences)."""
    h = 1e-6
    steps = np.array([[h, 0.0], [0.0, h]])
    grad = np.stack(
        [scene_distance(points + e, jars) - scene_distance(points - e, jars) for e in steps],
        axis=-1,
    )
    return grad / np.linalg.norm(grad, axis=-1, keepdims=True)


def depth_scan(
    jars: dict[str, Any], rays: int, noise_std: float, rng: np.random.Generator
) -> NDArray[np.float64]:
    """First hits of a fan of camera rays (sphere tracing the signed distance), with noise."""
    half_fov = np.arctan2(BOUNDS[0][1], -CAMERA[1] + FAN_SETBACK)
    angles = np.pi / 2 + np.linspace(-half_fov, half_fov, rays)
    directions = np.c_[np.cos(angles), np.sin(angles)]
    travelled = np.zeros(rays)
    for _ in range(200):
        distance = scene_distance(CAMERA + travelled[:, None] * directions, jars)
        travelled += np.maximum(distance, 0.0)
    hit_points = CAMERA + travelled[:, None] * directions
    hits = hit_points[scene_distance(hit_points, jars) < 1e-5]
    return hits + rng.normal(0.0, noise_std, size=hits.shape)


def hidden_contacts(
    jars: dict[str, Any], per_jar: int, noise_std: float, rng: np.random.Generator
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Touches on the sides the camera cannot see, as (points, outward normals)."""
    count = len(jars["shapes"])
    points = []
    for k, outline in enumerate(_core.jar_outlines(jars, OUTLINE_SAMPLES)):
        normals = outward_normals(outline, jars)
        away = np.einsum("ij,ij->i", normals, outline - CAMERA) > 0.0
        others = subset(jars, [j for j in range(count) if j != k])
        exposed = scene_distance(outline, others) > 0.01
        candidates = outline[away & exposed]
        chosen = rng.choice(len(candidates), size=min(per_jar, len(candidates)), replace=False)
        points.append(candidates[np.sort(chosen)])
    points = np.concatenate(points)
    normals = outward_normals(points, jars)
    return points + rng.normal(0.0, noise_std, size=points.shape), normals


def interior_iou(gpis: Gpis, jars: dict[str, Any]) -> float:
    """IoU of the map's interior (mean < 0) against the true footprints, on the map's grid,
    as the environment reports it."""
    truth = _core.footprint_mask(jars, gpis.bounds, gpis.shape)
    return _core.interior_iou(gpis.mean, truth)


def build_maps(
    seed: int, shape: tuple[int, int], prior_mean: float
) -> tuple[Gpis, Gpis, dict[str, NDArray[np.float64]]]:
    """The depth-only map and the depth + touch map of the synthetic shelf."""
    rng = np.random.default_rng(seed)
    depth = depth_scan(SHELF, rays=RAYS, noise_std=DEPTH_NOISE_STD, rng=rng)
    contact_points, contact_normals = hidden_contacts(
        SHELF, CONTACTS_PER_JAR, noise_std=CONTACT_NOISE_STD, rng=rng
    )
    settings = {"prior_mean": prior_mean}
    prior = start_map(depth, CAMERA, BOUNDS, shape, settings)
    touched = start_map(depth, CAMERA, BOUNDS, shape, settings)
    add_touch(touched, contact_points, contact_normals)
    measurements = {"depth": depth, "contacts": contact_points, "normals": contact_normals}
    return prior, touched, measurements


def plot(maps: dict[str, Gpis], measurements: dict[str, NDArray[np.float64]], out: Path) -> None:
    """Mean with its zero level set and the true outlines, and the standard deviation."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    (x0, x1), (y0, y1) = BOUNDS
    extent = (x0, x1, y0, y1)
    outlines = _core.jar_outlines(SHELF, OUTLINE_SAMPLES)
    fig, axes = plt.subplots(len(maps), 2, figsize=(11, 3.2 * len(maps)), squeeze=False)
    for row, (title, gpis) in enumerate(maps.items()):
        limit = np.abs(gpis.mean).max()
        ax = axes[row, 0]
        image = ax.imshow(
            gpis.mean, origin="lower", extent=extent, cmap="RdBu", vmin=-limit, vmax=limit
        )
        centres = gpis.cell_centres
        ax.contour(centres[..., 0], centres[..., 1], gpis.mean, levels=[0.0], colors="k")
        for outline in outlines:
            closed = np.vstack([outline, outline[:1]])
            ax.plot(closed[:, 0], closed[:, 1], color="magenta", lw=1.0)
        ax.scatter(*measurements["depth"].T, s=2, c="tab:green", label="depth")
        if "touch" in title:
            points, normals = measurements["contacts"], measurements["normals"]
            ax.quiver(*points.T, *normals.T, color="orange", scale=25, width=0.004)
            ax.scatter(*points.T, s=10, c="orange", label="touch")
        ax.set_title(f"{title}: mean f, zero level set (black), truth (magenta)")
        ax.legend(loc="upper right", fontsize=7)
        fig.colorbar(image, ax=ax, fraction=0.025)
        ax = axes[row, 1]
        image = ax.imshow(np.sqrt(gpis.variance), origin="lower", extent=extent, cmap="viridis")
        ax.set_title(f"{title}: standard deviation of f")
        fig.colorbar(image, ax=ax, fraction=0.025)
        for ax in axes[row]:
            ax.set_xlabel("x (m)")
            ax.set_ylabel("y (m, into the cupboard)")
            ax.set_aspect("equal")
    fig.tight_layout()
    out.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(out, dpi=110)
    plt.close(fig)


def run(seed: int, shape: tuple[int, int], prior_mean: float, out: Path) -> dict[str, float]:
    """Builds both maps, writes the figure to ``out`` and returns their IoUs and row counts."""
    prior, touched, measurements = build_maps(seed, shape, prior_mean)
    plot({"depth only": prior, "depth + touch": touched}, measurements, out)
    return {
        "depth_points": len(measurements["depth"]),
        "contacts": len(measurements["contacts"]),
        "rows": touched.n_rows,
        "iou_depth_only": interior_iou(prior, SHELF),
        "iou_depth_and_touch": interior_iou(touched, SHELF),
    }


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=Path("results/demo_gpis.png"))
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument(
        "--prior-mean",
        type=float,
        default=_DEFAULTS["prior_mean"],
        help="constant prior mean (default: the environment's)",
    )
    parser.add_argument("--grid", type=int, nargs=2, default=GRID, metavar=("H", "W"))
    args = parser.parse_args(argv)

    result = run(args.seed, tuple(args.grid), args.prior_mean, args.out)
    print(
        f"depth points: {result['depth_points']}, contacts: {result['contacts']}, "
        f"GPIS rows: {result['rows']}"
    )
    print("IoU of the map's interior (mean < 0) against the true jar footprints:")
    print(f"  depth only:    {result['iou_depth_only']:.3f}")
    print(f"  depth + touch: {result['iou_depth_and_touch']:.3f}")
    print(f"figure written to {args.out}")


if __name__ == "__main__":
    main()
