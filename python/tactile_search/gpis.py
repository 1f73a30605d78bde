"""``Gpis``: a Gaussian Process Implicit Surface map over a 2D domain.

The map holds an exact posterior over an implicit function f of the plane, with f < 0
inside objects, f = 0 on their surfaces and f > 0 in free space. Depth points are value
observations (f = 0); a touch is a contact: f = 0 at the point and ∇f = the outward normal.
The posterior mean and variance are kept on an (H, W) grid and updated incrementally as rows
are added, in O(k·n·G) for k new rows, n rows held and G grid cells. See ``docs/DESIGN.md`` §3.

Example::

    g = Gpis(bounds=((-0.3, 0.3), (0.0, 0.3)), shape=(64, 64))
    g.add_values(depth_points)                      # f = 0 on seen surfaces
    g.add_contacts(touch_points, touch_normals)     # f = 0 and ∇f = normal
    mean, var = g.predict(query_points)
    g.mean, g.variance                               # (64, 64) float64 grids
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from tactile_search import _core
from tactile_search._validation import as_points, as_real, as_vector

#: The defaults of the map and of its ``add_*`` calls, from the core (``_core.gpis_defaults()``:
#: ``psi_factor``, ``prior_mean``, ``max_rows``, ``value_noise_std``, ``contact_noise_std``,
#: ``normal_noise_std``, ``circle_diameter``); the signatures below show them.
DEFAULTS: dict[str, float | int] = _core.gpis_defaults()


class Gpis:
    """A GPIS map with the thin-plate kernel and an exact, incremental posterior.

    Args:
        bounds: ``((x0, x1), (y0, y1))`` in metres. Observations and queries must lie inside.
        shape: ``(H, W)`` of the grid. Cell ``(i, j)`` has its centre at
            ``(x0 + (j + 0.5)(x1 - x0)/W, y0 + (i + 0.5)(y1 - y0)/H)``: row ``i`` runs along
            y, column ``j`` along x.
        psi: the kernel's ψ, fixed for the map's life. ``None`` (default) gives
            ``DEFAULTS["psi_factor"]`` (the core's) times the bounds' diagonal; a ψ below the
            diagonal is refused, because the thin-plate kernel is not a covariance beyond
            r = ψ.
        prior_mean: constant prior mean of f. A positive value makes unobserved space read
            as free.
        max_rows: the most GP rows the map will hold (a value is 1 row, a contact 3). An
            ``add_*`` call that could exceed it raises ``ValueError`` and adds nothing.

    Raises:
        TypeError: an argument of the wrong kind.
        ValueError: an argument of the right kind with a wrong value.
        RuntimeError: a call while another thread's call on the same map is running (the
            map releases the GIL while it computes and serves one thread at a time; give
            each thread its own map).
    """

    def __init__(
        self,
        bounds: ArrayLike,
        shape: tuple[int, int],
        psi: float | None = None,
        prior_mean: float = DEFAULTS["prior_mean"],
        max_rows: int = int(DEFAULTS["max_rows"]),
    ) -> None:
        # The core checks every argument (TypeError / ValueError naming it).
        self._core = _core.GpisCore(bounds, shape, psi, prior_mean, max_rows)

    def add_values(
        self,
        points: ArrayLike,
        values: ArrayLike | None = None,
        noise_std: float = DEFAULTS["value_noise_std"],
    ) -> int:
        """Adds value observations f(points[i]) = values[i] (0, a surface, by default).

        Args:
            points: ``(N, 2)`` positions inside the bounds.
            values: ``(N,)`` observed f, or ``None`` for 0.
            noise_std: standard deviation of the value noise (depth is noisier than touch).

        Returns:
            The number of rows added. A point whose row would make the covariance singular
            (e.g. an exact noise-free duplicate) is rejected and counted in
            ``last_report["rejected_degenerate"]``.
        """
        points = as_points("points", points)
        if values is not None:
            values = as_vector("values", values, len(points))
        noise_std = as_real("noise_std", noise_std, minimum=0.0)
        return self._core.add_values(points, values, noise_std)

    def add_contacts(
        self,
        points: ArrayLike,
        normals: ArrayLike,
        noise_std: float = DEFAULTS["contact_noise_std"],
        normal_noise_std: float = DEFAULTS["normal_noise_std"],
        skip_below_variance: float | None = None,
    ) -> int:
        """Adds contacts: f(points[i]) = 0 and ∇f(points[i]) = normals[i] / ‖normals[i]‖.

        Args:
            points: ``(N, 2)`` contact positions inside the bounds.
            normals: ``(N, 2)`` outward normals, non-zero (they are normalised).
            noise_std: standard deviation of the contact position's value noise.
            normal_noise_std: standard deviation of each normal component's noise.
            skip_below_variance: if given, a contact whose posterior variance of f at its
                point (given everything added before it) is below this is skipped as
                uninformative, and counted in ``last_report["skipped_uninformative"]``.

        Returns:
            The number of rows added (3 per contact accepted).
        """
        points = as_points("points", points)
        normals = as_points("normals", normals)
        if len(normals) != len(points):
            raise ValueError(
                f"normals must have one row per point ({len(points)}), got {len(normals)}"
            )
        return self._core.add_contacts(
            points,
            normals,
            as_real("noise_std", noise_std, minimum=0.0),
            as_real("normal_noise_std", normal_noise_std, minimum=0.0),
            None
            if skip_below_variance is None
            else as_real("skip_below_variance", skip_below_variance, minimum=0.0),
        )

    def add_circle_prior(
        self,
        centre: ArrayLike,
        diameter: float = DEFAULTS["circle_diameter"],
        noise_std: float = DEFAULTS["contact_noise_std"],
        normal_noise_std: float = DEFAULTS["normal_noise_std"],
    ) -> int:
        """Adds the paper's circle prior: four contacts equally spaced on a circle.

        The contacts sit at angles 0, 90, 180 and 270 degrees on a circle of ``diameter``
        around ``centre`` (x, y), each with its outward radial normal, so f is shaped
        (negative inside) before any touch. The default diameter is the paper's; a circle
        much larger than the object distorts the shape (its Fig. 8). The four points must lie
        inside the bounds. Returns the number of rows added (12).
        """
        centre = as_vector("centre", centre, 2)
        return self._core.add_circle_prior(
            (float(centre[0]), float(centre[1])),
            as_real("diameter", diameter, minimum=0.0),
            as_real("noise_std", noise_std, minimum=0.0),
            as_real("normal_noise_std", normal_noise_std, minimum=0.0),
        )

    def add_observations(self, observations: _core.Observations) -> int:
        """Adds ready-made observations in one call, in their order: the rows of
        ``_core.depth_prior``, the environment's depth prior, so that a map started this way
        holds exactly what the environment's map holds after reset.

        Returns:
            The number of rows added.

        Raises:
            TypeError: ``observations`` is not a ``_core.Observations``.
            ValueError: they do not fit in ``free_rows`` or lie outside the bounds.
        """
        if not isinstance(observations, _core.Observations):
            raise TypeError(
                "observations must be a tactile_search._core.Observations (from "
                f"_core.depth_prior), got {type(observations).__name__}"
            )
        return self._core.add_observations(observations)

    def predict(
        self, points: ArrayLike, return_gradient: bool = False
    ) -> (
        tuple[NDArray[np.float64], NDArray[np.float64]]
        | tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]
    ):
        """Posterior mean and variance of f at ``(M, 2)`` points inside the bounds.

        With ``return_gradient=True`` also returns the ``(M, 2)`` gradient of the posterior
        mean, ∇E[f], which near surfaces approximates the gradient of a signed distance.
        Cost O(n²·M).
        """
        mean, variance, gradient = self._core.predict(as_points("points", points))
        if return_gradient:
            return mean, variance, gradient
        return mean, variance

    def recompute_from_scratch(self) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """The grid (mean, variance) recomputed from all rows at once, in O(n³ + n²·G).

        The paper's approach; kept as the reference the incremental update must match.
        """
        return self._core.recompute_from_scratch()

    def clear(self) -> None:
        """Forgets every observation, keeping ψ, the grid and the allocated storage."""
        self._core.clear()

    @property
    def mean(self) -> NDArray[np.float64]:
        """Posterior mean of f on the grid, ``(H, W)`` float64 (a copy)."""
        return self._core.mean

    @property
    def variance(self) -> NDArray[np.float64]:
        """Posterior variance of f on the grid, ``(H, W)`` float64 (a copy), never negative."""
        return self._core.variance

    @property
    def cell_centres(self) -> NDArray[np.float64]:
        """Centres of the grid cells as ``(H, W, 2)`` float64 ``(x, y)``."""
        height, width = self.shape
        return self._core.cell_centres.reshape(height, width, 2)

    @property
    def psi(self) -> float:
        """The kernel's ψ."""
        return self._core.psi

    @property
    def n_rows(self) -> int:
        """GP rows held (1 per value, 3 per contact)."""
        return self._core.n_rows

    @property
    def max_rows(self) -> int:
        """The most rows the map will hold."""
        return self._core.max_rows

    @property
    def free_rows(self) -> int:
        """Rows that can still be added."""
        return self._core.free_rows

    @property
    def prior_mean(self) -> float:
        """The constant prior mean of f."""
        return self._core.prior_mean

    @property
    def bounds(self) -> tuple[tuple[float, float], tuple[float, float]]:
        """``((x0, x1), (y0, y1))``."""
        (x0, x1), (y0, y1) = self._core.bounds
        return (x0, x1), (y0, y1)

    @property
    def shape(self) -> tuple[int, int]:
        """``(H, W)`` of the grid."""
        height, width = self._core.shape
        return (height, width)

    @property
    def memory_bytes(self) -> int:
        """Bytes held by the map's numeric state (grows by doubling up to ``max_rows``)."""
        return self._core.memory_bytes

    @property
    def last_report(self) -> dict[str, int]:
        """What the last ``add_*`` call did: ``added_rows``, ``added_observations``,
        ``skipped_uninformative``, ``rejected_degenerate``."""
        return self._core.last_report

    def __repr__(self) -> str:
        return (
            f"Gpis(bounds={self.bounds}, shape={self.shape}, psi={self.psi:.4g}, "
            f"prior_mean={self.prior_mean}, n_rows={self.n_rows}, max_rows={self.max_rows})"
        )
