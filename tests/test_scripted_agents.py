"""The scripted baselines: the planner finds targets without ground truth through the probe
interface, random actions are bounded and seeded, the oracle solves an episode, and the
rollout summarises it."""

from __future__ import annotations

import dataclasses
from typing import Any

import numpy as np
import pytest

from agents.rollout import run_episodes
from agents.scripted import SCRIPTED_AGENTS, GpisProbePlanner, OracleAgent, RandomAgent
from tactile_search import CupboardSearchEnv

# Held-in seeds the planner solves in a few probes (the measurement uses 1_000_000 onwards).
PLANNER_SEEDS = [1, 2, 4, 5, 6]


class NoGroundTruthEnv(CupboardSearchEnv):
    """An env whose ground truth (state and oracle) cannot be read."""

    def render_state(self) -> dict[str, Any]:
        raise AssertionError("the agent read the ground truth (render_state)")

    def oracle_action(self) -> np.ndarray:
        raise AssertionError("the agent asked the oracle")


def run(agent: Any, env: CupboardSearchEnv, seed: int) -> dict[str, Any]:
    observation, info = env.reset(seed=seed)
    agent.reset(env, observation, info)
    for _ in range(env.config.max_steps):
        action = agent.act(observation)
        assert action.shape == (3,) and action.dtype == np.float32
        assert np.all(np.abs(action) <= 1.0)
        observation, _, terminated, _, info = env.step(action)
        if terminated:
            break
    return info


def run_probes(agent: Any, env: CupboardSearchEnv, seed: int) -> dict[str, Any]:
    """An episode of a probe-mode agent: every action a probe of the env's grid."""
    observation, info = env.reset(seed=seed)
    agent.reset(env, observation, info)
    for _ in range(env.config.max_steps):
        action = agent.act(observation)
        assert action.dtype == np.int64 and env.action_space.contains(action)
        observation, _, terminated, truncated, info = env.step(action)
        if terminated or truncated:
            break
    return info


@pytest.mark.parametrize("seed", PLANNER_SEEDS)
def test_planner_touches_the_target_without_ground_truth_or_tipping(seed: int) -> None:
    info = run_probes(GpisProbePlanner(), NoGroundTruthEnv(**GpisProbePlanner.env_kwargs), seed)
    assert info["success"] and info["tips"] == 0


class StaticConfigOnly:
    """What a planner may be handed instead of the env: the static configuration and what
    the core derives from it alone (its geometry and the decoders of its observation), taken
    from a twin env of the same settings that never saw the episode (no episode, no scene, no
    oracle; any other attribute is an ``AttributeError``)."""

    __slots__ = ("config", "decode_map", "decode_proprio", "geometry", "probe_motions")

    def __init__(self, env: CupboardSearchEnv) -> None:
        self.config = env.config
        twin = CupboardSearchEnv(**dataclasses.asdict(env.config))
        self.geometry = twin.geometry
        self.decode_map = twin.decode_map
        self.decode_proprio = twin.decode_proprio
        self.probe_motions = twin.probe_motions


@pytest.mark.parametrize("seed", PLANNER_SEEDS[:3])
def test_planner_sees_only_the_observation_and_the_static_configuration(seed: int) -> None:
    env = CupboardSearchEnv(**GpisProbePlanner.env_kwargs)
    planner = GpisProbePlanner()
    observation, info = env.reset(seed=seed)
    planner.reset(StaticConfigOnly(env), observation, {})  # no info: it holds metrics
    for _ in range(env.config.max_steps):
        # The planner gets the observation alone, never the info.
        observation, _, terminated, truncated, info = env.step(planner.act(observation))
        if terminated or truncated:
            break
    assert info["success"] and info["tips"] == 0


def test_planner_needs_the_gpis_map_and_the_probe_mode() -> None:
    env = CupboardSearchEnv(map="none", action_mode="probe")
    observation, info = env.reset(seed=0)
    with pytest.raises(ValueError, match="map"):
        GpisProbePlanner().reset(env, observation, info)
    env = CupboardSearchEnv(map="gpis")
    observation, info = env.reset(seed=0)
    with pytest.raises(ValueError, match="action_mode='probe'"):
        GpisProbePlanner().reset(env, observation, info)


def test_random_actions_are_in_bounds_and_seeded() -> None:
    first, second, other = RandomAgent(7), RandomAgent(7), RandomAgent(8)
    a = np.array([first.act({}) for _ in range(100)])
    b = np.array([second.act({}) for _ in range(100)])
    assert a.dtype == np.float32 and np.all(np.abs(a) <= 1.0)
    np.testing.assert_array_equal(a, b)
    assert not np.array_equal(a, np.array([other.act({}) for _ in range(100)]))


def test_oracle_touches_the_target() -> None:
    assert run(OracleAgent(), CupboardSearchEnv(), 2)["success"]


def test_run_episodes_summarises_each_seed() -> None:
    results = run_episodes(OracleAgent(), [2, 3])
    assert [r["seed"] for r in results] == [2, 3]
    assert all(r["success"] and r["steps"] > 0 and r["tips"] == 0 for r in results)
    keys = {"jar_displacement", "max_jar_displacement", "iou", "reward"}
    assert keys <= results[0].keys()


def test_registry_builds_every_scripted_agent() -> None:
    assert set(SCRIPTED_AGENTS) == {
        "random",
        "oracle",
        "gpis_probe_planner",
        "random_identify",
        "identify_planner",
        "random_map",
        "variance_mapper",
        "occupancy_mapper",
        "map_oracle",
    }
    for name, factory in SCRIPTED_AGENTS.items():
        assert factory().name == name
