"""Type stubs of the compiled module ``tactile_search._core`` (Rust, pyo3)."""

import numpy as np
from numpy.typing import NDArray

__version__: str

class GpisCore:
    """The Rust GPIS behind ``tactile_search.Gpis``; prefer that class, which validates input."""

    def __init__(
        self,
        bounds: tuple[tuple[float, float], tuple[float, float]],
        shape: tuple[int, int],
        psi: float | None,
        prior_mean: float,
        max_rows: int,
    ) -> None: ...
    def add_values(
        self, points: NDArray[np.float64], values: NDArray[np.float64] | None, noise_std: float
    ) -> int: ...
    def add_contacts(
        self,
        points: NDArray[np.float64],
        normals: NDArray[np.float64],
        noise_std: float,
        normal_noise_std: float,
        skip_below_variance: float | None,
    ) -> int: ...
    def add_circle_prior(
        self,
        centre: tuple[float, float],
        diameter: float,
        noise_std: float,
        normal_noise_std: float,
    ) -> int: ...
    def predict(
        self, points: NDArray[np.float64]
    ) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]: ...
    def recompute_from_scratch(self) -> tuple[NDArray[np.float64], NDArray[np.float64]]: ...
    def clear(self) -> None: ...
    @property
    def mean(self) -> NDArray[np.float64]: ...
    @property
    def variance(self) -> NDArray[np.float64]: ...
    @property
    def cell_centres(self) -> NDArray[np.float64]: ...
    @property
    def psi(self) -> float: ...
    @property
    def n_rows(self) -> int: ...
    @property
    def max_rows(self) -> int: ...
    @property
    def free_rows(self) -> int: ...
    @property
    def prior_mean(self) -> float: ...
    @property
    def bounds(self) -> tuple[tuple[float, float], tuple[float, float]]: ...
    @property
    def shape(self) -> tuple[int, int]: ...
    @property
    def memory_bytes(self) -> int: ...
    @property
    def last_report(self) -> dict[str, int]: ...
