"""Demonstrations recorded over a batch of episodes on every core
(``agents.imitation.batched``): the teacher's are exactly those recorded one episode at a
time, a student with another map sees its own observations, DAgger's labels are the
planner's following the student's probes, and a clone stage run twice with one seed on one
thread gives the same demonstrations and the same weights, bit for bit."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from agents.imitation.batched import record_batched
from agents.imitation.demonstrations import PER_ROW, Demonstrations, record
from agents.imitation.training import _training_layouts

PROBE_GPIS = {"map": "gpis", "action_mode": "probe", "reward_approach": 10.0}
GAMMA = 0.9


def assert_same(a: Demonstrations, b: Demonstrations) -> None:
    for name in PER_ROW:
        np.testing.assert_array_equal(getattr(a, name), getattr(b, name), err_msg=name)
    assert a.observations.keys() == b.observations.keys()
    for key in a.observations:
        np.testing.assert_array_equal(a.observations[key], b.observations[key], err_msg=key)


@pytest.mark.parametrize("map_mode", ["gpis", "occupancy"])
def test_a_batch_records_the_teachers_episodes_as_one_at_a_time_does(map_mode: str) -> None:
    """11 layouts on 4 sub-envs (the last batch runs short; the layouts' order is kept), for
    the planner's own map and for a student with another (two envs stepped together)."""
    settings = {**PROBE_GPIS, "map": map_mode}
    layouts = _training_layouts(2, 11)
    batched = record_batched(layouts, settings, GAMMA, num_envs=4, threads=2)
    assert_same(batched, record(layouts, settings, GAMMA))


class CountingStudent:
    """A deterministic student: in each episode, its k-th probe is lane k (mod the lanes),
    depth 0, the middle sweep; in a batch it counts each row's probes from the row's
    episode start."""

    def __init__(self, lanes: int = 29) -> None:
        self.lanes = lanes
        self.counts: np.ndarray | None = None

    def batch(self, observations: dict, starts: np.ndarray) -> np.ndarray:
        n = len(starts)
        if self.counts is None:
            self.counts = np.zeros(n, dtype=np.int64)
        self.counts[starts] = 0
        probes = np.stack([self.counts % self.lanes, np.zeros(n), np.full(n, 4)], axis=1)
        self.counts += 1
        return probes.astype(np.int64)

    def episode(self, _layout: int):
        count = iter(range(10**6))
        return lambda _observation: np.array([next(count) % self.lanes, 0, 4])


def test_dagger_in_a_batch_labels_the_students_probes_as_one_at_a_time_does() -> None:
    layouts = _training_layouts(3, 6)
    student = CountingStudent()
    batched = record_batched(layouts, PROBE_GPIS, GAMMA, student=student.batch, num_envs=3)
    alone = record(layouts, PROBE_GPIS, GAMMA, student=student.episode)
    assert_same(batched, alone)
    assert not np.array_equal(batched.actions[:, 0], np.arange(len(batched)) % 29)


def test_a_batch_needs_the_probe_action_mode() -> None:
    with pytest.raises(ValueError, match="action_mode='probe'"):
        record_batched([1], {"map": "gpis"}, GAMMA)


def test_the_clone_stage_is_bit_identical_for_a_seed_on_one_thread(tmp_path: Path) -> None:
    """Two clone stages of one seed (torch on one thread, the env batch on every core: its
    results do not depend on the threads): the same demonstrations and the same weights."""
    import torch

    from agents.imitation.cloning import CloningSettings
    from agents.imitation.training import ImitationSettings, imitate

    settings = ImitationSettings(
        demo_episodes=12,
        dagger_rounds=1,
        dagger_episodes=6,
        dagger_epochs=1,
        mirror=True,
        cloning=CloningSettings(epochs=2, seed=7),
    )
    runs = []
    for name in ("first", "second"):
        run = imitate("gpis", out=tmp_path / name, seed=7, settings=settings, progress=False)
        runs.append(run)
    demos = [Demonstrations.load(run / "demonstrations.npz") for run in runs]
    assert_same(*demos)
    from stable_baselines3 import PPO

    weights = [PPO.load(run / "model.zip", device="cpu").policy.state_dict() for run in runs]
    assert weights[0].keys() == weights[1].keys()
    for key in weights[0]:
        assert torch.equal(weights[0][key], weights[1][key]), key


def test_the_identify_planner_labels_a_batch_with_its_claims_as_it_acts_alone() -> None:
    """The identify task's teacher over a batch: its actions (probe and claim) are those it
    takes playing each layout alone."""
    import gymnasium as gym

    from agents.scripted import IdentifyPlanner
    from tactile_search import CupboardSearchEnv

    settings = {**gym.spec("tactile_search/IdentifyByTouch-v0").kwargs, **PROBE_GPIS}
    layouts = _training_layouts(4, 5)
    batched = record_batched(
        layouts, settings, GAMMA, num_envs=2, threads=1, teacher="identify_planner"
    )
    assert batched.actions.shape[1] == 4
    alone = []
    env = CupboardSearchEnv(threads=1, **settings)
    face = IdentifyPlanner()
    for layout in layouts:
        observation, info = env.reset(seed=layout)
        face.reset(env, observation, info)
        ended = False
        while not ended:
            action = face.act(observation)
            alone.append(action)
            observation, _, terminated, truncated, info = env.step(action)
            ended = terminated or truncated
    env.close()
    np.testing.assert_array_equal(batched.actions, np.array(alone))


def test_a_batch_teacher_is_one_of_the_cores_planners() -> None:
    with pytest.raises(ValueError, match="one of the core's planners"):
        record_batched([1], PROBE_GPIS, GAMMA, teacher="oracle")
