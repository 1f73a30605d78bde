"""Determinism across the ways of running: the same seed and actions give bit-identical
rollouts in one process or another, on one or two worker threads, in the single env or any
slot of a vector env of any size, and after a pickle round trip mid-episode."""

from __future__ import annotations

import pickle
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from tactile_search import CupboardSearchEnv, CupboardSearchVectorEnv
from tactile_search.envs.config import MAP_MODES
from tests.rollouts import record_all

MODES = list(MAP_MODES)
ROOT = Path(__file__).resolve().parents[1]


def actions_for(seed: int, steps: int, shape: tuple[int, ...] = (3,)) -> np.ndarray:
    """Random actions, some outside [-1, 1] (the core clips them)."""
    return np.random.default_rng(seed).uniform(-1.3, 1.3, (steps, *shape))


def single_trace(env: CupboardSearchEnv, actions: np.ndarray) -> list[np.ndarray]:
    """Every observation array, reward and info value of stepping ``actions`` from the env's
    current state, flattened to float64 arrays (stops at the episode's end)."""
    trace = []
    for action in actions:
        obs, reward, terminated, truncated, info = env.step(action)
        trace += [obs[key].astype(np.float64).ravel() for key in sorted(obs)]
        trace.append(np.array([reward, terminated, truncated, *info.values()], dtype=np.float64))
        if terminated or truncated:
            break
    return trace


def assert_traces_equal(a: list[np.ndarray], b: list[np.ndarray]) -> None:
    assert len(a) == len(b)
    for x, y in zip(a, b, strict=True):
        np.testing.assert_array_equal(x, y)


def test_another_process_gives_the_same_rollouts_bit_for_bit(tmp_path: Path) -> None:
    """Every env face's pinned rollouts (tests/rollouts.py: single, vector, SB3; every map
    mode), recorded here and in a fresh interpreter."""
    pytest.importorskip("stable_baselines3")
    out = tmp_path / "other_process.npz"
    subprocess.run(
        [sys.executable, str(ROOT / "tests" / "rollouts.py"), "--out", str(out)],
        check=True,
        cwd=ROOT,
        timeout=600,
    )
    other = np.load(out)
    here = record_all()
    assert sorted(other.files) == sorted(here)
    for key in other.files:
        np.testing.assert_array_equal(other[key], here[key], err_msg=key)


@pytest.mark.parametrize("mode", MODES)
def test_one_or_two_worker_threads_give_the_same_rollouts(mode: str) -> None:
    """A batch of 4 with short episodes (so autoresets happen) on 1 and on 2 threads."""
    traces = []
    for threads in (1, 2):
        env = CupboardSearchVectorEnv(num_envs=4, threads=threads, map=mode, max_steps=8)
        obs, _ = env.reset(seed=[21, 22, 23, 24])
        trace = [obs[key].copy() for key in sorted(obs)]
        for actions in actions_for(3, 20, (4, 3)):
            obs, rewards, terminated, truncated, info = env.step(actions)
            trace += [obs[key] for key in sorted(obs)]
            trace += [rewards, terminated, truncated, *(info[key] for key in sorted(info))]
        traces.append(trace)
    assert_traces_equal(*traces)


@pytest.mark.parametrize("num_envs", [1, 3, 5])
def test_every_slot_of_a_vector_env_steps_as_the_single_env(num_envs: int) -> None:
    """Slot k of a vector env of any size, seeded s, gives what the single env seeded s gives
    under the same actions."""
    seeds = [31 + 7 * k for k in range(num_envs)]
    steps = 15
    actions = actions_for(num_envs, steps, (num_envs, 3))
    vector = CupboardSearchVectorEnv(num_envs=num_envs, max_steps=steps)
    obs, _ = vector.reset(seed=seeds)
    vector_trace = [obs]
    for step_actions in actions:
        vector_trace.append(vector.step(step_actions))
    for slot, seed in enumerate(seeds):
        single = CupboardSearchEnv(max_steps=steps)
        obs, _ = single.reset(seed=seed)
        for key in obs:
            np.testing.assert_array_equal(obs[key], vector_trace[0][key][slot])
        for step, step_actions in enumerate(actions):
            obs, reward, terminated, truncated, info = single.step(step_actions[slot])
            v_obs, v_rewards, v_terminated, v_truncated, v_info = vector_trace[step + 1]
            for key in obs:
                np.testing.assert_array_equal(obs[key], v_obs[key][slot])
            assert (reward, terminated, truncated) == (
                v_rewards[slot],
                v_terminated[slot],
                v_truncated[slot],
            )
            for key, value in info.items():
                assert value == v_info[key][slot], key
            if terminated or truncated:
                break


@pytest.mark.parametrize("mode", MODES)
def test_a_pickle_round_trip_mid_episode_goes_on_bit_identically(mode: str) -> None:
    env = CupboardSearchEnv(map=mode, max_steps=40)
    env.reset(seed=41)
    before = actions_for(4, 12).astype(np.float32)  # float32 actions replay exactly too
    single_trace(env, before)
    clone = pickle.loads(pickle.dumps(env))
    after = actions_for(5, 40)
    assert_traces_equal(single_trace(env, after), single_trace(clone, after))
    # The env's generator travels too: unseeded resets draw the same layouts.
    first, _ = env.reset()
    second, _ = clone.reset()
    for key in first:
        np.testing.assert_array_equal(first[key], second[key])


def test_a_pickle_before_any_reset_or_after_the_end_round_trips() -> None:
    fresh = pickle.loads(pickle.dumps(CupboardSearchEnv(max_steps=3)))
    fresh.reset(seed=2)
    ended = CupboardSearchEnv(max_steps=3)
    ended.reset(seed=2)
    single_trace(ended, np.zeros((3, 3)))
    clone = pickle.loads(pickle.dumps(ended))
    assert clone.render_state()["hand"] == ended.render_state()["hand"]
    assert_traces_equal(single_trace(ended, np.ones((2, 3))), single_trace(clone, np.ones((2, 3))))
