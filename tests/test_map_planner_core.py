"""The core's greedy mappers (``tactile_search._core.MapPlanner``, which ``VarianceMapper`` and
``OccupancyMapper`` are faces of): each makes the pinned probes of the Python reference it
replaced (``BeliefVarianceMapper``, ``BeliefOccupancyMapper``), one episode at a time and over
a batch on every core, and refuses settings it cannot plan in."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from agents.scripted import CORE_PLANNERS
from tactile_search import CupboardSearchEnv, _core
from tests.planner_decisions import map_settings, pinned_episodes, record, record_batch

MAPPERS = ("variance_mapper", "occupancy_mapper")


def pinned(mapper: str) -> dict[str, np.ndarray]:
    with np.load(Path(__file__).parent / "data" / f"{mapper}_decisions.npz") as data:
        return {key: data[key] for key in data.files}


@pytest.mark.parametrize("mapper", MAPPERS)
@pytest.mark.parametrize("implementation", ["core", "python reference"])
def test_the_core_and_the_python_reference_make_the_pinned_probes(mapper, implementation) -> None:
    face, reference = CORE_PLANNERS[mapper]
    made = record(face if implementation == "core" else reference, *pinned_episodes(mapper))
    expected = pinned(mapper)
    np.testing.assert_array_equal(made["episode_lengths"], expected["episode_lengths"])
    np.testing.assert_array_equal(made["actions"], expected["actions"])


@pytest.mark.parametrize("mapper", MAPPERS)
def test_a_batch_of_mappers_makes_each_episodes_pinned_probes(mapper) -> None:
    made = record_batch(_core.MapPlanner, *pinned_episodes(mapper))
    expected = pinned(mapper)
    assert made["actions"].shape[1] == 3
    np.testing.assert_array_equal(made["episode_lengths"], expected["episode_lengths"])
    np.testing.assert_array_equal(made["actions"], expected["actions"])


def test_the_mapper_refuses_settings_it_cannot_plan_in() -> None:
    with pytest.raises(ValueError, match="needs map='gpis', got map='none'"):
        _core.MapPlanner(CupboardSearchEnv(**map_settings("none")).config.core, 1)
    wrist = {**map_settings("gpis"), "action_mode": "wrist"}
    with pytest.raises(ValueError, match="needs action_mode='probe', got action_mode='wrist'"):
        _core.MapPlanner(CupboardSearchEnv(**wrist).config.core, 1)
