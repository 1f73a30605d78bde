"""Pictures of an episode: the scene from above beside the agent's map, and GIFs.

``render_frame`` draws what ``CupboardSearchEnv.render()`` returns (an RGB array) with
numpy alone, from what the core hands it (``EpisodeBatch.render_state``: the jars' pixels,
the hand, the readings and the map's grids by name), so the environment renders with only
its own dependencies; ``save_gif`` writes a list of frames and needs Pillow (the ``plots``
extra).
"""

from __future__ import annotations

import itertools
from pathlib import Path
from typing import Any

import numpy as np

#: How to get what writing GIFs needs: the ``plots`` extra.
PLOTS_EXTRA = "pip install 'tactile_search[plots]'"


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
DECOY = np.array([123, 104, 238], dtype=np.uint8)
CLAIM_RIGHT = np.array([0, 170, 0], dtype=np.uint8)
CLAIM_WRONG = np.array([255, 140, 0], dtype=np.uint8)
#: Width of the ring drawn around a claimed jar, m.
CLAIM_RING = 0.006
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
    # Typed here: numpy types an array indexed by an array as Any.
    colours: np.ndarray = ((1 - t) * anchors[low] + t * anchors[low + 1]).round().astype(np.uint8)
    return colours


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

    def segment(self, start: np.ndarray, end: np.ndarray, half_width: float) -> np.ndarray:
        """Pixels within ``half_width`` of the segment from ``start`` to ``end``."""
        d = end - start
        t = ((self.x - start[0]) * d[0] + (self.y - start[1]) * d[1]) / max(d @ d, 1e-12)
        t = np.clip(t, 0.0, 1.0)
        distance = np.hypot(self.x - start[0] - t * d[0], self.y - start[1] - t * d[1])
        near: np.ndarray = distance <= half_width  # typed: numpy's comparison is Any
        return near

    def grid(self, values: np.ndarray) -> np.ndarray:
        """A (H, W) map grid over the same bounds (row 0 at y0), nearest cell per pixel."""
        (x0, x1), (y0, y1) = self.bounds
        h, w = values.shape
        i = np.clip(((self.y - y0) / (y1 - y0) * h).astype(int), 0, h - 1)
        j = np.clip(((self.x - x0) / (x1 - x0) * w).astype(int), 0, w - 1)
        cells: np.ndarray = values[i, j]  # typed: numpy types array indexing as Any
        return cells


def _edges(mask: np.ndarray) -> np.ndarray:
    """The pixels of ``mask`` with a neighbour outside it."""
    inner = mask.copy()
    inner[1:] &= mask[:-1]
    inner[:-1] &= mask[1:]
    inner[:, 1:] &= mask[:, :-1]
    inner[:, :-1] &= mask[:, 1:]
    edges: np.ndarray = mask & ~inner  # typed: numpy's operators on arrays are Any
    return edges


def _scene_panel(state: dict[str, Any]) -> np.ndarray:
    """The cupboard from above: walls, jars (the target red, hidden decoys purple), the
    hand, the readings, and a claim's ring around the jar it named (green on the target,
    orange on another jar; around the fingertip when it named none)."""
    (x0, x1), (y0, y1) = state["bounds"]
    panel = _Panel(((x0, x1), (y0 - SCENE_MARGIN, y1)))
    wall = 3 / PIXELS_PER_METRE
    corners = [np.array(c) for c in ((x0, y0), (x0, y1), (x1, y1), (x1, y0))]
    for start, end in itertools.pairwise(corners):
        panel.image[panel.segment(start, end, wall)] = WALL
    jar_pixels = state["jar_pixels"]
    panel.image[jar_pixels >= 0] = JAR
    for index, jar in enumerate(state["jars"]):
        if jar["is_target"]:
            panel.image[jar_pixels == index] = TARGET
        elif jar.get("is_decoy"):
            panel.image[jar_pixels == index] = DECOY
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
    claim = state.get("claim")
    if claim is not None:
        centre = tip if claim["jar"] is None else state["jars"][claim["jar"]]
        cx, cy = (centre[0], centre[1]) if claim["jar"] is None else (centre["x"], centre["y"])
        radius = 0.0 if claim["jar"] is None else 1.5 * centre["half_width"]
        distance = np.hypot(panel.x - cx, panel.y - cy)
        ring = (distance >= radius + CLAIM_RING / 2) & (distance <= radius + CLAIM_RING * 1.5)
        panel.image[ring] = CLAIM_RIGHT if claim["correct"] else CLAIM_WRONG
    return panel.image


def _map_panel(name: str, grid: np.ndarray, state: dict[str, Any], outlines: np.ndarray,
               height: int) -> np.ndarray:  # fmt: skip
    """The map's grid ``name`` over the map's bounds, with the true ``outlines`` (a pixel
    mask of the same panel) in magenta, padded to ``height``: a signed ``mean`` on a
    diverging ramp with its zero level in black, a ``std`` scaled to its largest value,
    anything else (a probability) on [0, 1]."""
    panel = _Panel(state["bounds"])
    values = panel.grid(np.asarray(grid, dtype=float))
    if name == "mean":
        limit = max(float(np.abs(grid).max()), 1e-6)
        panel.image[:] = _ramp(0.5 + 0.5 * values / limit, DIVERGING)
        panel.image[_edges(values < 0)] = FINGER
    else:
        top = max(float(np.max(grid)), 1e-9) if name == "std" else 1.0
        panel.image[:] = _ramp(values / top, SEQUENTIAL)
    panel.image[outlines] = OUTLINE
    padded = np.empty((height, panel.width, 3), dtype=np.uint8)
    padded[:] = BACKGROUND
    padded[height - panel.height :] = panel.image
    return padded


def episode_frame(batch: Any, index: int) -> np.ndarray:
    """The frame of episode ``index`` of ``batch`` (a ``_core.EpisodeBatch``)."""
    return render_frame(batch.render_state(index, PIXELS_PER_METRE, SCENE_MARGIN))


def render_frame(state: dict[str, Any]) -> np.ndarray:
    """An RGB ``(H, W, 3)`` uint8 picture of a ``render_state`` made with
    ``PIXELS_PER_METRE`` and ``SCENE_MARGIN`` (``episode_frame``), drawn with numpy alone:
    the scene from above (the cupboard and what is in front of it), then a panel per grid
    of the map, in the core's order (GPIS mean with its zero level in black, and std; or
    the occupancy), each with the jars' true outlines in magenta; in the map task a last
    panel, the reconstruction its score is measured on, drawn as a GPIS mean."""
    scene = _scene_panel(state)
    # The map's panels are the scene panel's rows behind the opening.
    map_height = _Panel(state["bounds"]).height
    outlines = _edges(state["jar_pixels"][:map_height] >= 0)
    grids = dict(state["map"])
    if state.get("score_mean") is not None:
        # The map task's reconstruction, drawn as a GPIS mean against the true outlines.
        grids["score"] = state["score_mean"]
    panels = [scene] + [
        _map_panel("mean" if name == "score" else name, grid, state, outlines, scene.shape[0])
        for name, grid in grids.items()
    ]
    gap = np.empty((scene.shape[0], 4, 3), dtype=np.uint8)
    gap[:] = 255
    parts = [panels[0]]
    for panel in panels[1:]:
        parts += [gap, panel]
    return np.concatenate(parts, axis=1)


def save_gif(
    frames: list[np.ndarray], path: str | Path, fps: int = 10, comment: str | None = None
) -> Path:
    """Writes ``frames`` (RGB arrays) to a GIF with Pillow (the ``plots`` extra);
    ``comment``, if given, is stored in the GIF (Pillow reads it back as
    ``Image.open(path).info``'s ``comment``)."""
    try:
        from PIL import Image
    except ModuleNotFoundError as error:
        raise ImportError(
            f"writing GIFs needs Pillow, which is not installed: {PLOTS_EXTRA}"
        ) from error

    if not frames:
        raise ValueError("frames must hold at least one frame, got none")
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    images = [Image.fromarray(frame) for frame in frames]
    extra: dict[str, Any] = {} if comment is None else {"comment": comment.encode()}
    images[0].save(
        path, save_all=True, append_images=images[1:], duration=int(1000 / fps), loop=0, **extra
    )
    return path
