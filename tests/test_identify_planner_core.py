"""The core's identify planner (``tactile_search._core.IdentifyPlanner``, which
``agents.scripted.IdentifyPlanner`` is a face of): it makes the pinned actions of the Python
reference it replaced (``BeliefIdentifyPlanner``), one episode at a time and over a batch on
every core, refuses settings it cannot plan in, and follows another agent's probes."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from agents.scripted import BeliefIdentifyPlanner, IdentifyPlanner
from tactile_search import CupboardSearchEnv, _core
from tests.planner_decisions import IDENTIFY_LAYOUTS, identify_settings, record, record_batch

PINNED = Path(__file__).parent / "data" / "identify_planner_decisions.npz"


@pytest.fixture(scope="module")
def pinned() -> dict[str, np.ndarray]:
    with np.load(PINNED) as data:
        return {key: data[key] for key in data.files}


def test_the_pinned_episodes_claim_inspect_and_time_out(pinned) -> None:
    """The pinned layouts hold what the rules decide: claims, and episodes without one."""
    assert tuple(pinned["layout_seeds"]) == IDENTIFY_LAYOUTS
    claims = pinned["actions"][:, 3]
    assert 0 < claims.sum() < len(IDENTIFY_LAYOUTS)
    assert pinned["episode_lengths"].max() >= 5


@pytest.mark.parametrize("planner", [IdentifyPlanner, BeliefIdentifyPlanner])
def test_the_core_and_the_python_reference_make_the_pinned_actions(planner, pinned) -> None:
    made = record(planner, IDENTIFY_LAYOUTS, identify_settings())
    np.testing.assert_array_equal(made["episode_lengths"], pinned["episode_lengths"])
    np.testing.assert_array_equal(made["actions"], pinned["actions"])


def test_a_batch_of_identify_planners_makes_each_episodes_pinned_actions(pinned) -> None:
    made = record_batch(_core.IdentifyPlanner, IDENTIFY_LAYOUTS, identify_settings())
    assert made["actions"].shape[1] == 4
    np.testing.assert_array_equal(made["episode_lengths"], pinned["episode_lengths"])
    np.testing.assert_array_equal(made["actions"], pinned["actions"])


def test_the_identify_planner_refuses_settings_it_cannot_plan_in() -> None:
    search = CupboardSearchEnv(map="gpis", action_mode="probe").config.core
    with pytest.raises(ValueError, match="needs task='identify', got task='search'"):
        _core.IdentifyPlanner(search, 1)
    round_target = {**identify_settings(), "target_shape": "round", "round_fraction": 0.0}
    with pytest.raises(ValueError, match="needs target_shape='square', got target_shape='round'"):
        _core.IdentifyPlanner(CupboardSearchEnv(**round_target).config.core, 1)
    occupancy = {**identify_settings(), "map": "occupancy"}
    with pytest.raises(ValueError, match="needs map='gpis', got map='occupancy'"):
        _core.IdentifyPlanner(CupboardSearchEnv(**occupancy).config.core, 1)


def test_the_face_follows_an_identify_actions_probe_and_refuses_anything_else() -> None:
    env = CupboardSearchEnv(**identify_settings())
    observation, _ = env.reset(seed=IDENTIFY_LAYOUTS[0])
    planner = IdentifyPlanner()
    with pytest.raises(RuntimeError, match="call reset before"):
        planner.follow(np.array([0, 0, 0, 0]))
    planner.reset(env, observation, {})
    action = planner.act(observation)
    assert action.shape == (4,) and env.action_space.contains(action)
    planner.follow(np.array([1, 2, 3, 0]))
    planner.follow(np.array([1, 2, 3]))
    with pytest.raises(ValueError, match=r"follow needs a probe \(lane, depth, sweep\) below"):
        planner.follow(np.array([1, 2, 99, 0]))
