"""The GPIS update timing of the paper's Fig. 9: one contact appended incrementally against
the full recompute, on maps of exactly n rows.

It lives here, beside the figure code (``experiments.paper.cli`` times Fig. 9's rows with
it), and ``benchmarks.gpis_append`` is its command-line front end (the table, the targets and
the plot of ``make bench``): the method is the experiment's, so the dependency runs from the
benchmark to the experiments, and the experiments import no benchmark.

The map: the environment's default cupboard interior (x in [-w/2, w/2], y in [0, d], from the
core's ``cupboard_width`` and ``cupboard_depth``), a grid x grid grid, default psi; n rows =
value rows at random points (noise_std 0.002) plus about 10 % of the rows as contacts, from a
fixed seed, filled up with value points until exactly n.

- append: every timed append starts from a map of n .. n + 3 (R - 1) rows, where
  R = max(1, n // 150) (about 2 % of n in rows): a map with exactly n rows is built
  (untimed) with ``max_rows = n + 3 R``, so that its storage has room for R contacts and
  no timed append reallocates, then receives R single-contact appends, then is rebuilt.
  The time includes the Python wrapper's argument checks (what a user pays).
- full recompute: ``recompute_from_scratch()`` on a map of exactly n rows built with
  ``Gpis``'s default ``max_rows`` (``DEFAULT_MAX_ROWS``, read from its signature).
"""

from __future__ import annotations

import inspect
import time

import numpy as np

from tactile_search import Gpis
from tactile_search.envs.config import SETTINGS

_DEFAULTS = {s["key"]: s["default"] for s in SETTINGS}
#: The map's bounds: the environment's default cupboard interior in the slice plane.
BOUNDS = (
    (-_DEFAULTS["cupboard_width"] / 2, _DEFAULTS["cupboard_width"] / 2),
    (0.0, _DEFAULTS["cupboard_depth"]),
)
VALUE_NOISE_STD = 0.002
CONTACT_NOISE_STD = 0.0005
NORMAL_NOISE_STD = 0.05
#: ``Gpis``'s default row capacity.
DEFAULT_MAX_ROWS: int = inspect.signature(Gpis).parameters["max_rows"].default
CONTACT_POINT = np.array([[0.031, 0.137]])
CONTACT_NORMAL = np.array([[0.6, -0.8]])


def random_points(rng: np.random.Generator, count: int) -> np.ndarray:
    """``count`` points uniform in the bounds, ``(count, 2)``."""
    (x0, x1), (y0, y1) = BOUNDS
    return np.column_stack([rng.uniform(x0, x1, count), rng.uniform(y0, y1, count)])


def build_map(n: int, grid: int, max_rows: int, seed: int) -> Gpis:
    """A map holding exactly ``n`` rows (the same rows for the same ``n`` and ``seed``)."""
    rng = np.random.default_rng(seed + n)
    g = Gpis(BOUNDS, (grid, grid), max_rows=max_rows)
    n_contacts = n // 30
    g.add_values(random_points(rng, n - 3 * n_contacts), noise_std=VALUE_NOISE_STD)
    angles = rng.uniform(0.0, 2.0 * np.pi, n_contacts)
    g.add_contacts(
        random_points(rng, n_contacts),
        np.column_stack([np.cos(angles), np.sin(angles)]),
        noise_std=CONTACT_NOISE_STD,
        normal_noise_std=NORMAL_NOISE_STD,
    )
    while g.n_rows < n:  # a rejected (degenerate) row is replaced by a fresh value point
        g.add_values(random_points(rng, n - g.n_rows), noise_std=VALUE_NOISE_STD)
    if g.n_rows != n:
        raise RuntimeError(f"built {g.n_rows} rows instead of {n}")
    return g


def append_one_contact(g: Gpis) -> float:
    """Seconds taken by appending one contact (3 rows) to ``g``."""
    start = time.perf_counter()
    added = g.add_contacts(
        CONTACT_POINT,
        CONTACT_NORMAL,
        noise_std=CONTACT_NOISE_STD,
        normal_noise_std=NORMAL_NOISE_STD,
    )
    elapsed = time.perf_counter() - start
    if added != 3:
        raise RuntimeError(f"the contact added {added} rows instead of 3")
    return elapsed


def time_appends(n: int, grid: int, repeats: int, seed: int) -> list[float]:
    """``repeats`` single-contact append times (s), each starting from n .. n + 3 (R - 1)."""
    per_build = max(1, n // 150)
    times: list[float] = []
    g = None
    while len(times) < repeats:
        if g is None or g.free_rows < 3:
            g = build_map(n, grid, max_rows=n + 3 * per_build, seed=seed)
        times.append(append_one_contact(g))
    return times


def time_full(g: Gpis, repeats: int) -> list[float]:
    """``repeats`` times (s) of the full recompute of ``g``."""
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        g.recompute_from_scratch()
        times.append(time.perf_counter() - start)
    return times
