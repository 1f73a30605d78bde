"""The GPIS planner on the agents' action interface (``action_mode="probe"``): its actions
are probes of the core's grid, it finds targets without ground truth, it reads only the
observation and the static configuration, and (in the Python reference, whose belief is
open to look at) its belief learns the path of each probe."""

from __future__ import annotations

import numpy as np
import pytest

from agents.scripted import BeliefProbePlanner, GpisProbePlanner
from tactile_search import CupboardSearchEnv
from tests.test_scripted_agents import NoGroundTruthEnv, StaticConfigOnly

# Held-in seeds it solves (the measurement uses 1_000_000 onwards; seed 0 times out).
PLANNER_SEEDS = [1, 2, 3, 4, 5]


def run(planner: GpisProbePlanner, env: CupboardSearchEnv, seed: int, agent_env=None) -> dict:
    observation, info = env.reset(seed=seed)
    planner.reset(agent_env or env, observation, {})  # no info: it holds metrics
    for _ in range(env.config.max_steps):
        action = planner.act(observation)
        assert env.action_space.contains(action), action
        observation, _, terminated, truncated, info = env.step(action)
        if terminated or truncated:
            break
    return info


@pytest.mark.parametrize("seed", PLANNER_SEEDS)
def test_probe_planner_touches_the_target_without_ground_truth_or_tipping(seed: int) -> None:
    info = run(GpisProbePlanner(), NoGroundTruthEnv(action_mode="probe"), seed)
    assert info["success"] and info["tips"] == 0


@pytest.mark.parametrize("seed", PLANNER_SEEDS[:2])
def test_probe_planner_sees_only_the_observation_and_the_static_configuration(seed: int) -> None:
    env = CupboardSearchEnv(action_mode="probe")
    info = run(GpisProbePlanner(), env, seed, agent_env=StaticConfigOnly(env))
    assert info["success"] and info["tips"] == 0


def test_probe_planner_needs_the_probe_action_mode_and_the_gpis_map() -> None:
    env = CupboardSearchEnv()
    observation, info = env.reset(seed=0)
    with pytest.raises(ValueError, match="action_mode='probe'"):
        GpisProbePlanner().reset(env, observation, info)
    env = CupboardSearchEnv(action_mode="probe", map="none")
    observation, info = env.reset(seed=0)
    with pytest.raises(ValueError, match="map"):
        GpisProbePlanner().reset(env, observation, info)


def test_a_probe_that_touches_nothing_is_swept_along_its_lane_and_turn() -> None:
    """After a probe that touched nothing, the belief holds the finger's path: every cell the
    straight finger passed along the lane, and the arc of its turn."""
    env = CupboardSearchEnv(action_mode="probe")
    planner = BeliefProbePlanner()
    observation, info = env.reset(seed=0)
    planner.reset(env, observation, info)
    g = planner.geometry
    lane, depth, sweep = 10, 2, 0  # left of the middle, shallow, the full turn towards -x
    before = planner.belief.swept.copy()
    planner._chosen = (lane, depth, sweep)
    observation, _, terminated, _, info = env.step(np.array(planner._chosen))
    in_contact = env.decode_proprio(observation["proprio"])["in_contact"]
    assert not terminated and not in_contact, "this probe touches nothing in layout 0"
    planner.act(observation)
    swept = planner.belief.swept & ~before
    x, y = g.probe_lanes[lane], g.probe_depths[depth]
    tip_straight = y + g.reach
    cells = np.abs(planner.belief.xs - x) < 0.5 * g.cell
    on_path = cells & (planner.belief.ys > 0.0) & (planner.belief.ys < tip_straight - g.cell)
    assert swept[on_path].all()
    # The turn swept its arc: the tip halfway through the turn (the observation shows the
    # finger only at its end).
    yaw = 0.5 * g.probe_yaws[sweep]
    tip = np.array([x, y]) + g.reach * np.array([-np.sin(yaw), np.cos(yaw)])
    near_tip = np.hypot(planner.belief.xs - tip[0], planner.belief.ys - tip[1]) < g.cell
    assert swept[near_tip].any()
