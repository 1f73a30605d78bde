"""Fuzzing the step and reset inputs (hypothesis): action sequences of any dtype, shape and
value, through the single and the vector env, and seeds of any kind.

A valid action (integers or real floats, as numpy reads it, of the right shape, all finite;
out-of-range values are clipped) steps with finite outputs in the spaces. Anything else
(complex, string, datetime, boolean or object arrays included) raises ``ValueError`` or
``TypeError`` naming the action, and changes nothing: a twin env given only the valid
actions of the same sequence stays bit-identical, autoresets included; in every registered
task and tier too, with and without the identify task's claim entry. A pyo3
``PanicException`` (a ``BaseException``) or any other exception is a failure. test_env.py
and test_step_path.py check a few fixed bad actions; this file draws them.
"""

from __future__ import annotations

import math
import warnings
from typing import Any

import gymnasium as gym
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import array_shapes, arrays, scalar_dtypes

from tactile_search import ENV_ID, ENV_IDS, CupboardSearchEnv, CupboardSearchVectorEnv
from tactile_search.envs.config import MAP_MODES

DOCUMENTED = (ValueError, TypeError)
VALID, INVALID = "valid", "invalid"


def examples(weight: float) -> int:
    """This test's share of the profile's ``max_examples`` (tests/conftest.py)."""
    return max(5, round(settings.default.max_examples * weight))


def call(function: Any, *args: Any) -> tuple[Any, BaseException | None]:
    """The result, or the documented error; anything else (PanicException included) fails."""
    try:
        return function(*args), None
    except DOCUMENTED as error:
        return None, error
    except BaseException as error:  # PanicException derives from it
        pytest.fail(f"{type(error).__name__} from {function} with {args!r}: {error}")


def classify(action: Any, shape: tuple[int, ...]) -> str:
    """VALID for what numpy reads as an integer or real-float array of ``shape``, all
    finite; INVALID otherwise (numpy cannot read it, another dtype: complex, string,
    datetime, boolean or object, another shape, or a NaN or inf)."""
    array = as_numbers(action)
    if array is None or array.shape != shape:
        return INVALID
    return VALID if np.all(np.isfinite(array)) else INVALID


def as_numbers(action: Any) -> np.ndarray | None:
    """``action`` as float64 if numpy reads it as integers or real floats, else None."""
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            array = np.asarray(action)
    except (ValueError, TypeError, OverflowError):
        return None  # ragged nesting and the like
    if array.dtype.kind not in "iuf":
        return None
    return array.astype(np.float64)


FLOATS = st.floats(allow_subnormal=True)
NASTY = st.sampled_from([0.0, -0.0, 1.0, -1.0, 1.0000001, 5e-324, 1e300, math.nan, math.inf])


def action_values(shape: tuple[int, ...]) -> st.SearchStrategy[Any]:
    """Anything an agent might pass, biased towards ``shape`` (one action or a batch)."""
    dtypes = st.one_of(
        scalar_dtypes(),
        st.sampled_from([np.float32, np.float64, np.int8, np.uint64, np.bool_, np.float16]),
    )
    return st.one_of(
        arrays(np.float64, shape, elements=st.floats(-1, 1)),
        arrays(np.float32, shape, elements=st.floats(-3, 3, width=32)),
        arrays(dtypes, st.just(shape)),
        arrays(dtypes, array_shapes(min_dims=0, max_dims=3, min_side=0, max_side=4)),
        arrays(np.float64, shape, elements=st.one_of(FLOATS, NASTY)),
        st.lists(st.one_of(FLOATS, NASTY, st.integers(-(2**70), 2**70)), max_size=4),
        st.lists(st.lists(st.floats(-2, 2), min_size=3, max_size=3), max_size=4),
        st.sampled_from([None, "left", b"abc", 0.5, 7, math.nan, [], [[]], {"dx": 0.1}]),
        st.lists(st.sampled_from(["1", "0.5", "x"]), min_size=3, max_size=3),
        st.lists(st.complex_numbers(max_magnitude=2), min_size=3, max_size=3),
        st.tuples(*[st.sampled_from([0.1, np.float32(2.0), np.int64(-1), True])] * 3),
        st.lists(st.booleans(), min_size=3, max_size=3),
        arrays(object, shape, elements=st.one_of(st.floats(-1, 1), st.integers(-1, 1))),
        arrays(
            st.sampled_from(["datetime64[s]", "timedelta64[ms]", "complex64", "U3", "S3"]),
            st.just(shape),
        ),
    )


def assert_same(a: Any, b: Any) -> None:
    if isinstance(a, dict):
        assert a.keys() == b.keys()
        for key in a:
            assert_same(a[key], b[key])
    elif isinstance(a, tuple | list):
        assert len(a) == len(b)
        for x, y in zip(a, b, strict=True):
            assert_same(x, y)
    else:
        np.testing.assert_array_equal(a, b)


def assert_finite_info(info: dict[str, Any]) -> None:
    for key, value in info.items():
        assert np.all(np.isfinite(np.asarray(value, dtype=np.float64))), key


# One env and its twin per map mode, and per vector size: reset to the example's seed.
SINGLE = {mode: (CupboardSearchEnv(map=mode), CupboardSearchEnv(map=mode)) for mode in MAP_MODES}
VECTOR = {
    n: (
        CupboardSearchVectorEnv(num_envs=n, threads=1, max_steps=3),
        CupboardSearchVectorEnv(num_envs=n, threads=1, max_steps=3),
    )
    for n in (1, 2, 3)
}


@settings(max_examples=examples(3))
@given(
    mode=st.sampled_from(MAP_MODES),
    seed=st.integers(0, 2**64 - 1),
    actions=st.lists(action_values((3,)), min_size=1, max_size=6),
)
def test_single_env_steps_valid_actions_and_refuses_the_rest_changing_nothing(
    mode: str, seed: int, actions: list
) -> None:
    env, twin = SINGLE[mode]
    env.reset(seed=seed)
    twin.reset(seed=seed)
    for action in actions:
        result = single_step(env, twin, action)
        if result is None:
            continue
        _, _, terminated, truncated, info = result
        clipped = np.any(np.abs(np.asarray(action, dtype=np.float64)) > 1)
        assert info["clipped"] == clipped, (action, info["clipped"])
        if terminated or truncated:
            env.reset(seed=seed // 2)
            twin.reset(seed=seed // 2)


def single_step(env: Any, twin: Any, action: Any) -> tuple | None:
    """Steps ``env`` with ``action``: refused (None) exactly when it is not a valid action of
    the env's action shape, with an error naming the action; else finite outputs in the
    spaces, and its twin stepped with it gives the same. The step's result, or None."""
    kind = classify(action, env.action_space.shape)
    result, error = call(env.step, action)
    if error is not None:
        assert kind != VALID, (action, error)
        assert "action" in str(error), error
        return None
    assert kind != INVALID, f"accepted {action!r}"
    observation, reward, _, _, info = result
    assert env.observation_space.contains(observation)
    assert math.isfinite(reward)
    assert_finite_info(info)
    assert_same(result, twin.step(action))
    return result


@settings(max_examples=examples(3))
@given(
    data=st.data(),
    num_envs=st.sampled_from(sorted(VECTOR)),
    seed=st.integers(0, 2**64 - 1),
    length=st.integers(1, 8),
)
def test_vector_env_steps_valid_actions_and_refuses_the_rest_changing_nothing(
    data: st.DataObject, num_envs: int, seed: int, length: int
) -> None:
    """Episodes of 3 steps, so a sequence crosses autoresets (their seeds come from the
    env's generator: a refused step must not draw them)."""
    env, twin = VECTOR[num_envs]
    shape = (num_envs, 3)
    env.reset(seed=seed)
    twin.reset(seed=seed)
    resetting = np.zeros(num_envs, dtype=bool)
    for _ in range(length):
        actions = data.draw(action_values(shape))
        kind = classify(actions, shape)
        rows = as_numbers(actions)
        if kind == INVALID and resetting.any() and rows is not None and rows.shape == shape:
            # The rows of episodes that reset this step are ignored, non-finite or not.
            kind = classify(np.where(resetting[:, None], 0.0, rows), shape)
        result, error = call(env.step, actions)
        if error is not None:
            assert kind != VALID, (actions, error)
            assert "action" in str(error), error
            continue
        assert kind != INVALID, f"accepted {actions!r}"
        observation, rewards, terminated, truncated, info = result
        assert env.observation_space.contains(observation)
        assert rewards.shape == (num_envs,) and np.all(np.isfinite(rewards))
        assert terminated.dtype == truncated.dtype == np.bool_
        assert_finite_info(info)
        assert_same(result, twin.step(actions))
        resetting = terminated | truncated


# One env and its twin per registered id other than v0 (the tasks and tiers), wrist mode.
TASK_IDS = [env_id for env_id in ENV_IDS if env_id != ENV_ID]
TASKS = {
    env_id: (gym.make(env_id, max_steps=5).unwrapped, gym.make(env_id, max_steps=5).unwrapped)
    for env_id in TASK_IDS
}


@settings(max_examples=examples(2))
@given(
    env_id=st.sampled_from(TASK_IDS),
    seed=st.integers(0, 2**64 - 1),
    actions=st.lists(st.one_of(action_values((3,)), action_values((4,))), min_size=1, max_size=6),
)
def test_every_task_id_steps_valid_actions_and_refuses_the_rest_changing_nothing(
    env_id: str, seed: int, actions: list
) -> None:
    """Actions with and without the identify task's claim entry: the id's own shape steps
    (a claim entry above 0 claims and ends the episode), anything else is refused."""
    env, twin = TASKS[env_id]
    shape = env.action_space.shape
    env.reset(seed=seed)
    twin.reset(seed=seed)
    for action in actions:
        result = single_step(env, twin, action)
        if result is None:
            continue
        _, _, terminated, truncated, info = result
        if shape == (4,) and as_numbers(action)[3] > 0:
            assert terminated and info["success"] != info["wrong_claim"]
        if terminated or truncated:
            env.reset(seed=seed // 2)
            twin.reset(seed=seed // 2)


SEEDS = st.one_of(
    st.none(),
    st.integers(0, 2**64 - 1),
    st.integers(-(2**70), 2**70),
    st.sampled_from([2**63, 2**64 - 1, 2**64, -1, True, 1.5, math.nan, "7", np.int64(3)]),
    st.lists(st.integers(-1, 2**64), min_size=1, max_size=3),
)


def usable(env: Any) -> None:
    env.reset(seed=0)
    action = env.action_space.sample() * 0
    result = env.step(action)
    assert np.all(np.isfinite(np.asarray(result[1], dtype=np.float64)))


@settings(max_examples=examples(2))
@given(seed=SEEDS, vector=st.booleans())
def test_reset_takes_any_seed_in_range_and_refuses_others_naming_the_seed(
    seed: Any, vector: bool
) -> None:
    """Single env: an int in [0, 2**64). Vector env: one int, or a list of num_envs of
    them. Refusals are gymnasium's own ``gymnasium.error.Error`` (its seeding) or the
    documented errors, naming the seed; the env stays usable."""
    env = VECTOR[2][0] if vector else SINGLE[MAP_MODES[0]][0]
    try:
        observation, info = env.reset(seed=seed)
    except (*DOCUMENTED, gym.error.Error) as error:
        assert "seed" in str(error).lower(), error
        usable(env)
        return
    except BaseException as error:  # PanicException derives from it
        pytest.fail(f"{type(error).__name__} from reset(seed={seed!r}): {error}")
    assert env.observation_space.contains(observation)
    assert_finite_info(info)
    usable(env)


# --- found by this fuzzer ------------------------------------------------------------

NOT_REAL_NUMBERS = {
    "complex": np.array([0.5 + 1j, 0.0, 0.0]),
    "complex list": [0.5 + 1j, 0.0, 0.0],
    "numeric strings": np.array(["0.5", "0", "0"]),
    "string list": ["0.5", "0", "0"],
    "datetime": np.array([1, 0, 0], dtype="datetime64[s]"),
    "NaT": np.array(["NaT", "NaT", "NaT"], dtype="datetime64[s]"),
    "timedelta": np.array([1, 0, 0], dtype="timedelta64[ms]"),
    "bool": np.array([True, False, True]),
    "bool list": [True, False, True],
    "object": np.array([0.5, 0.0, 0.0], dtype=object),
    "int beyond 64 bits": [2**70, 0, 0],
}


@pytest.mark.parametrize("name", sorted(NOT_REAL_NUMBERS))
def test_an_action_that_is_not_real_numbers_is_refused(name: str) -> None:
    """Found by this fuzzer, fixed in env_core/src/bindings/actions.rs: an action that was
    not float32/float64 went through ``numpy.asarray(..., float64)``, which dropped a complex
    action's imaginary part (only a ComplexWarning) and read numeric strings, datetimes
    (NaT as -9.2e18) and booleans as numbers. Now only integer and real-float dtypes are
    read; the others are refused (single and vector env) naming the action and the dtype,
    and change nothing."""
    action = NOT_REAL_NUMBERS[name]
    dtype = np.asarray(action).dtype
    env, twin = SINGLE[MAP_MODES[0]]
    env.reset(seed=0)
    twin.reset(seed=0)
    with pytest.raises(ValueError, match="action") as error:
        env.step(action)
    assert str(dtype) in str(error.value), error.value
    assert_same(env.step(np.zeros(3)), twin.step(np.zeros(3)))
    vector, vector_twin = VECTOR[2]
    vector.reset(seed=0)
    vector_twin.reset(seed=0)
    batch = np.stack([np.asarray(action)] * 2)
    with pytest.raises(ValueError, match="actions") as error:
        vector.step(batch)
    assert str(dtype) in str(error.value), error.value
    assert_same(vector.step(np.zeros((2, 3))), vector_twin.step(np.zeros((2, 3))))


def test_a_refused_vector_step_draws_no_reset_seeds() -> None:
    """Found by the vector property above, fixed in vector.py: a step refused while
    autoresets were due had drawn their seeds, so the layouts after it differed from a run
    without the refused step."""
    env, twin = VECTOR[2]
    env.reset(seed=3)
    twin.reset(seed=3)
    for _ in range(3):
        env.step(np.zeros((2, 3)))
        twin.step(np.zeros((2, 3)))
    with pytest.raises(ValueError, match="actions"):
        env.step(np.zeros((2, 2)))
    assert_same(env.step(np.zeros((2, 3))), twin.step(np.zeros((2, 3))))
