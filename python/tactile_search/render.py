"""Pictures of an episode: the scene from above beside the agent's map, and GIFs.

``render_frame`` draws what ``CupboardSearchEnv.render()`` returns (an RGB array) with
numpy alone, so the environment renders with only its own dependencies; ``save_gif``
writes a list of frames and needs Pillow through matplotlib (the ``plots`` extra).
"""

from __future__ import annotations

import itertools
from pathlib import Path
from typing import Any

import numpy as np

from tactile_search import _core

#: How to get what drawing needs: the ``plots`` extra.
PLOTS_EXTRA = "pip install 'tactile_search[plots]'"


def _matplotlib() -> Any:
    """matplotlib with its file-only backend, or an ImportError saying which extra to
    install (the environment itself needs only numpy and gymnasium)."""
    try:
        import matplotlib
    except ModuleNotFoundError as error:
        raise ImportError(
            f"rendering frames needs matplotlib, which is not installed: {PLOTS_EXTRA}"
        ) from error
    matplotlib.use("Agg")
    return matplotlib


#: Pixels per metre of every panel (2 mm a pixel).
PIXELS_PER_METRE = 500
#: How far in front of the opening the scene panel reaches (the hand starts there), m.
SCENE_MARGIN = 0.15
BACKGROUND = np.array([245, 245, 240], dtype=np.uint8)
WALL = np.array([139, 69, 19], dtype=np.uint8)
JAR = np.array([70, 130, 180], dtype=np.uint8)
TARGET = np.array([220, 20, 60], dtype=np.uint8)
HAND = np.array([105, 105, 105], dtype=np.uint8)
FINGER = np.array([30, 30, 30], dtype=np.uint8)
CONTACT = np.array([255, 200, 0], dtype=np.uint8)
OUTLINE = np.array([255, 0, 255], dtype=np.uint8)
# Anchors of the colour ramps: blue-white-red for the mean (red inside, f < 0) and a
# viridis-like ramp for the standard deviation and the occupancy.
DIVERGING = np.array([[178, 24, 43], [247, 247, 247], [33, 102, 172]], dtype=float)
SEQUENTIAL = np.array(
    [[68, 1, 84], [59, 82, 139], [33, 145, 140], [94, 201, 98], [253, 231, 37]], dtype=float
)


def _ramp(values: np.ndarray, anchors: np.ndarray) -> np.ndarray:
    """Colours of ``values`` in [0, 1] on a piecewise-linear ramp through ``anchors``."""
    position = np.clip(values, 0.0, 1.0) * (len(anchors) - 1)
    low = np.minimum(position.astype(int), len(anchors) - 2)
    t = (position - low)[..., None]
    return ((1 - t) * anchors[low] + t * anchors[low + 1]).round().astype(np.uint8)


class _Panel:
    """A pixel grid over ``[[x0, x1], [y0, y1]]`` (row 0 at the top, y1) and its pixel
    centres in metres."""

    def __init__(self, bounds: tuple[tuple[float, float], tuple[float, float]]) -> None:
        (x0, x1), (y0, y1) = bounds
        self.bounds = ((x0, x1), (y0, y1))
        self.width = round((x1 - x0) * PIXELS_PER_METRE)
        self.height = round((y1 - y0) * PIXELS_PER_METRE)
        columns = x0 + (np.arange(self.width) + 0.5) / PIXELS_PER_METRE
        rows = y1 - (np.arange(self.height) + 0.5) / PIXELS_PER_METRE
        self.x, self.y = np.meshgrid(columns, rows)
        self.image = np.empty((self.height, self.width, 3), dtype=np.uint8)
        self.image[:] = BACKGROUND

    def footprints(self, jars: list[dict[str, Any]]) -> np.ndarray:
        """Where the jars stand, (height, width) booleans, from the core's footprints."""
        if not jars:
            return np.zeros((self.height, self.width), dtype=bool)
        mask = _core.footprint_mask(_jar_dict(jars), self.bounds, (self.height, self.width))
        return np.flipud(mask)

    def segment(self, start: np.ndarray, end: np.ndarray, half_width: float) -> np.ndarray:
        """Pixels within ``half_width`` of the segment from ``start`` to ``end``."""
        d = end - start
        t = ((self.x - start[0]) * d[0] + (self.y - start[1]) * d[1]) / max(d @ d, 1e-12)
        t = np.clip(t, 0.0, 1.0)
        return np.hypot(self.x - start[0] - t * d[0], self.y - start[1] - t * d[1]) <= half_width

    def grid(self, values: np.ndarray) -> np.ndarray:
        """A (H, W) map grid over the same bounds (row 0 at y0), nearest cell per pixel."""
        (x0, x1), (y0, y1) = self.bounds
        h, w = values.shape
        i = np.clip(((self.y - y0) / (y1 - y0) * h).astype(int), 0, h - 1)
        j = np.clip(((self.x - x0) / (x1 - x0) * w).astype(int), 0, w - 1)
        return values[i, j]


def _jar_dict(jars: list[dict[str, Any]]) -> dict[str, Any]:
    """``render_state``'s jars as the core's jar arrays."""
    return {
        "shapes": [jar["shape"] for jar in jars],
        "positions": [[jar["x"], jar["y"]] for jar in jars],
        "half_widths": [jar["size"] / 2 for jar in jars],
        "yaws": [jar["yaw"] for jar in jars],
    }


def _edges(mask: np.ndarray) -> np.ndarray:
    """The pixels of ``mask`` with a neighbour outside it."""
    inner = mask.copy()
    inner[1:] &= mask[:-1]
    inner[:-1] &= mask[1:]
    inner[:, 1:] &= mask[:, :-1]
    inner[:, :-1] &= mask[:, 1:]
    return mask & ~inner


def _scene_panel(state: dict[str, Any]) -> np.ndarray:
    """The cupboard from above: walls, jars (the target red), the hand, the readings."""
    (x0, x1), (y0, y1) = state["bounds"]
    panel = _Panel(((x0, x1), (y0 - SCENE_MARGIN, y1)))
    wall = 3 / PIXELS_PER_METRE
    corners = [np.array(c) for c in ((x0, y0), (x0, y1), (x1, y1), (x1, y0))]
    for start, end in itertools.pairwise(corners):
        panel.image[panel.segment(start, end, wall)] = WALL
    for jar in state["jars"]:
        panel.image[panel.footprints([jar])] = TARGET if jar["is_target"] else JAR
    x, y, yaw = state["hand"]
    h = state["wrist_half_extent"]
    c, s = np.cos(yaw), np.sin(yaw)
    along, across = -(panel.x - x) * s + (panel.y - y) * c, (panel.x - x) * c + (panel.y - y) * s
    panel.image[(np.abs(along) <= h) & (np.abs(across) <= h)] = HAND
    arm_end = np.array([x + (h + state["arm_length"]) * s, y - (h + state["arm_length"]) * c])
    panel.image[panel.segment(np.array([x, y]), arm_end, state["arm_half_width"])] = HAND
    fx, fy, fyaw = state["finger"]
    length = state["finger_length"]
    tip = np.array([fx - length * np.sin(fyaw), fy + length * np.cos(fyaw)])
    panel.image[panel.segment(np.array([fx, fy]), tip, 2 / PIXELS_PER_METRE)] = FINGER
    for px, py, *_ in state["contacts"]:
        panel.image[np.hypot(panel.x - px, panel.y - py) <= 4 / PIXELS_PER_METRE] = CONTACT
    return panel.image


def _map_panel(state: dict[str, Any], key: str, outlines: np.ndarray, height: int) -> np.ndarray:
    """One map channel over the map's bounds, with the true ``outlines`` (a pixel mask of
    the same panel) in magenta, padded to ``height``."""
    panel = _Panel(state["bounds"])
    values = panel.grid(np.asarray(state[key], dtype=float))
    if key == "mean":
        limit = max(float(np.abs(state[key]).max()), 1e-6)
        panel.image[:] = _ramp(0.5 + 0.5 * values / limit, DIVERGING)
        panel.image[_edges(values < 0)] = FINGER
    else:
        top = max(float(np.max(state[key])), 1e-9) if key == "std" else 1.0
        panel.image[:] = _ramp(values / top, SEQUENTIAL)
    panel.image[outlines] = OUTLINE
    padded = np.empty((height, panel.width, 3), dtype=np.uint8)
    padded[:] = BACKGROUND
    padded[height - panel.height :] = panel.image
    return padded


def render_frame(state: dict[str, Any], map_mode: str) -> np.ndarray:
    """An RGB ``(H, W, 3)`` uint8 picture, drawn with numpy alone: the scene from above (the
    cupboard and what is in front of it), then the map's panels (GPIS mean with its zero
    level in black, and std; or the occupancy), each with the jars' true outlines in
    magenta."""
    scene = _scene_panel(state)
    keys = {"gpis": ["mean", "std"], "occupancy": ["occupancy"], "none": []}[map_mode]
    outlines = _edges(_Panel(state["bounds"]).footprints(state["jars"])) if keys else None
    panels = [scene] + [_map_panel(state, key, outlines, scene.shape[0]) for key in keys]
    gap = np.empty((scene.shape[0], 4, 3), dtype=np.uint8)
    gap[:] = 255
    parts = [panels[0]]
    for panel in panels[1:]:
        parts += [gap, panel]
    return np.concatenate(parts, axis=1)


def save_gif(
    frames: list[np.ndarray], path: str | Path, fps: int = 10, comment: str | None = None
) -> Path:
    """Writes ``frames`` (RGB arrays) to a GIF with matplotlib's Pillow writer; ``comment``,
    if given, is stored in the GIF (Pillow reads it back as ``Image.open(path).info``'s
    ``comment``)."""
    _matplotlib()
    from PIL import Image

    if not frames:
        raise ValueError("frames must hold at least one frame, got none")
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    images = [Image.fromarray(frame) for frame in frames]
    extra = {} if comment is None else {"comment": comment.encode()}
    images[0].save(
        path, save_all=True, append_images=images[1:], duration=int(1000 / fps), loop=0, **extra
    )
    return path
