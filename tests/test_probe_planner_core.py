"""The core's GPIS probe planner (``tactile_search._core.ProbePlanner``, which
``GpisProbePlanner`` is a face of): it makes the pinned probes of the Python reference it
replaced, one episode at a time and over a batch on every core, and refuses bad input with
errors that name what was expected."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from agents.scripted import BeliefProbePlanner, GpisProbePlanner
from tactile_search import CupboardSearchEnv, _core
from tests.planner_decisions import SETTINGS, record, record_batch

PINNED = Path(__file__).parent / "data" / "probe_planner_decisions.npz"


@pytest.fixture(scope="module")
def pinned() -> dict[str, np.ndarray]:
    with np.load(PINNED) as data:
        return {key: data[key] for key in data.files}


@pytest.mark.parametrize("planner", [GpisProbePlanner, BeliefProbePlanner])
def test_the_core_and_the_python_reference_make_the_pinned_probes(planner, pinned) -> None:
    made = record(planner, tuple(int(s) for s in pinned["layout_seeds"]))
    np.testing.assert_array_equal(made["episode_lengths"], pinned["episode_lengths"])
    np.testing.assert_array_equal(made["actions"], pinned["actions"])


def test_a_batch_of_planners_makes_each_episodes_pinned_probes(pinned) -> None:
    """``ProbePlanner(config, n)`` acting on n episodes at once (in parallel) chooses, per
    episode, what one planner alone chooses."""
    made = record_batch(_core.ProbePlanner, tuple(int(s) for s in pinned["layout_seeds"]))
    assert made["actions"].shape[1] == 3
    np.testing.assert_array_equal(made["episode_lengths"], pinned["episode_lengths"])
    np.testing.assert_array_equal(made["actions"], pinned["actions"])


@pytest.fixture(scope="module")
def first() -> tuple[CupboardSearchEnv, dict]:
    env = CupboardSearchEnv(**SETTINGS)
    observation, _ = env.reset(seed=1_000_000)
    return env, observation


def test_the_planner_refuses_settings_it_cannot_plan_in() -> None:
    with pytest.raises(ValueError, match="needs map='gpis', got map='occupancy'"):
        _core.ProbePlanner(CupboardSearchEnv(map="occupancy", action_mode="probe").config.core, 1)
    with pytest.raises(ValueError, match="needs action_mode='probe', got action_mode='wrist'"):
        _core.ProbePlanner(CupboardSearchEnv(map="gpis").config.core, 1)
    with pytest.raises(TypeError, match="config must be an EpisodeConfig"):
        _core.ProbePlanner({"map": "gpis"}, 1)
    with pytest.raises(ValueError, match="num_envs must be at least 1"):
        _core.ProbePlanner(CupboardSearchEnv(**SETTINGS).config.core, 0)


def test_the_planner_refuses_observations_of_the_wrong_kind(first) -> None:
    env, observation = first
    planner = _core.ProbePlanner(env.config.core, 1)
    maps, proprio = observation["map"][None], observation["proprio"][None]
    with pytest.raises(ValueError, match="no episode: reset it"):
        planner.act(maps, proprio)
    planner.reset(0, observation["map"], observation["proprio"])
    with pytest.raises(TypeError, match="maps must be a uint8 numpy array of shape"):
        planner.act(maps.astype(np.float32), proprio)
    with pytest.raises(
        ValueError, match=r"maps must have shape \(n, 2, 40, 80\), got shape \(1, 2, 40, 40\)"
    ):
        planner.act(maps[..., :40], proprio)
    with pytest.raises(ValueError, match="one row per episode"):
        planner.act(np.concatenate([maps, maps]), np.concatenate([proprio, proprio]))
    with pytest.raises(TypeError, match="proprio must be a float32"):
        planner.reset(0, observation["map"], observation["proprio"].astype(np.float64))
    with pytest.raises(IndexError, match="episode index must be from 0 to 0, got 3"):
        planner.reset(3, observation["map"], observation["proprio"])


def test_follow_takes_only_probes_of_the_grid(first) -> None:
    env, observation = first
    planner = _core.ProbePlanner(env.config.core, 1)
    with pytest.raises(ValueError, match="no episode"):
        planner.follow(0, [0, 0, 0])
    planner.reset(0, observation["map"], observation["proprio"])
    planner.follow(0, [int(n) - 1 for n in env.action_space.nvec])
    lanes = int(env.action_space.nvec[0])
    with pytest.raises(ValueError, match="lane"):
        planner.follow(0, [lanes, 0, 0])
    face = GpisProbePlanner()
    face.reset(env, observation, {})
    with pytest.raises(ValueError, match=r"follow needs a probe \(lane, depth, sweep\) below"):
        face.follow(np.array([0.5, 0, 0]))


def test_a_copied_planner_plans_from_its_next_reset(first) -> None:
    """A runner copies an agent per slot: the copy pickles without the core's planner and
    makes the same probes from its next reset."""
    import copy
    import pickle

    env, observation = first
    planner = GpisProbePlanner()
    planner.reset(env, observation, {})
    probe = planner.act(observation)
    for clone in (copy.deepcopy(planner), pickle.loads(pickle.dumps(planner))):
        with pytest.raises(RuntimeError, match="call reset before act"):
            clone.act(observation)
        clone.reset(env, observation, {})
        np.testing.assert_array_equal(clone.act(observation), probe)
