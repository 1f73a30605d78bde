"""Demo: reconstruct a synthetic shelf cross-section from depth, then from depth and touch.

Three jar outlines (two round, one square) stand in the slice plane of a cupboard 0.6 m wide
and 0.3 m deep. A depth camera in front of the opening sees only their front faces; its
noisy points build the GPIS prior (f = 0 on each hit, f = +d a little in front of it along
the ray, where the camera saw free space). A handful of contacts on the hidden sides
(point + outward normal) then update the map. The demo prints the IoU of the map's interior
(mean < 0) against the true jar footprints for both maps and writes a figure of mean,
standard deviation and zero level set against the true outlines.

Run: ``python -m tactile_search.demo --out results/demo_gpis.png`` (``make demo`` does this).
The full environment replaces this synthetic scene once the cupboard simulation lands.
"""

from __future__ import annotations

import argparse
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from tactile_search import Gpis

BOUNDS = ((-0.3, 0.3), (0.0, 0.3))
CAMERA = np.array([0.0, -0.25])


@dataclass(frozen=True)
class Jar:
    """A jar's outline in the slice plane: a circle, or a square rotated by ``yaw``."""

    centre: tuple[float, float]
    size: float  # diameter of a round jar, side of a square one
    square: bool = False
    yaw: float = 0.0

    def signed_distance(self, points: NDArray[np.float64]) -> NDArray[np.float64]:
        """Exact signed distance (negative inside) at ``(N, 2)`` points."""
        local = points - np.asarray(self.centre)
        if not self.square:
            return np.linalg.norm(local, axis=-1) - self.size / 2
        c, s = np.cos(self.yaw), np.sin(self.yaw)
        local = local @ np.array([[c, -s], [s, c]])  # into the jar's frame
        q = np.abs(local) - self.size / 2
        outside = np.linalg.norm(np.maximum(q, 0.0), axis=-1)
        return outside + np.minimum(np.max(q, axis=-1), 0.0)

    def outline(self, count: int = 200) -> NDArray[np.float64]:
        """``(count, 2)`` points along the outline, for plotting and touching."""
        t = np.linspace(0.0, 2 * np.pi, count, endpoint=False)
        if not self.square:
            return np.asarray(self.centre) + self.size / 2 * np.c_[np.cos(t), np.sin(t)]
        # Walk the square's perimeter at uniform speed.
        u = np.linspace(0.0, 4.0, count, endpoint=False)
        side, f = np.floor(u).astype(int), u - np.floor(u)
        corners = np.array([[-1, -1], [1, -1], [1, 1], [-1, 1], [-1, -1]]) * self.size / 2
        local = corners[side] + f[:, None] * (corners[side + 1] - corners[side])
        c, s = np.cos(self.yaw), np.sin(self.yaw)
        return np.asarray(self.centre) + local @ np.array([[c, s], [-s, c]])


SHELF = (
    Jar((-0.06, 0.09), 0.050),
    Jar((0.03, 0.10), 0.048, square=True, yaw=0.35),
    Jar((-0.02, 0.17), 0.052),  # behind the other two: the hidden target
)


def scene_distance(points: NDArray[np.float64], jars: tuple[Jar, ...]) -> NDArray[np.float64]:
    """Signed distance to the nearest jar."""
    return np.min([jar.signed_distance(points) for jar in jars], axis=0)


def outward_normals(points: NDArray[np.float64], jars: tuple[Jar, ...]) -> NDArray[np.float64]:
    """Unit gradient of the scene's signed distance (central differences)."""
    h = 1e-6
    steps = np.array([[h, 0.0], [0.0, h]])
    grad = np.stack(
        [scene_distance(points + e, jars) - scene_distance(points - e, jars) for e in steps],
        axis=-1,
    )
    return grad / np.linalg.norm(grad, axis=-1, keepdims=True)


def depth_scan(
    jars: tuple[Jar, ...], rays: int, noise_std: float, rng: np.random.Generator
) -> NDArray[np.float64]:
    """First hits of a fan of camera rays (sphere tracing the signed distance), with noise."""
    half_fov = np.arctan2(0.3, 0.25 + 0.05)
    angles = np.pi / 2 + np.linspace(-half_fov, half_fov, rays)
    directions = np.c_[np.cos(angles), np.sin(angles)]
    travelled = np.zeros(rays)
    for _ in range(200):
        distance = scene_distance(CAMERA + travelled[:, None] * directions, jars)
        travelled += np.maximum(distance, 0.0)
    hit_points = CAMERA + travelled[:, None] * directions
    hits = hit_points[scene_distance(hit_points, jars) < 1e-5]
    return hits + rng.normal(0.0, noise_std, size=hits.shape)


def free_space_points(
    surface: NDArray[np.float64], offset: float
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Points ``offset`` in front of each surface point along its camera ray, f = +offset."""
    towards_camera = CAMERA - surface
    towards_camera /= np.linalg.norm(towards_camera, axis=-1, keepdims=True)
    return surface + offset * towards_camera, np.full(len(surface), offset)


def hidden_contacts(
    jars: tuple[Jar, ...], per_jar: int, noise_std: float, rng: np.random.Generator
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Touches on the sides the camera cannot see, as (points, outward normals)."""
    points = []
    for jar in jars:
        outline = jar.outline()
        normals = outward_normals(outline, jars)
        away = np.einsum("ij,ij->i", normals, outline - CAMERA) > 0.0
        exposed = scene_distance(outline, tuple(j for j in jars if j is not jar)) > 0.01
        candidates = outline[away & exposed]
        chosen = rng.choice(len(candidates), size=min(per_jar, len(candidates)), replace=False)
        points.append(candidates[np.sort(chosen)])
    points = np.concatenate(points)
    normals = outward_normals(points, jars)
    return points + rng.normal(0.0, noise_std, size=points.shape), normals


def interior_iou(gpis: Gpis, jars: tuple[Jar, ...]) -> float:
    """IoU of the map's interior (mean < 0) against the true footprints, on the map's grid."""
    truth = scene_distance(gpis.cell_centres.reshape(-1, 2), jars).reshape(gpis.shape) < 0.0
    estimate = gpis.mean < 0.0
    union = np.count_nonzero(truth | estimate)
    return np.count_nonzero(truth & estimate) / union if union else 1.0


def build_maps(
    seed: int, shape: tuple[int, int], prior_mean: float
) -> tuple[Gpis, Gpis, dict[str, NDArray[np.float64]]]:
    """The depth-only map and the depth + touch map of the synthetic shelf."""
    rng = np.random.default_rng(seed)
    depth = depth_scan(SHELF, rays=240, noise_std=0.002, rng=rng)
    free, free_values = free_space_points(depth, offset=0.01)
    contact_points, contact_normals = hidden_contacts(SHELF, 5, noise_std=0.0005, rng=rng)

    prior = Gpis(bounds=BOUNDS, shape=shape, prior_mean=prior_mean)
    prior.add_values(depth, noise_std=0.002)
    prior.add_values(free, free_values, noise_std=0.004)
    touched = Gpis(bounds=BOUNDS, shape=shape, prior_mean=prior_mean)
    touched.add_values(depth, noise_std=0.002)
    touched.add_values(free, free_values, noise_std=0.004)
    touched.add_contacts(contact_points, contact_normals, noise_std=0.0005, normal_noise_std=0.05)
    measurements = {"depth": depth, "contacts": contact_points, "normals": contact_normals}
    return prior, touched, measurements


def plot(maps: dict[str, Gpis], measurements: dict[str, NDArray[np.float64]], out: Path) -> None:
    """Mean with its zero level set and the true outlines, and the standard deviation."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    (x0, x1), (y0, y1) = BOUNDS
    extent = (x0, x1, y0, y1)
    fig, axes = plt.subplots(len(maps), 2, figsize=(11, 3.2 * len(maps)), squeeze=False)
    for row, (title, gpis) in enumerate(maps.items()):
        limit = np.abs(gpis.mean).max()
        ax = axes[row, 0]
        image = ax.imshow(
            gpis.mean, origin="lower", extent=extent, cmap="RdBu", vmin=-limit, vmax=limit
        )
        centres = gpis.cell_centres
        ax.contour(centres[..., 0], centres[..., 1], gpis.mean, levels=[0.0], colors="k")
        for jar in SHELF:
            outline = np.vstack([jar.outline(), jar.outline()[:1]])
            ax.plot(outline[:, 0], outline[:, 1], color="magenta", lw=1.0)
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
    parser.add_argument("--prior-mean", type=float, default=0.01)
    parser.add_argument("--grid", type=int, nargs=2, default=(64, 128), metavar=("H", "W"))
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
