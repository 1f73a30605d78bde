"""The ``probe`` action mode (``action_mode="probe"``): a ``MultiDiscrete`` space read from the
core, the gymnasium and SB3 checkers in every map mode, the vector envs, clear errors, and
pickling; the default ``wrist`` mode stays v0's."""

from __future__ import annotations

import pickle

import gymnasium as gym
import numpy as np
import pytest
from gymnasium import spaces
from gymnasium.utils.env_checker import check_env

import tactile_search  # noqa: F401  (registers the environment)
from tactile_search import CupboardSearchEnv, CupboardSearchVectorEnv
from tactile_search.envs.config import MAP_MODES
from tactile_search.envs.sb3_vec_env import CupboardSearchSb3VecEnv

ENV_ID = "tactile_search/CupboardSearch-v0"


@pytest.mark.parametrize("mode", list(MAP_MODES))
def test_gymnasium_env_checker_passes_in_the_probe_mode(mode: str) -> None:
    env = gym.make(ENV_ID, map=mode, action_mode="probe")
    check_env(env.unwrapped, skip_render_check=True)
    env.close()


@pytest.mark.parametrize("mode", list(MAP_MODES))
def test_stable_baselines3_env_checker_passes_in_the_probe_mode(mode: str) -> None:
    sb3_checker = pytest.importorskip("stable_baselines3.common.env_checker")
    sb3_checker.check_env(CupboardSearchEnv(map=mode, action_mode="probe"), warn=True)


def test_the_action_space_follows_the_mode_and_the_probe_counts() -> None:
    assert CupboardSearchEnv().action_space == spaces.Box(-1.0, 1.0, (3,), np.float32)
    env = CupboardSearchEnv(action_mode="probe", probe_lanes=7, probe_depths=4, probe_sweeps=3)
    assert env.action_space == spaces.MultiDiscrete([7, 4, 3])
    vector = CupboardSearchVectorEnv(num_envs=2, action_mode="probe", probe_lanes=7)
    assert vector.single_action_space == spaces.MultiDiscrete([7, 10, 9])
    assert vector.action_space.shape == (2, 3)
    sb3 = CupboardSearchSb3VecEnv(num_envs=2, action_mode="probe")
    assert sb3.action_space == spaces.MultiDiscrete([29, 10, 9])


def test_a_probe_step_is_many_motions_with_their_rewards_summed() -> None:
    env = CupboardSearchEnv(action_mode="probe", map="none")
    env.reset(seed=1_000_003)
    _, reward, terminated, truncated, info = env.step(np.array([3, 6, 2]))
    assert info["motions"] > 1 and info["steps"] == info["motions"]
    assert reward == pytest.approx(
        info["reward_success"]
        + info["reward_step"]
        + info["reward_displacement"]
        + info["reward_tip"]
        + info["reward_approach"]
    )
    assert info["reward_step"] == pytest.approx(-0.01 * info["motions"])
    assert not terminated or info["success"] or info["tipped"]
    assert isinstance(truncated, bool)


def test_the_cores_motion_count_is_what_a_probe_that_touches_nothing_takes() -> None:
    """``probe_motions`` (from the settings alone) against the env: a probe that touches
    nothing takes exactly the counted motions, from the start and then from wherever the
    last one ended (a lane change turns back, backs out, shifts and comes in)."""
    env = CupboardSearchEnv(action_mode="probe", map="none")
    observation, _ = env.reset(seed=1_000_003)
    actions = ([14, 0, 4], [14, 0, 0], [3, 0, 8], [25, 1, 2], [25, 1, 2], [0, 0, 4])
    checked = 0
    for action in actions:
        decoded = env.decode_proprio(observation["proprio"])
        pose = (decoded["x"], decoded["y"], decoded["yaw"])
        counted = env.probe_motions(pose, np.array([action], dtype=np.int64))
        observation, _, terminated, truncated, info = env.step(np.array(action))
        assert not terminated
        if truncated:  # the time limit (200 motions) cut it
            break
        if info["contacts"] == 0 and not info["blocked"]:
            # A probe already made waits one step (a motion that moves nothing).
            assert info["motions"] == max(int(counted[0]), 1), action
            checked += 1
        else:  # a touch stops the probe early
            assert info["motions"] <= counted[0], action
    assert checked >= 3
    with pytest.raises(ValueError, match="action\\[1\\]"):
        env.probe_motions((0.0, 0.0, 0.0), np.array([[0, 10, 0]], dtype=np.int64))
    with pytest.raises(ValueError, match="shape"):
        env.probe_motions((0.0, 0.0, 0.0), np.zeros((2, 2), dtype=np.int64))


def test_the_vector_envs_step_probe_batches() -> None:
    vector = CupboardSearchVectorEnv(num_envs=3, action_mode="probe", map="gpis")
    vector.reset(seed=[1_000_000, 1_000_001, 1_000_002])
    actions = vector.action_space.sample()
    observations, rewards, _, _, infos = vector.step(actions)
    assert np.isfinite(rewards).all() and (infos["motions"] >= 1).all()
    assert observations["map"].shape == (3, 2, 40, 80)
    sb3 = CupboardSearchSb3VecEnv(num_envs=2, action_mode="probe", map="none", seed=5)
    sb3.reset()
    sb3.step_async(np.array([[14, 3, 4], [0, 9, 8]]))
    _, sb3_rewards, _, _ = sb3.step_wait()
    assert np.isfinite(sb3_rewards).all()


@pytest.mark.parametrize(
    ("action", "message"),
    [
        (np.array([29, 0, 0]), r"action\[0\] must be an integer from 0 to 28"),
        (np.array([0, 10, 0]), r"action\[1\] must be an integer from 0 to 9"),
        (np.array([0, 0, -1]), r"action\[2\] must be an integer from 0 to 8"),
        (np.array([1, 2]), "shape"),
    ],
)
def test_bad_probe_indices_raise_value_error_naming_them(action: np.ndarray, message: str) -> None:
    env = CupboardSearchEnv(action_mode="probe", map="none")
    env.reset(seed=1_000_000)
    with pytest.raises(ValueError, match=message):
        env.step(action)


@pytest.mark.parametrize(
    "action", [np.array([0.0, 1.0, 0.0]), [0.0, 1.5, 0.0], np.array([1.0, 2, 3])]
)
def test_probe_indices_cross_as_integers_and_floats_are_refused(action: object) -> None:
    env = CupboardSearchEnv(action_mode="probe", map="none")
    env.reset(seed=1_000_000)
    with pytest.raises(TypeError, match="action must be integers in the probe action mode"):
        env.step(action)
    for integers in ([14, 3, 4], np.array([14, 3, 4], dtype=np.int32), np.array([14, 3, 4])):
        env.step(integers)


def test_bad_probe_settings_raise_naming_them() -> None:
    with pytest.raises(ValueError, match="action_mode"):
        CupboardSearchEnv(action_mode="waypoint")
    with pytest.raises(ValueError, match="probe_lanes"):
        CupboardSearchEnv(action_mode="probe", probe_lanes=0)
    with pytest.raises(ValueError, match="probe_sweep_rate"):
        CupboardSearchEnv(action_mode="probe", probe_sweep_rate=0.5)
    with pytest.raises(TypeError, match="probe_depths"):
        CupboardSearchEnv(action_mode="probe", probe_depths="ten")


def test_the_oracle_refuses_the_probe_mode() -> None:
    env = CupboardSearchEnv(action_mode="probe")
    env.reset(seed=1_000_000)
    with pytest.raises(ValueError, match="action_mode"):
        env.oracle_action()


def test_a_pickled_probe_env_goes_on_exactly_as_the_original() -> None:
    env = CupboardSearchEnv(action_mode="probe", map="gpis")
    env.reset(seed=1_000_004)
    env.step(np.array([10, 5, 7]))
    clone = pickle.loads(pickle.dumps(env))
    for action in ([20, 3, 1], [14, 8, 4]):
        a = env.step(np.array(action))
        b = clone.step(np.array(action))
        np.testing.assert_array_equal(a[0]["map"], b[0]["map"])
        np.testing.assert_array_equal(a[0]["proprio"], b[0]["proprio"])
        assert a[1:4] == b[1:4]
        if a[2]:
            break


class _AlternatingProber:
    """Probes the outermost lanes in turn: many wrist motions per agent step."""

    name = "alternating_prober"

    def __init__(self) -> None:
        self.calls = 0

    def reset(self, env, observation, info) -> None:
        self.calls = 0

    def act(self, observation) -> np.ndarray:
        self.calls += 1
        return np.array([28 * (self.calls % 2), 0, 4])


def test_an_evaluation_episode_ends_at_the_envs_own_time_limit_in_the_probe_mode() -> None:
    from agents.rollout import run_episodes

    agent = _AlternatingProber()
    (result,) = run_episodes(agent, [1_000_001], action_mode="probe", map="none")
    # The env's limit (200) counts wrist motions: far fewer agent steps end the episode.
    assert result["steps"] <= 200
    assert result["success"] or result["tips"] or result["steps"] == 200
    assert agent.calls < 50


def test_a_probes_motions_replayed_in_the_wrist_mode_reproduce_it() -> None:
    probing = CupboardSearchEnv(action_mode="probe", map="gpis")
    moving = CupboardSearchEnv(action_mode="wrist", map="gpis")
    for env in (probing, moving):
        env.reset(seed=1_000_005)
    assert probing.last_motions().shape == (0, 3)
    rng = np.random.default_rng(5)
    for _ in range(4):
        observation, _, terminated, truncated, info = probing.step(
            rng.integers(probing.action_space.nvec)
        )
        motions = probing.last_motions()
        assert motions.shape == (info["motions"], 3) and np.all(np.abs(motions) <= 1)
        for motion in motions:
            replayed, *_ = moving.step(motion)
        for key in observation:
            np.testing.assert_array_equal(replayed[key], observation[key])
        if terminated or truncated:
            break


def test_an_example_gif_of_a_prober_draws_every_other_motion_not_every_probe(tmp_path) -> None:
    from PIL import Image

    from agents.evaluation.gifs import record_gif
    from agents.rollout import run_episodes

    settings = {"map": "none", "action_mode": "probe"}
    (result,) = run_episodes(_AlternatingProber(), [1_000_001], max_steps=6, **settings)
    assert result["steps"] > result["actions"]  # many motions per probe
    record_gif(tmp_path / "probes.gif", _AlternatingProber(), settings, 1_000_001, max_steps=6)
    with Image.open(tmp_path / "probes.gif") as gif:
        # The reset, a frame every two wrist motions, and the last motion's.
        assert gif.n_frames == 1 + result["steps"] // 2 + result["steps"] % 2
