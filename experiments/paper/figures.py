"""Figs. 3-9: depth pipeline, measurements, maps under a prior option, update timing."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np

from experiments.paper.episodes import DEFAULT_DEPTH_NOISE, Episode, map_bounds
from tactile_search import Gpis, _core
from tactile_search._core import Scene


def _pyplot():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def _outlines(ax, jars: dict[str, Any]) -> None:
    for outline in _core.jar_outlines(jars, 120):
        closed = np.vstack([outline, outline[:1]])
        ax.plot(closed[:, 0], closed[:, 1], color="magenta", lw=1.0)


def _frame(ax, bounds) -> None:
    (x0, x1), (y0, y1) = bounds
    ax.set_xlim(x0, x1)
    ax.set_ylim(y0, y1)
    ax.set_aspect("equal")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m, into the cupboard)")


def _inside(points: np.ndarray, bounds) -> np.ndarray:
    (x0, x1), (y0, y1) = bounds
    keep = (points[:, 0] >= x0) & (points[:, 0] <= x1) & (points[:, 1] >= y0) & (points[:, 1] <= y1)
    return points[keep]


def _map_panels(fig, axes, gpis: Gpis, jars, depth, touch, title: str) -> None:
    """Mean with zero level set, truth and measurements; then the variance."""
    (x0, x1), (y0, y1) = gpis.bounds
    extent = (x0, x1, y0, y1)
    mean = gpis.mean
    limit = max(float(np.abs(mean).max()), 1e-9)
    ax = axes[0]
    image = ax.imshow(mean, origin="lower", extent=extent, cmap="RdBu", vmin=-limit, vmax=limit)
    for a, b in _core.zero_level_segments(mean, gpis.bounds):
        ax.plot([a[0], b[0]], [a[1], b[1]], color="k", lw=1.0)
    _outlines(ax, jars)
    ax.scatter(*_inside(depth, gpis.bounds).T, s=3, c="tab:green", label="depth")
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


def fig3(scene: Scene, jars: dict[str, Any], out: Path) -> None:
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
        _outlines(ax, jars)
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
    """Time per update against the number of rows, full recompute against append."""
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
