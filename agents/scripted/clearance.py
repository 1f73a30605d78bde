"""Where the hand can go without coming near a jar: the planner's clearance queries on its
belief.

A ``ClearanceField`` is the distance to the nearest blocked cell of the map, padded beyond
the cupboard (the side walls block; the space outside the opening is free).
``deepest_clear`` is how deep the wrist can go straight in along a lane, and ``safe_angle``
how far the finger can turn at a wrist position, the wrist's corners and the arm kept clear
and the turn stopped where the finger would meet a seen jar.
"""

from __future__ import annotations

import numpy as np

from agents.scripted.geometry import Geometry
from agents.scripted.search_map import SearchMap, distance_to

# Clearance kept between the wrist or arm and a cell that may hold a jar, m.
MARGIN = 0.004
# Extra rows and columns of the clearance field beyond the map (outside the cupboard).
PAD_CELLS = 10


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


def deepest_clear(
    g: Geometry, field: ClearanceField, solid: ClearanceField, x: float
) -> float | None:
    """The deepest wrist depth along lane ``x`` the wrist reaches without coming near a cell
    that may hold a jar (``field``), the fingertip ahead clear of seen jars (``solid``); None
    if the lane is blocked at the opening."""
    ys = np.arange(-g.wrist_half_extent, g.depth, 0.5 * g.cell)
    lane = np.full(ys.shape, x)
    wrist_room = g.wrist_half_extent + MARGIN + 0.5 * g.cell
    clear = field.at(lane, ys + g.wrist_half_extent) >= wrist_room
    clear &= field.at(lane, ys) >= wrist_room
    # The fingertip ahead must not run into a seen jar either.
    clear &= solid.at(lane, ys + g.reach) >= 0.5 * g.cell
    stop = len(ys) if clear.all() else int(np.argmin(clear))
    return None if stop == 0 else ys[stop - 1]


def safe_angle(
    g: Geometry, field: ClearanceField, solid: ClearanceField, x: float, y: float, side: float
) -> float:
    """Largest turn towards ``side`` (+1: +x) at wrist ``(x, y)`` keeping the wrist's corners
    and the arm clear (``field``), and stopping where the finger would meet a seen jar
    (``solid``). The turns tried are the probe controller's: steps of its sweep rate up to
    the largest sweep angle of the env's settings (``probe_sweep_rate``,
    ``probe_max_angle``)."""
    angles = np.arange(g.probe_sweep_rate, g.probe_max_angle + 1e-9, g.probe_sweep_rate)
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
