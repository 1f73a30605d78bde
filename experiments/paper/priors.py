"""The prior options the paper's table compares. Each is a set of environment settings
(``prior_mean``, ``circle_prior_diameter``, ``free_space_offset``,
``prior_wall_clearance``), so the chosen option is directly the settings the environment
should run.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

POSITIVE_MEAN = 0.01
FREE_SPACE_OFFSET = 0.01
WALL_CLEARANCE = 0.005


@dataclass(frozen=True)
class PriorOption:
    """How a map is started: a constant mean, circle priors, depth free-space points, and
    whether depth points on the walls are left out."""

    name: str
    prior_mean: float = 0.0
    circle_prior_diameter: float | None = None
    free_space_offset: float | None = None
    wall_clearance: float = 0.0

    def settings(self) -> dict[str, Any]:
        """The option as environment settings."""
        return {
            "prior_mean": self.prior_mean,
            "circle_prior_diameter": self.circle_prior_diameter,
            "free_space_offset": self.free_space_offset,
            "prior_wall_clearance": self.wall_clearance,
        }


_FREE = f"free space + mean +{POSITIVE_MEAN:g}"

PRIOR_OPTIONS = (
    PriorOption("mean 0"),
    PriorOption(f"mean +{POSITIVE_MEAN:g}", prior_mean=POSITIVE_MEAN),
    PriorOption(f"mean +{5 * POSITIVE_MEAN:g}", prior_mean=5 * POSITIVE_MEAN),
    PriorOption("circle 0.03", circle_prior_diameter=0.03),
    PriorOption("circle 0.2", circle_prior_diameter=0.2),
    PriorOption(
        f"circle 0.03 + mean +{POSITIVE_MEAN:g}",
        prior_mean=POSITIVE_MEAN,
        circle_prior_diameter=0.03,
    ),
    PriorOption(_FREE, prior_mean=POSITIVE_MEAN, free_space_offset=FREE_SPACE_OFFSET),
    PriorOption(
        f"{_FREE}, walls out",
        prior_mean=POSITIVE_MEAN,
        free_space_offset=FREE_SPACE_OFFSET,
        wall_clearance=WALL_CLEARANCE,
    ),
)


def option_named(name: str) -> PriorOption:
    """The option called ``name``."""
    return next(o for o in PRIOR_OPTIONS if o.name == name)
