"""The map task's scripted baselines (``agents.scripted.map_probe``, the mappers' faces of the
core's in ``agents.scripted.core_mappers``) on
``tactile_search/MapByTouch-v0``'s settings in the probe action mode: the non-oracle ones read
only the observation and the static configuration, the variance mapper's first probe is the
one whose finger passes the most GPIS std, and it maps better than random probes."""

from __future__ import annotations

from typing import Any

import gymnasium
import numpy as np
import pytest

import tactile_search  # noqa: F401  (registers the ids)
from agents.evaluation.agent_specs import make_agent
from agents.scripted import SCRIPTED_AGENTS
from agents.scripted.core_mappers import OccupancyMapper, VarianceMapper
from agents.scripted.map_probe import (
    PATH_HALF_WIDTH,
    BeliefVarianceMapper,
    MapOracle,
    RandomMapAgent,
)
from tactile_search import CupboardSearchEnv
from tactile_search.seed_ranges import held_out_seeds
from tests.test_scripted_agents import NoGroundTruthEnv, StaticConfigOnly

MAP_ID = "tactile_search/MapByTouch-v0"


def settings(agent: Any) -> dict[str, Any]:
    kwargs = dict(gymnasium.spec(MAP_ID).kwargs)
    kwargs.update({"map": "gpis", "action_mode": "probe"})
    kwargs.update(getattr(agent, "env_kwargs", {}))
    return kwargs


def play(agent: Any, env: CupboardSearchEnv, seed: int, agent_env: Any = None) -> dict:
    observation, _ = env.reset(seed=seed)
    agent.reset(agent_env or env, observation, {})  # no info: it holds the scores
    info: dict = {}
    for _ in range(env.config.max_steps):
        action = agent.act(observation)
        assert action.dtype == np.int64 and env.action_space.contains(action), action
        observation, _, terminated, truncated, info = env.step(action)
        if terminated or truncated:
            break
    return info


def test_the_map_baselines_are_registered_scripted_agents() -> None:
    for name, cls in [
        ("random_map", RandomMapAgent),
        ("variance_mapper", VarianceMapper),
        ("occupancy_mapper", OccupancyMapper),
        ("map_oracle", MapOracle),
    ]:
        assert SCRIPTED_AGENTS[name] is cls and cls().name == name


def test_the_map_baselines_are_made_by_name_with_their_maps() -> None:
    # make_agent (what agents.evaluate and agents.datasets make agents with): the GPIS map
    # unless an agent names its own; random_map names none, as it plays any map.
    for name in ("random_map", "variance_mapper", "occupancy_mapper", "map_oracle"):
        _, env_kwargs = make_agent(name)
        expected = SCRIPTED_AGENTS[name].env_kwargs.get("map", "gpis")  # type: ignore[attr-defined]
        assert env_kwargs == {"map": expected, "action_mode": "probe"}, name


@pytest.mark.parametrize("cls", [RandomMapAgent, VarianceMapper, OccupancyMapper])
def test_the_non_oracle_baselines_read_only_the_observation(cls: type) -> None:
    seed = held_out_seeds("validation", 1)[0]
    agent = cls()
    info = play(agent, NoGroundTruthEnv(**settings(cls)), seed)
    assert info["steps"] > 0 and np.isfinite(info["map_score_mm"])
    # Handed only the static configuration, it plays the same episode.
    env = CupboardSearchEnv(**settings(cls))
    again = play(cls(), env, seed, agent_env=StaticConfigOnly(env))
    assert again["map_score_mm"] == info["map_score_mm"]


def test_random_probes_are_seeded_by_the_first_observation() -> None:
    env = CupboardSearchEnv(**settings(RandomMapAgent))
    seeds = held_out_seeds("validation", 2)
    first = [play(RandomMapAgent(), env, seed)["map_score_mm"] for seed in seeds]
    agent = RandomMapAgent()  # one agent for both, in the other order
    second = [play(agent, env, seed)["map_score_mm"] for seed in reversed(seeds)]
    assert first == second[::-1]


def test_the_mappers_refuse_another_map_or_action_mode() -> None:
    for cls, wrong in [(VarianceMapper, "occupancy"), (OccupancyMapper, "gpis")]:
        env = CupboardSearchEnv(**{**settings(cls), "map": wrong})
        observation, info = env.reset(seed=0)
        with pytest.raises(ValueError, match="map="):
            cls().reset(env, observation, info)
        env = CupboardSearchEnv(**{**settings(cls), "action_mode": "wrist"})
        observation, info = env.reset(seed=0)
        with pytest.raises(ValueError, match="action_mode='probe'"):
            cls().reset(env, observation, info)


def _finger_path(g: Any, probe: Any) -> tuple[np.ndarray, np.ndarray]:
    """The finger's segments (joint, tip) along a probe: in along its lane from outside the
    cupboard, then the turn, sampled finely."""
    ys = np.arange(g.probe_outside, probe.y + 1e-9, 0.0025)
    yaws = -probe.side * np.linspace(0.0, probe.angle, max(2, int(probe.angle / 0.02)))
    poses = [(probe.x, y, 0.0) for y in ys] + [(probe.x, probe.y, yaw) for yaw in yaws]
    pose = np.array(poses)
    forward = np.c_[-np.sin(pose[:, 2]), np.cos(pose[:, 2])]
    joint = pose[:, :2] + g.joint_offset * forward
    return joint, pose[:, :2] + g.reach * forward


def _std_along(g: Any, probe: Any, std: np.ndarray) -> float:
    """The std summed over the cells within PATH_HALF_WIDTH of any finger segment."""
    joint, tip = _finger_path(g, probe)
    cells = np.c_[g.xs.ravel(), g.ys.ravel()]
    d = tip - joint  # (S, 2)
    rel = cells[None, :, :] - joint[:, None, :]  # (S, N, 2)
    t = np.clip((rel @ d[:, :, None])[..., 0] / (d * d).sum(1)[:, None], 0.0, 1.0)
    off = rel - t[..., None] * d[:, None, :]
    near = (np.hypot(off[..., 0], off[..., 1]) <= PATH_HALF_WIDTH + 1e-9).any(axis=0)
    return float(std.ravel()[near].sum())


def test_the_variance_mappers_first_probe_passes_the_most_std() -> None:
    """On a fixed validation layout, of the probes the mapper may make (clear of the jars
    its map shows), the first it chooses is the one whose finger passes the most GPIS std,
    summed over the cells its path passes (computed here from the finger's segments)."""
    env = CupboardSearchEnv(**settings(VarianceMapper))
    observation, info = env.reset(seed=held_out_seeds("validation", 1)[0])
    # The probes it may make, from its Python reference's belief of the same observation.
    reference = BeliefVarianceMapper()
    reference.reset(env, observation, info)
    std = env.decode_map(observation["map"])["std"]
    pose = reference._pose(observation["proprio"])
    candidates = reference._candidates(pose)
    assert len(candidates) > 10
    sums = {index: _std_along(reference.geometry, probe, std) for index, probe, _ in candidates}
    agent = VarianceMapper()
    agent.reset(env, observation, info)
    chosen = tuple(int(i) for i in agent.act(observation))
    assert chosen in sums
    best = max(sums, key=sums.get)
    assert sums[chosen] == pytest.approx(sums[best]), (chosen, best)
    assert sums[best] > np.median(list(sums.values()))


def test_the_variance_mapper_maps_better_than_random_probes() -> None:
    seeds = held_out_seeds("validation", 12)
    scores = {}
    for cls in (RandomMapAgent, VarianceMapper):
        env = CupboardSearchEnv(**settings(cls))
        scores[cls.name] = np.mean([play(cls(), env, seed)["map_score_mm"] for seed in seeds])
    assert scores["variance_mapper"] < scores["random_map"], scores


def test_the_map_oracle_reads_the_ground_truth_and_touches_jars() -> None:
    env = CupboardSearchEnv(**settings(MapOracle))
    seed = held_out_seeds("validation", 1)[0]
    _, start = env.reset(seed=seed)
    info = play(MapOracle(), env, seed)
    assert info["tips"] == 0 and info["map_score_mm"] < start["map_score_mm"] - 1.0
    with pytest.raises(AssertionError, match="ground truth"):
        play(MapOracle(), NoGroundTruthEnv(**settings(MapOracle)), seed)
