"""Pictures of an episode: the scene from above beside the agent's map, and GIFs.

``render_frame`` draws what ``CupboardSearchEnv.render()`` returns (an RGB array);
``save_gif`` writes a list of frames. Both need matplotlib (the ``plots`` extra).
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from tactile_search import _core


def _jar_outline(jar: dict[str, Any]) -> np.ndarray:
    """(N, 2) closed outline of a jar's footprint (``render_state``'s jar dict), from the
    core's footprint geometry."""
    jars = {
        "shapes": [jar["shape"]],
        "positions": [[jar["x"], jar["y"]]],
        "half_widths": [jar["size"] / 2],
        "yaws": [jar["yaw"]],
    }
    outline = _core.jar_outlines(jars, 48)[0]
    return np.vstack([outline, outline[:1]])


def _draw_scene(ax: Any, state: dict[str, Any]) -> None:
    from matplotlib.patches import Rectangle

    (x0, x1), (y0, y1) = state["bounds"]
    ax.plot([x0, x0, x1, x1], [y0, y1, y1, y0], color="saddlebrown", lw=3)
    for jar in state["jars"]:
        outline = _jar_outline(jar)
        color = "crimson" if jar["is_target"] else "steelblue"
        ax.fill(outline[:, 0], outline[:, 1], color=color, alpha=0.8)
    x, y, yaw = state["hand"]
    h = state["wrist_half_extent"]
    ax.add_patch(
        Rectangle(
            (x - h, y - h),
            2 * h,
            2 * h,
            angle=np.degrees(yaw),
            rotation_point="center",
            color="dimgray",
        )
    )
    ax.plot([x, x - 0.3 * np.sin(yaw)], [y, y - 0.3 * np.cos(yaw)], color="dimgray", lw=6)
    fx, fy, fyaw = state["finger"]
    length = state["finger_length"]
    ax.plot([fx, fx - length * np.sin(fyaw)], [fy, fy + length * np.cos(fyaw)], color="k", lw=2)
    for px, py, nx, ny in state["contacts"]:
        ax.plot(px, py, "o", color="orange", ms=4)
        ax.arrow(px, py, 0.02 * nx, 0.02 * ny, color="orange", width=0.001)
    ax.set_xlim(x0 - 0.05, x1 + 0.05)
    ax.set_ylim(y0 - 0.15, y1 + 0.02)
    ax.set_aspect("equal")
    ax.set_title("scene (target red)")


def render_frame(state: dict[str, Any], map_mode: str) -> np.ndarray:
    """An RGB ``(H, W, 3)`` uint8 picture: the scene from above, then the map's panels."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    panels = {"gpis": ["mean", "std"], "occupancy": ["occupancy"], "none": []}[map_mode]
    fig, axes = plt.subplots(1, 1 + len(panels), figsize=(4.0 * (1 + len(panels)), 3.4))
    axes = np.atleast_1d(axes)
    _draw_scene(axes[0], state)
    (x0, x1), (y0, y1) = state["bounds"]
    for ax, key in zip(axes[1:], panels, strict=True):
        grid = state[key]
        if key == "mean":
            limit = max(float(np.abs(grid).max()), 1e-6)
            image = ax.imshow(
                grid, origin="lower", extent=(x0, x1, y0, y1), cmap="RdBu", vmin=-limit, vmax=limit
            )
            ax.contour(grid, levels=[0.0], colors="k", origin="lower", extent=(x0, x1, y0, y1))
        else:
            image = ax.imshow(grid, origin="lower", extent=(x0, x1, y0, y1), cmap="viridis")
        for jar in state["jars"]:
            outline = _jar_outline(jar)
            ax.plot(outline[:, 0], outline[:, 1], color="magenta", lw=0.8)
        ax.set_title(
            {"mean": "GPIS mean (zero level black)", "std": "GPIS std", "occupancy": "P(occupied)"}[
                key
            ]
        )
        fig.colorbar(image, ax=ax, fraction=0.03)
    fig.tight_layout()
    fig.canvas.draw()
    frame = np.asarray(fig.canvas.buffer_rgba())[..., :3].copy()
    plt.close(fig)
    return frame


def save_gif(frames: list[np.ndarray], path: str | Path, fps: int = 10) -> Path:
    """Writes ``frames`` (RGB arrays) to a GIF with matplotlib's Pillow writer."""
    import matplotlib

    matplotlib.use("Agg")
    from PIL import Image

    if not frames:
        raise ValueError("frames must hold at least one frame, got none")
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    images = [Image.fromarray(frame) for frame in frames]
    images[0].save(path, save_all=True, append_images=images[1:], duration=int(1000 / fps), loop=0)
    return path
