"""The identify task through its registered id (``tactile_search/IdentifyByTouch-v0``): its
spaces carry the claim entry, it passes gymnasium's and SB3's checkers, a claim naming the
target succeeds and a wrong one fails in both action modes, the info keeps the target secret
until the claim, bad claims and settings that cannot name the target are clear errors, and
the SB3 VecEnv runs and pickles it."""

from __future__ import annotations

import pickle

import gymnasium as gym
import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env

import tactile_search

IDENTIFY = "tactile_search/IdentifyByTouch-v0"


def test_the_identify_id_is_registered_with_its_task_from_the_core() -> None:
    assert IDENTIFY in tactile_search.ENV_IDS
    env = gym.make(IDENTIFY)
    config = env.unwrapped.config
    assert (config.task, config.target_shape, config.round_fraction) == ("identify", "square", 1.0)
    assert gym.make(tactile_search.ENV_ID).unwrapped.config.task == "search"


@pytest.mark.parametrize(
    ("action_mode", "space"),
    [
        ("wrist", gym.spaces.Box(-1.0, 1.0, (4,), np.float32)),
        ("probe", gym.spaces.MultiDiscrete([29, 10, 9, 2])),
    ],
)
def test_the_action_carries_the_claim_entry_and_the_checkers_pass(
    action_mode: str, space: gym.Space
) -> None:
    env = gym.make(IDENTIFY, action_mode=action_mode)
    assert env.action_space == space
    check_env(env.unwrapped, skip_render_check=True)
    sb3_checker = pytest.importorskip("stable_baselines3.common.env_checker")
    sb3_checker.check_env(env.unwrapped, warn=True)


def test_the_oracle_touches_then_claims_the_target_and_succeeds() -> None:
    env = gym.make(IDENTIFY)
    _, info = env.reset(seed=3)
    jars = env.unwrapped.render_state()["jars"]
    target = next(index for index, jar in enumerate(jars) if jar["is_target"])
    for _ in range(env.unwrapped.config.max_steps):
        action = env.unwrapped.oracle_action()
        _, reward, terminated, truncated, info = env.step(action)
        if terminated or truncated:
            break
        # Until the claim, nothing says where or which the target is.
        assert info["target_distance"] == 0.0 and info["claimed_jar"] == -1
        assert not info["success"]
    assert action[3] > 0  # the oracle's last action was its claim
    assert terminated and info["success"] and not info["wrong_claim"]
    assert info["claimed_jar"] == target
    assert reward == env.unwrapped.config.reward_success


@pytest.mark.parametrize("action_mode", ["wrist", "probe"])
def test_a_claim_with_nothing_touched_fails(action_mode: str) -> None:
    env = gym.make(IDENTIFY, action_mode=action_mode)
    env.reset(seed=1)
    claim = np.array([0, 0, 0, 1], dtype=np.float32 if action_mode == "wrist" else np.int64)
    _, reward, terminated, _, info = env.step(claim)
    assert terminated and info["wrong_claim"] and not info["success"]
    assert info["claimed_jar"] == -1
    assert reward == -env.unwrapped.config.reward_wrong_claim == info["reward_wrong_claim"]


def test_a_probe_with_claim_index_zero_probes_and_ends_nothing() -> None:
    env = gym.make(IDENTIFY, action_mode="probe")
    env.reset(seed=1)
    _, _, terminated, _, info = env.step(np.array([14, 9, 4, 0]))
    assert info["motions"] > 0 and info["claimed_jar"] == -1
    assert not info["wrong_claim"] and not (terminated and not info["tipped"])


@pytest.mark.parametrize(
    ("action_mode", "action", "error", "words"),
    [
        ("wrist", [0.0, 0.0, 0.0, np.nan], ValueError, "action[3] must be finite"),
        ("probe", [0, 0, 0, 2], ValueError, "action[3] must be an integer from 0 to 1"),
        ("probe", [0.0, 0.0, 0.0, 1.0], TypeError, "claim index"),
        ("wrist", [0.0, 0.0, 0.0], ValueError, "(4,)"),
    ],
)
def test_a_bad_claim_is_a_clear_error(
    action_mode: str, action: list, error: type, words: str
) -> None:
    env = gym.make(IDENTIFY, action_mode=action_mode)
    env.reset(seed=0)
    with pytest.raises(error) as raised:
        env.unwrapped.step(np.asarray(action))
    assert words in str(raised.value)


def test_a_claim_entry_in_the_search_task_is_a_shape_error() -> None:
    env = gym.make(tactile_search.ENV_ID)
    env.reset(seed=0)
    with pytest.raises(ValueError, match=r"\(3,\)"):
        env.unwrapped.step(np.zeros(4))


@pytest.mark.parametrize(
    ("settings", "key"),
    [({"target_shape": "any"}, "target_shape"), ({"round_fraction": 0.5}, "round_fraction")],
)
def test_settings_that_cannot_name_the_target_are_refused(settings: dict, key: str) -> None:
    with pytest.raises(ValueError, match=key) as raised:
        gym.make(IDENTIFY, **settings)
    assert "identify" in str(raised.value)


def test_the_sb3_vec_env_steps_claims_and_pickles() -> None:
    pytest.importorskip("stable_baselines3")
    from tactile_search.envs.sb3_vec_env import CupboardSearchSb3VecEnv

    settings = gym.spec(IDENTIFY).kwargs
    env = CupboardSearchSb3VecEnv(num_envs=2, seed=0, action_mode="probe", **settings)
    assert env.action_space == gym.spaces.MultiDiscrete([29, 10, 9, 2])
    env.reset()
    rng = np.random.default_rng(0)
    ended = 0
    for _ in range(6):
        _, _, dones, infos = env.step(rng.integers(0, env.action_space.nvec, size=(2, 4)))
        ended += int(dones.sum())
        for done, info in zip(dones, infos, strict=True):
            assert not done or "terminal_observation" in info
    assert ended > 0  # random claims end episodes
    copy = pickle.loads(pickle.dumps(env))
    action = rng.integers(0, env.action_space.nvec, size=(2, 4))
    ours, theirs = copy.step(action), env.step(action)
    np.testing.assert_array_equal(ours[1], theirs[1])
    np.testing.assert_array_equal(ours[2], theirs[2])


def test_the_benchmark_scores_wrong_claims_on_the_identify_id() -> None:
    from tactile_search.benchmark import evaluate
    from tests.benchmark_policies import ProbeThenClaim

    result = evaluate(
        ProbeThenClaim(), episodes=6, num_envs=2, progress=False, env_id=IDENTIFY,
        action_mode="probe",
    )  # fmt: skip
    assert result.task == "identify" and result.env_id == IDENTIFY
    assert result.env_kwargs["hidden_decoys"] == 1
    for row in result.rows:
        # Every episode ends with the claim (or a tip): never both outcomes, never neither.
        assert row["success"] != row["wrong_claim"] or row["tips"] > 0, row
    wrong = sum(row["wrong_claim"] for row in result.rows)
    assert result.summary.wrong_claim_rate == wrong / 6


def test_the_benchmark_cli_runs_an_identify_id_and_reports_its_wrong_claims(capsys) -> None:
    from tactile_search.benchmark.__main__ import main

    main(["--policy", "tests.benchmark_policies:ProbeThenClaim", "--env-id", IDENTIFY,
          "--env", "action_mode=probe", "--episodes", "2", "--no-progress"])  # fmt: skip
    described, summary = capsys.readouterr().out.splitlines()[:2]
    assert described.startswith(f"{IDENTIFY}, map gpis, action_mode probe")
    assert "wrong claims" in summary


def test_render_shows_the_claim_around_the_claimed_jar() -> None:
    from tactile_search import render

    env = gym.make(IDENTIFY, render_mode="rgb_array")
    env.reset(seed=3)
    for _ in range(env.unwrapped.config.max_steps):
        action = env.unwrapped.oracle_action()
        if action[3] > 0:
            break
        env.step(action)
    before = env.render()
    _, _, terminated, _, info = env.step(action)
    after = env.render()
    assert terminated and info["success"]
    ring = np.all(after == render.CLAIM_RIGHT, axis=-1)
    assert ring.sum() > 20 and not np.all(before == render.CLAIM_RIGHT, axis=-1).any()
