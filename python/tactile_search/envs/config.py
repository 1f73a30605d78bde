"""The constructor arguments of the cupboard-search environments, checked once.

Defaults come from the Rust core (``_core.EpisodeBatch.episode_defaults()``), so there is a
single source of truth; scene settings not listed here go in ``scene_config`` (keys:
``tactile_search._core.Scene.config_keys()``).
"""

from __future__ import annotations

import dataclasses
from typing import Any

from tactile_search import _core
from tactile_search._validation import as_count, as_real

CORE_DEFAULTS: dict[str, Any] = dict(_core.EpisodeBatch.episode_defaults())
MAP_MODES = ("gpis", "occupancy", "none")


@dataclasses.dataclass(frozen=True)
class CupboardSearchConfig:
    """Everything the environment is built from. See ``CupboardSearchEnv`` for meanings."""

    map: str = CORE_DEFAULTS["map_mode"]
    grid_shape: tuple[int, int] = tuple(CORE_DEFAULTS["grid_shape"])
    prior_mean: float = CORE_DEFAULTS["prior_mean"]
    circle_prior_diameter: float | None = CORE_DEFAULTS["circle_prior_diameter"]
    map_depth_noise_std: float = CORE_DEFAULTS["map_depth_noise_std"]
    max_prior_depth_points: int = CORE_DEFAULTS["max_prior_depth_points"]
    free_space_offset: float | None = CORE_DEFAULTS["free_space_offset"]
    contact_noise_std: float = CORE_DEFAULTS["contact_noise_std"]
    normal_noise_std: float = CORE_DEFAULTS["normal_noise_std"]
    skip_below_variance: float = CORE_DEFAULTS["skip_below_variance"]
    max_rows: int = CORE_DEFAULTS["max_rows"]
    mean_scale: float = CORE_DEFAULTS["mean_scale"]
    std_scale: float = CORE_DEFAULTS["std_scale"]
    reward_success: float = CORE_DEFAULTS["reward_success"]
    reward_step_cost: float = CORE_DEFAULTS["reward_step_cost"]
    reward_displacement: float = CORE_DEFAULTS["reward_displacement"]
    reward_tip: float = CORE_DEFAULTS["reward_tip"]
    reward_approach: float = CORE_DEFAULTS["reward_approach"]
    max_steps: int = CORE_DEFAULTS["max_steps"]
    tip_angle: float = CORE_DEFAULTS["tip_angle"]
    jar_count: int | tuple[int, int] | None = None
    depth_noise_std: float | None = None
    finger_stiffness: float | None = None
    scene_config: dict[str, Any] | None = None

    def __post_init__(self) -> None:
        if self.map not in MAP_MODES:
            raise ValueError(f"map must be one of {MAP_MODES}, got {self.map!r}")
        try:
            height, width = self.grid_shape
        except (TypeError, ValueError):
            raise ValueError(
                f"grid_shape must be a pair of ints (H, W), got {self.grid_shape!r}"
            ) from None
        object.__setattr__(
            self,
            "grid_shape",
            (as_count("grid_shape[0]", height), as_count("grid_shape[1]", width)),
        )
        # Check each scalar by its annotated type; ranges beyond these the core checks.
        for field in dataclasses.fields(self):
            value = getattr(self, field.name)
            if field.type == "int":
                as_count(field.name, value)
            elif field.type == "float":
                as_real(field.name, value)
            elif field.type == "float | None" and value is not None:
                as_real(field.name, value, minimum=0.0)
        if self.scene_config is not None and not isinstance(self.scene_config, dict):
            raise TypeError(
                f"scene_config must be a dict or None, got {type(self.scene_config).__name__}"
            )

    def scene_dict(self) -> dict[str, Any]:
        """The flat scene config handed to the core."""
        scene = dict(self.scene_config or {})
        for name in ("jar_count", "depth_noise_std", "finger_stiffness"):
            value = getattr(self, name)
            if value is not None:
                if name in scene:
                    raise ValueError(f"{name} was given both as an argument and in scene_config")
                scene[name] = value
        return scene

    def make_batch(self, seeds: list[int], threads: int | None = None) -> _core.EpisodeBatch:
        """The Rust batch of episodes for these settings (``ValueError`` on a bad value)."""
        episode = {name: getattr(self, name) for name in CORE_DEFAULTS if name != "map_mode"}
        return _core.EpisodeBatch(
            seeds,
            threads=threads,
            scene_config=self.scene_dict(),
            map_mode=self.map,
            **episode,
        )
