"""``tactile_search.benchmark.evaluate`` fails clearly and never scores a policy other than
the one given: SB3's ``(action, state)`` tuple, a model object, a wrong action shape and
actions outside the action mode's space each raise one error in the policy's terms."""

from __future__ import annotations

import re
from typing import Any

import numpy as np
import pytest

from tactile_search.benchmark import evaluate, from_sb3
from tests.benchmark_policies import RandomProbes, forward


def run(policy: Any, **env_kwargs: Any) -> Any:
    kwargs = {"map": "none", **env_kwargs}
    return evaluate(policy, episodes=1, num_envs=2, progress=False, **kwargs)


class StandIn:
    """A stand-in for a loaded SB3 model: ``predict`` returns ``(action, state)``, and it is
    not callable (as ``PPO.load(path)`` is not)."""

    def __init__(self, action: np.ndarray) -> None:
        self.action = action
        self.calls: list[Any] = []

    def predict(self, observation: dict, state: Any = None, episode_start: Any = None,
                deterministic: bool = False) -> tuple[np.ndarray, Any]:  # fmt: skip
        self.calls.append((state, None if episode_start is None else episode_start.copy()))
        return self.action, state


def test_sb3s_action_state_tuple_is_refused_with_how_to_fix_it() -> None:
    model = StandIn(np.array([0.0, 1.0, 0.0], dtype=np.float32))
    with pytest.raises(
        TypeError, match=r"returned a tuple of 2.*model\.predict\(observation\)\[0\]"
    ):
        run(lambda observation: model.predict(observation), action_mode="wrist")


def test_a_model_object_as_the_policy_is_told_to_be_wrapped_with_from_sb3() -> None:
    with pytest.raises(TypeError, match=r"StandIn model object: wrap it, evaluate\(from_sb3"):
        run(StandIn(np.zeros(3)), action_mode="wrist")  # type: ignore[arg-type]


def test_from_sb3_runs_a_model_and_its_deepcopies_share_it() -> None:
    model = StandIn(np.array([0.0, 1.0, 0.0], dtype=np.float32))
    rows = run(from_sb3(model), action_mode="wrist").rows
    assert rows == run(forward, action_mode="wrist").rows
    assert model.calls  # the slots' copies called the one model
    with pytest.raises(TypeError, match="from_sb3 takes a loaded SB3 model"):
        from_sb3(forward)


def test_a_recurrent_models_state_is_carried_and_cleared_at_each_episode() -> None:
    class RecurrentStandIn(StandIn):
        def predict(self, observation: dict, state: Any = None, episode_start: Any = None,
                    deterministic: bool = False) -> tuple[np.ndarray, Any]:  # fmt: skip
            super().predict(observation, state, episode_start, deterministic)
            return self.action, (0 if state is None else state[0] + 1,)

    policy = from_sb3(RecurrentStandIn(np.array([0.0, 1.0, 0.0], dtype=np.float32)))
    policy.reset({}, {})
    for _ in range(3):
        policy({})
    policy.reset({}, {})
    policy({})
    calls = policy.model.calls
    assert [c[0] for c in calls] == [None, (0,), (1,), None]
    assert [bool(c[1][0]) for c in calls] == [True, False, False, True]


def test_a_wrong_shape_is_reported_per_observation_not_per_batch() -> None:
    message = (
        "the policy returned shape (2,) for one observation; this env's action space is "
        "Box(-1, 1, (3,)) (action_mode='wrist'"
    )
    with pytest.raises(ValueError, match=re.escape(message)):
        run(lambda observation: np.zeros(2), action_mode="wrist")
    with pytest.raises(ValueError, match=re.escape("shape (1, 3) for one observation")):
        run(lambda observation: np.zeros((1, 3), dtype=np.int64), action_mode="probe")
    with pytest.raises(ValueError, match=re.escape("is MultiDiscrete([29 10  9])")):
        run(lambda observation: np.zeros(4, dtype=np.int64), action_mode="probe")


def test_a_wrist_policy_in_a_probe_env_is_refused_not_cast() -> None:
    with pytest.raises(TypeError, match=r"action_mode='probe' takes integer indices.*float32"):
        run(forward, action_mode="probe")


def test_probe_indices_in_a_wrist_env_are_refused_not_clipped() -> None:
    with pytest.raises(ValueError, match=r"action_mode='wrist' takes 3 finite numbers in \[-1, 1\]"
                       r".*not clipped.*pass action_mode='probe'"):  # fmt: skip
        run(RandomProbes(), action_mode="wrist")


def test_out_of_range_actions_are_refused_in_either_mode() -> None:
    with pytest.raises(ValueError, match="refused, not clipped"):
        run(lambda observation: np.array([0.0, 1.5, 0.0]), action_mode="wrist")
    with pytest.raises(ValueError, match="refused, not clipped"):
        run(lambda observation: np.array([0.0, np.nan, 0.0]), action_mode="wrist")
    with pytest.raises(ValueError, match=re.escape("indices 0 <= a < [29 10  9]")):
        run(lambda observation: np.array([29, 0, 0]), action_mode="probe")


def test_actions_that_fit_pass_in_any_real_dtype() -> None:
    wrist = run(lambda observation: np.array([0.0, 1.0, 0.0]), action_mode="wrist").rows
    assert wrist == run(forward, action_mode="wrist").rows  # float64 as float32
    assert run(lambda observation: [0, 1, 0], action_mode="wrist").rows == wrist


def test_a_real_sb3_model_runs_through_from_sb3() -> None:
    sb3 = pytest.importorskip("stable_baselines3")
    import gymnasium as gym

    import tactile_search

    env = gym.make(tactile_search.ENV_ID, map="none", action_mode="probe")
    model = sb3.PPO("MultiInputPolicy", env, n_steps=8, batch_size=8, device="cpu", seed=0)
    env.close()
    result = run(from_sb3(model), action_mode="probe")
    assert len(result.rows) == 1 and result.summary.agent == "PPO"
    with pytest.raises(TypeError, match="wrap it"):
        run(model, action_mode="probe")
    with pytest.raises(TypeError, match="returned a tuple of 2"):
        run(lambda observation: model.predict(observation), action_mode="probe")
    # Without action_mode, the model's own (its action space's); another is refused.
    assert run(from_sb3(model)).env_kwargs["action_mode"] == "probe"
    with pytest.raises(ValueError, match="cannot run under action_mode='wrist'"):
        run(from_sb3(model), action_mode="wrist")
