"""Fuzzing the settings (hypothesis): any key, known or not, with any value, through every
public way of building an environment or a scene.

Every example either works, and then a reset and a few steps give finite observations,
rewards and infos inside their spaces, or raises ``ValueError``/``TypeError`` whose message
names a setting: the key given when its own value is wrong. A pyo3 ``PanicException`` (a
``BaseException``) or any other exception is a failure. The keys, types, defaults and ranges
come from the core's settings table (``tactile_search.envs.config.SETTINGS``); nothing about
a particular setting is written here. test_settings.py checks one wrong type and one
out-of-range value per setting; this file draws them at random, several at a time, at the
edges of the ranges, and runs what is valid.
"""

from __future__ import annotations

import inspect
import math
import re
from typing import Any

import gymnasium as gym
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from tactile_search import CupboardSearchEnv, CupboardSearchVectorEnv, _core
from tactile_search.envs.config import SCENE_KEYS, SETTINGS, CupboardSearchConfig

ENV_ID = "tactile_search/CupboardSearch-v0"
BY_KEY: dict[str, dict[str, Any]] = {s["key"]: s for s in SETTINGS}
KEYS = sorted(BY_KEY)
SCENE = sorted(SCENE_KEYS)
DOCUMENTED = (ValueError, TypeError)

# Parameters of the constructors themselves: not settings, so never drawn as unknown keys.
OWN_PARAMETERS = {
    name
    for function in (CupboardSearchEnv.__init__, CupboardSearchVectorEnv.__init__)
    for name in inspect.signature(function).parameters
    if name not in BY_KEY
} | {"self", "seed", "seeds", "config", "threads", "env_id", "id", "num_envs"}


def examples(weight: float) -> int:
    """This test's share of the profile's ``max_examples`` (tests/conftest.py)."""
    return max(5, round(settings.default.max_examples * weight))


# --- the table, read -------------------------------------------------------------------


def parse_range(text: str | None) -> tuple[float, bool, float, bool] | None:
    """``"(0, inf)"`` -> (low, low_closed, high, high_closed)."""
    if not text:
        return None
    low, high = (float(end.strip()) for end in text[1:-1].split(","))
    return low, text[0] == "[", high, text[-1] == "]"


def arity(setting: dict[str, Any]) -> int | None:
    """Entries of a tuple setting (``tuple[float, float]`` -> 2), or None for a scalar."""
    match = re.search(r"tuple\[([^\]]*)\]", setting["type"])
    return None if match is None else len(match.group(1).split(","))


def is_int(setting: dict[str, Any]) -> bool:
    return setting["type"].startswith("int") or "tuple[int" in setting["type"]


def optional(setting: dict[str, Any]) -> bool:
    return "None" in setting["type"]


# --- valid values, at the edges of the ranges -----------------------------------------

TINY = 5e-324  # the smallest positive float
HUGE = 1e300
FLOAT_MAX = float(np.finfo(np.float64).max)


def run_cap(setting: dict[str, Any], high: float) -> float:
    """Upper end for values that are run, not only validated: integer settings without a
    tight upper bound cost time in proportion to their value (grid cells, image pixels,
    attempts, substeps), so runs stay within twice the default (a limit for run time only;
    validation goes to the range's end). Floats are run over their whole range."""
    default = setting["default"]
    scale = max(default) if isinstance(default, tuple) else default
    if is_int(setting) and isinstance(scale, int) and high > 2 * scale:
        return float(2 * scale)
    return high


def numbers(setting: dict[str, Any], *, run: bool) -> st.SearchStrategy[float]:
    """Valid numbers of a numeric setting: the ends of its range (or the closest numbers
    inside an open end; the largest float for an unbounded end), the default and others in
    between."""
    low, low_closed, high, high_closed = parse_range(setting["range"]) or (
        -math.inf,
        False,
        math.inf,
        False,
    )
    if run:
        high = run_cap(setting, high)
        high_closed = True
    if is_int(setting):
        lo = math.ceil(low) if low_closed else math.floor(low) + 1
        hi = 2**63 - 1 if math.isinf(high) else (int(high) if high_closed else math.ceil(high) - 1)
        return st.one_of(st.sampled_from([lo, hi]), st.integers(lo, hi))
    lo = -FLOAT_MAX if math.isinf(low) else (low if low_closed else np.nextafter(low, math.inf))
    hi = FLOAT_MAX if math.isinf(high) else (high if high_closed else np.nextafter(high, -math.inf))
    edges = [float(lo), float(hi)]
    if low == 0 and not low_closed:
        edges += [TINY, 1e-300, 1e-12]
    if math.isinf(high):
        edges += [HUGE, 1e12]
    if math.isinf(low):
        edges += [-HUGE, -1e12]
    return st.one_of(
        st.sampled_from(edges),
        st.floats(float(lo), float(hi), allow_nan=False, allow_infinity=False),
    )


@st.composite
def valid_value(draw: st.DrawFn, key: str, run: bool = False) -> Any:
    """A value the table allows for ``key`` on its own (combinations may still clash)."""
    setting = BY_KEY[key]
    if setting["choices"]:
        return draw(st.sampled_from(setting["choices"]))
    if setting["type"] == "bool":
        return draw(st.booleans())
    default = setting["default"]
    if optional(setting) and draw(st.booleans()):
        return None
    if draw(st.integers(0, 4)) == 0:
        return default
    n = arity(setting)
    element = numbers(setting, run=run)
    if n is None or (setting["type"].startswith("int |") and draw(st.booleans())):
        value = draw(element)
    elif isinstance(default, tuple) and len(default) == 2 and is_int(setting):
        # An integer pair: a multiple of the default keeps its ratio (a grid's square cells).
        low, high = default
        ratio = high / low
        first = draw(element)
        value = (
            (first, round(first * ratio))
            if ratio > 1
            else tuple(sorted(draw(element) for _ in range(2)))
        )
    else:
        items = [draw(element) for _ in range(n)]
        # Pairs are (low, high); longer tuples keep each consecutive pair ordered.
        for i in range(0, n - 1, 2):
            items[i : i + 2] = sorted(items[i : i + 2])
        value = tuple(items)
    if not is_int(setting) and isinstance(value, float) and draw(st.integers(0, 5)) == 0:
        value = np.float64(value)
    return value


# --- anything at all ------------------------------------------------------------------

plain = st.one_of(
    st.none(),
    st.booleans(),
    st.integers(),
    st.integers(-(2**80), 2**80),
    st.sampled_from([2**63 - 1, 2**63, 2**64 - 1, 2**64, -(2**63), -1, 0]),
    st.floats(),
    st.sampled_from([math.nan, math.inf, -math.inf, -0.0, TINY, HUGE, -HUGE]),
    st.text(max_size=6),
    st.binary(max_size=3),
    st.complex_numbers(max_magnitude=10),
)
numpy_scalars = st.one_of(
    st.floats().map(np.float64),
    st.floats(width=32).map(np.float32),
    st.integers(-(2**31), 2**31 - 1).map(np.int32),
    st.integers(0, 2**64 - 1).map(np.uint64),
    st.booleans().map(np.bool_),
    st.text(max_size=6).map(np.str_),
)
containers = st.one_of(
    st.lists(st.one_of(st.integers(-100, 2**64), st.floats(), st.none()), max_size=5),
    st.lists(st.floats(allow_nan=False), max_size=5).map(tuple),
    st.lists(st.integers(-100, 100), max_size=5).map(np.array),
    st.dictionaries(st.text(max_size=3), st.integers(), max_size=2),
    st.just(object()),
    st.just(frozenset({1, 2})),
)
anything = st.one_of(plain, numpy_scalars, containers)

unknown_keys = st.one_of(
    st.from_regex(r"[a-z][a-z0-9_]{0,11}", fullmatch=True),
    st.sampled_from(KEYS).map(str.upper),
    st.sampled_from(KEYS).map(lambda key: key + "_"),
).filter(lambda key: key not in BY_KEY and key not in OWN_PARAMETERS and key.isidentifier())


def certainly_invalid(key: str, value: Any) -> bool:
    """True when ``value`` is wrong for ``key`` whatever the other settings are: a type no
    setting takes, a non-finite number, or a number outside the setting's range."""
    setting = BY_KEY[key]
    if value is None:
        return not optional(setting)
    # (bytes and sets are sequences: the core reads b"\\x00\\x00" as a pair of zeros.)
    if isinstance(value, (dict, complex)) or type(value) is object:
        return True
    if setting["choices"] or setting["type"] == "bool":
        return False  # checked by the core (bool subtleties, numpy strings): no claim
    if isinstance(value, (str, np.str_)):
        return True
    if isinstance(value, (float, np.floating)) and not math.isfinite(value):
        return True
    bounds = parse_range(setting["range"])
    if bounds is None or isinstance(value, (bool, np.bool_)):
        return False
    if not isinstance(value, (int, float, np.integer, np.floating)) or arity(setting):
        return False
    low, low_closed, high, high_closed = bounds
    below = value < low or (value == low and not low_closed)
    above = value > high or (value == high and not high_closed)
    return below or above


@st.composite
def settings_dicts(draw: st.DrawFn, keys: list[str], run: bool, hostile: float) -> dict:
    """1 to 4 settings: known keys with valid (or, with probability ``hostile``, arbitrary)
    values, and sometimes an unknown key."""
    result: dict[str, Any] = {}
    for key in draw(st.lists(st.sampled_from(keys), min_size=1, max_size=4, unique=True)):
        bad = draw(st.floats(0, 1)) < hostile
        result[key] = draw(anything) if bad else draw(valid_value(key, run))
    if draw(st.floats(0, 1)) < hostile / 4:
        result[draw(unknown_keys)] = draw(anything)
    return result


# --- the oracle -----------------------------------------------------------------------


def call(function: Any, *args: Any, **kwargs: Any) -> tuple[Any, BaseException | None]:
    """``function``'s result, or the documented error it raised. Anything else (a
    PanicException included: it is a BaseException) fails the test with the input."""
    try:
        return function(*args, **kwargs), None
    except DOCUMENTED as error:
        return None, error
    except BaseException as error:  # PanicException derives from it
        pytest.fail(
            f"{type(error).__module__}.{type(error).__name__} (not ValueError/TypeError) from "
            f"{getattr(function, '__qualname__', function)} with {args!r} {kwargs!r}: {error}"
        )


def assert_names_the_setting(error: BaseException, given: dict[str, Any]) -> None:
    """The message names a setting: the given key when that key alone is certainly wrong
    (or unknown); otherwise one of the given keys or the setting a combination clashes
    with (e.g. ``grid_shape`` for a cupboard of another shape)."""
    message = str(error)
    unknown = [key for key in given if key not in BY_KEY]
    culprits = unknown + [
        key for key, value in given.items() if key in BY_KEY and certainly_invalid(key, value)
    ]
    if len(given) == 1 and culprits:
        assert culprits[0] in message, (culprits, message)
    assert any(key in message for key in [*given, *KEYS]), (given, message)


def assert_finite(name: str, value: Any) -> None:
    array = np.asarray(value, dtype=np.float64)
    assert np.all(np.isfinite(array)), (name, value)


def reset_or_refused(env: Any, seed: int) -> tuple | None:
    """``env.reset(seed=seed)``'s result, or None if it was refused for the layout with a
    ValueError naming a setting (a documented error)."""
    reset, error = call(env.reset, seed=seed)
    if error is not None:
        assert isinstance(error, ValueError)
        assert_names_the_setting(error, {})
        return None
    return reset


def random_actions(space: Any, rng: np.random.Generator, batch: tuple[int, ...] = ()) -> Any:
    """Actions for ``space`` (one env's): probe indices in the probe mode, else wrist commands
    drawn past the Box's bounds (the env clips them)."""
    if isinstance(space, gym.spaces.MultiDiscrete):
        return rng.integers(0, space.nvec, (*batch, len(space.nvec)))
    return rng.uniform(-1.5, 1.5, (*batch, *space.shape)).astype(np.float32)


def check_rollout(env: Any, seed: int, steps: int, rng: np.random.Generator) -> None:
    """A reset and ``steps`` random steps of a single env: everything finite and in its
    space (a reset refused for the layout is a documented error)."""
    reset = reset_or_refused(env, seed)
    if reset is None:
        return
    observation, info = reset
    space = env.observation_space
    assert space.contains(observation), observation
    for key, value in info.items():
        assert_finite(key, value)
    for _ in range(steps):
        observation, reward, terminated, truncated, info = env.step(
            random_actions(env.action_space, rng)
        )
        assert space.contains(observation), observation
        assert math.isfinite(reward)
        assert isinstance(terminated, bool) and isinstance(truncated, bool)
        for key, value in info.items():
            assert_finite(key, value)
        if terminated or truncated:
            observation, info = env.reset(seed=seed + 1)


def check_vector_rollout(env: Any, seed: int, steps: int, rng: np.random.Generator) -> None:
    reset = reset_or_refused(env, seed)
    if reset is None:
        return
    observation, info = reset
    assert env.observation_space.contains(observation)
    for _ in range(steps):
        actions = random_actions(env.single_action_space, rng, (env.num_envs,))
        (observation, rewards, terminated, truncated, info), error = call(env.step, actions)
        if error is not None:  # an autoreset whose layout the settings do not allow
            assert isinstance(error, ValueError)
            assert_names_the_setting(error, {})
            return
        assert env.observation_space.contains(observation)
        assert np.all(np.isfinite(rewards))
        assert terminated.dtype == truncated.dtype == np.bool_
        for key, value in info.items():
            assert_finite(key, value)


def resolve_in_core(**settings: Any) -> dict[str, Any]:
    """Every setting by key as the core checks and reads ``settings``."""
    return _core.EpisodeConfig(**settings).as_dict()


# --- the properties ---------------------------------------------------------------------


@settings(max_examples=examples(10))
@given(given_settings=settings_dicts(KEYS, run=False, hostile=0.5))
def test_any_settings_validate_alike_everywhere_or_name_the_setting(given_settings: dict) -> None:
    """Validation alone (cheap, so many examples, up to the ranges' far ends): the config
    class and the core agree; a valid set resolves to every key and round-trips."""
    config, error = call(CupboardSearchConfig, **given_settings)
    resolved, core_error = call(resolve_in_core, **given_settings)
    if error is None or core_error is None:
        assert error is None and core_error is None, (error, core_error)
    else:  # (with several bad settings, each path may name a different one first)
        assert_names_the_setting(error, given_settings)
        assert_names_the_setting(core_error, given_settings)
        return
    assert sorted(resolved) == KEYS
    assert resolve_in_core(**resolved) == resolved
    assert CupboardSearchConfig(**resolved).settings_dict() == resolved
    # The config holds plain values (lists, arrays and numpy scalars read by the core), so
    # it is hashable and means what the core resolved.
    assert resolve_in_core(**config.settings_dict()) == resolved
    assert hash(config) == hash(CupboardSearchConfig(**config.settings_dict()))


ENTRY_POINTS = ["gym.make", "class", "vector", "gym.make_vec"]


@settings(max_examples=examples(2))
@given(
    given_settings=settings_dicts(KEYS, run=True, hostile=0.2),
    entry=st.sampled_from(ENTRY_POINTS),
    seed=st.integers(0, 2**64 - 1),
)
def test_edge_settings_build_reset_and_step_in_their_spaces(
    given_settings: dict, entry: str, seed: int
) -> None:
    """Settings at the ranges' edges (integers within twice their default), through every
    way of making an env: it builds, resets and steps with finite outputs in its spaces, or
    refuses naming a setting."""
    rng = np.random.default_rng(seed % 2**32)
    if entry == "gym.make":
        env, error = call(gym.make, ENV_ID, **given_settings)
    elif entry == "class":
        env, error = call(CupboardSearchEnv, **given_settings)
    elif entry == "vector":
        env, error = call(CupboardSearchVectorEnv, num_envs=2, threads=1, **given_settings)
    else:
        env, error = call(
            gym.make_vec,
            ENV_ID,
            num_envs=2,
            vectorization_mode="vector_entry_point",
            threads=1,
            **given_settings,
        )
    if error is not None:
        assert_names_the_setting(error, given_settings)
        return
    try:
        if entry in ("vector", "gym.make_vec"):
            check_vector_rollout(env, seed % 2**63, steps=4, rng=rng)
        else:
            check_rollout(env, seed % 2**63, steps=4, rng=rng)
    finally:
        env.close()


def scene_call(seed: int, scene_settings: dict, as_config: bool) -> tuple[Any, Any]:
    if as_config:
        return call(_core.Scene, seed, config=scene_settings)
    return call(_core.Scene, seed, **scene_settings)


@settings(max_examples=examples(3))
@given(
    scene_settings=settings_dicts(SCENE, run=True, hostile=0.3),
    as_config=st.booleans(),
    seed=st.integers(0, 2**64 - 1),
    commands=st.lists(
        st.tuples(*[st.floats(-0.05, 0.05, allow_nan=False)] * 2, st.floats(-0.5, 0.5)),
        max_size=4,
    ),
)
def test_scene_settings_build_and_step_or_name_the_setting(
    scene_settings: dict, as_config: bool, seed: int, commands: list
) -> None:
    """``_core.Scene`` (config dict or keywords): a scene that builds steps with finite
    poses, contacts, depth and state."""
    scene, error = scene_call(seed, scene_settings, as_config)
    if error is not None:
        assert_names_the_setting(error, scene_settings)
        return
    assert scene.seed == seed
    config = scene.config
    assert sorted(config) == SCENE
    for key, value in scene_settings.items():
        if key in BY_KEY and not isinstance(value, np.floating | np.integer):
            # (The core reads any collection as a sequence in iteration order, sets too.)
            collection = list | np.ndarray | set | frozenset | bytes
            expected = tuple(value) if isinstance(value, collection) else value
            assert config[key] == expected or np.isclose(config[key], expected).all(), key
    for dx, dy, dyaw in commands:
        report = scene.step(dx=dx, dy=dy, dyaw=dyaw)
        assert_finite("moved", report["moved"])
    assert_finite("hand_pose", scene.hand_pose)
    assert_finite("finger_pose", scene.finger_pose)
    assert_finite("state_vector", scene.state_vector)
    assert_finite("slice_points", scene.slice_points)
    contacts = scene.contacts
    assert_finite("contact points", contacts["points"])
    assert_finite("contact normals", contacts["normals"])
    jars = scene.jars
    assert_finite("jar positions", jars["positions"])
    assert 0 <= scene.target < len(jars["shapes"])


@settings(max_examples=examples(5))
@given(key=st.sampled_from(KEYS), value=anything)
def test_one_setting_of_any_type_is_accepted_or_refused_naming_it(key: str, value: Any) -> None:
    """One key, any value: the config class, the scene (for scene keys) and the core's
    resolver refuse it alike, with the key in the message."""
    given_settings = {key: value}
    _, error = call(CupboardSearchConfig, **given_settings)
    _, core_error = call(resolve_in_core, **given_settings)
    assert (error is None) == (core_error is None)
    if certainly_invalid(key, value):
        assert error is not None, f"{key}={value!r} was accepted"
    if error is not None:
        assert type(error) is type(core_error)
        assert_names_the_setting(error, given_settings)
    if key in SCENE_KEYS and certainly_invalid(key, value):
        _, scene_error = call(_core.Scene, 0, **given_settings)
        assert scene_error is not None and type(scene_error) is type(error)
        assert key in str(scene_error)


# --- found by this fuzzer: bugs in the Rust core (env_core), now regression tests ---------


def test_a_huge_cupboard_depth_is_refused_not_a_panic() -> None:
    """Found by this fuzzer, fixed in env_core/src/scene/config.rs (every scene length in
    ``Range::LENGTH``, env_core/src/settings/range.rs): a cupboard depth of 1e20 m passed
    the settings check, then parry3d's EPA panicked (index out of bounds) while
    ``Scene::new`` stepped the physics."""
    _, error = call(_core.Scene, 0, cupboard_depth=1e20)
    assert isinstance(error, ValueError) and "cupboard_depth" in str(error), error


@pytest.mark.parametrize(("key", "value"), [("cupboard_depth", 1e39), ("cupboard_width", 1e45)])
def test_a_scene_length_beyond_f32_is_refused(key: str, value: float) -> None:
    """Found by this fuzzer, fixed in env_core/src/scene/config.rs (``Range::LENGTH``): a
    length above f32::MAX (3.4e38) passed the settings check and the f32 physics turned it
    into inf (``Scene.state_vector`` not finite). Refused alike by the scene, the core's
    resolver and the config class, naming the key and the range the table gives."""
    _, _, high, _ = parse_range(BY_KEY[key]["range"])
    assert value > high
    for function, args in [
        (_core.Scene, (0,)),
        (resolve_in_core, ()),
        (CupboardSearchConfig, ()),
    ]:
        _, error = call(function, *args, **{key: value})
        assert isinstance(error, ValueError) and key in str(error), (function, error)
    # Its range's upper end itself is valid and builds a finite scene.
    scene, error = call(_core.Scene, 0, **{key: high})
    if error is None:
        assert_finite("state_vector", scene.state_vector)
    else:  # (a cupboard this size may not fit the default layout: named, not a panic)
        assert_names_the_setting(error, {key: high})


def test_occupancy_map_under_the_largest_depth_noise_steps() -> None:
    """Found by this fuzzer, fixed in env_core/src/episode/maps/occupancy.rs: under huge depth
    noise the occupancy map sampled each reading's whole ray, every half cell, so a reading
    far outside the grid took practically forever. The largest depth noise the table
    allows, and the longest camera range, now step like any other."""
    noise, far = (
        parse_range(BY_KEY[key]["range"])[2] for key in ("depth_noise_std", "camera_max_range")
    )
    env = CupboardSearchEnv(map="occupancy", depth_noise_std=noise, camera_max_range=far)
    try:
        check_rollout(env, seed=0, steps=5, rng=np.random.default_rng(0))
    finally:
        env.close()
