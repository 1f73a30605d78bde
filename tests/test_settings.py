"""The core's settings tables are the one source of every setting: the Python config class,
the environment's signature and docs, and the stub all follow from them, every setting
round-trips, and bad values raise errors that name the key as typed."""

from __future__ import annotations

import dataclasses
import inspect
import subprocess
import sys
from pathlib import Path

import gymnasium as gym
import pytest

from tactile_search import CupboardSearchEnv, CupboardSearchVectorEnv, _core
from tactile_search.envs import CupboardSearchConfig

EPISODE_SETTINGS = list(_core.EpisodeConfig.settings())
SCENE_SETTINGS = list(_core.Scene.settings())
ROOT = Path(__file__).resolve().parent.parent


def test_the_config_class_has_one_field_per_core_setting_with_its_default_and_type() -> None:
    fields = {f.name: f for f in dataclasses.fields(CupboardSearchConfig)}
    assert list(fields) == [s["key"] for s in EPISODE_SETTINGS]
    for s in EPISODE_SETTINGS:
        assert fields[s["key"]].default == s["default"]
        assert fields[s["key"]].type == s["type"]
        assert fields[s["key"]].metadata["doc"] == s["doc"]


def test_the_scene_table_is_part_of_the_episode_table() -> None:
    episode = {s["key"]: s for s in EPISODE_SETTINGS}
    for s in SCENE_SETTINGS:
        assert episode[s["key"]] == s


def test_the_env_signature_lists_every_setting_with_its_default() -> None:
    parameters = inspect.signature(CupboardSearchEnv).parameters
    assert next(iter(parameters)) == "render_mode"
    for s in EPISODE_SETTINGS:
        assert parameters[s["key"]].default == s["default"], s["key"]


def test_the_vector_env_signature_lists_its_own_arguments_then_every_setting() -> None:
    from tactile_search import CupboardSearchVectorEnv

    parameters = inspect.signature(CupboardSearchVectorEnv).parameters
    assert list(parameters)[:3] == ["num_envs", "threads", "copy"]
    assert [p for p in parameters if p in {s["key"] for s in EPISODE_SETTINGS}] == [
        s["key"] for s in EPISODE_SETTINGS
    ]


def test_the_env_docstring_has_a_row_per_setting() -> None:
    doc = CupboardSearchEnv.__doc__ or ""
    assert "{settings_table}" not in doc
    for s in EPISODE_SETTINGS:
        assert f"| ``{s['key']}`` |" in doc, s["key"]


def test_the_time_limit_and_every_default_come_from_the_core() -> None:
    defaults = {s["key"]: s["default"] for s in EPISODE_SETTINGS}
    config = CupboardSearchConfig()
    assert config.settings_dict() == defaults
    assert _core.EpisodeConfig().as_dict() == defaults


@pytest.mark.parametrize("setting", EPISODE_SETTINGS, ids=lambda s: s["key"])
def test_every_setting_round_trips_through_the_env(setting: dict) -> None:
    key = setting["key"]
    env_config = CupboardSearchConfig(**{key: setting["default"]})
    assert getattr(env_config, key) == setting["default"]
    batch = env_config.make_batch(1)
    assert batch.config.as_dict()[key] == setting["default"]
    assert _core.EpisodeBatch(batch.config, 1).config == batch.config


@pytest.mark.parametrize("setting", EPISODE_SETTINGS, ids=lambda s: s["key"])
def test_every_setting_refuses_a_wrong_type_naming_its_key(setting: dict) -> None:
    with pytest.raises(TypeError, match=f"^{setting['key']} must be"):
        CupboardSearchConfig(**{setting["key"]: {"not": "a setting"}})
    with pytest.raises(TypeError, match=f"^{setting['key']} must be"):
        CupboardSearchConfig(**{setting["key"]: [object()] * 2})


def _outside(text: str) -> float | None:
    """A number outside an interval written like ``(0, inf)`` or ``[1, 7]``."""
    low, high = (end.strip() for end in text[1:-1].split(","))
    if low != "-inf":
        return float(low) - (1.0 if text[0] == "[" else 0.0)
    if high != "inf":
        return float(high) + (1.0 if text[-1] == "]" else 0.0)
    return None


def _with_number(default: object, number: float) -> object:
    if isinstance(default, tuple):
        return tuple(_with_number(item, number) for item in default)
    if isinstance(default, int) and not isinstance(default, bool) and number == int(number):
        return int(number)
    return number


@pytest.mark.parametrize(
    "setting", [s for s in EPISODE_SETTINGS if s["range"]], ids=lambda s: s["key"]
)
def test_every_setting_refuses_a_value_out_of_range_naming_key_and_range(setting: dict) -> None:
    bad = _outside(setting["range"])
    value = _with_number(setting["default"], float("nan") if bad is None else bad)
    with pytest.raises(ValueError, match=f"^{setting['key']} must be") as error:
        CupboardSearchConfig(**{setting["key"]: value})
    expected = "finite" if bad is None else _in_words(setting["range"])
    assert expected in str(error.value)


def _in_words(text: str) -> str:
    """The rule of an interval written like ``[1, inf)`` in the words errors use: ``>= 1``,
    ``> 0``, ``from 0 to 1``, ``> 0 and <= 100``."""
    low, high = (end.strip() for end in text[1:-1].split(","))
    lower = None if low == "-inf" else (">=" if text[0] == "[" else ">", low)
    upper = None if high == "inf" else ("<=" if text[-1] == "]" else "<", high)
    if lower and upper and lower[0] == ">=" and upper[0] == "<=":
        return f"from {low} to {high}"
    return " and ".join(f"{bound[0]} {bound[1]}" for bound in (lower, upper) if bound)


def test_a_count_of_the_wrong_type_states_the_rule_as_one_out_of_range_does() -> None:
    with pytest.raises(TypeError, match=r"^max_steps must be an int >= 1, got 10.0"):
        CupboardSearchEnv(max_steps=10.0)
    with pytest.raises(ValueError, match=r"^max_steps must be an int >= 1, got 0"):
        CupboardSearchEnv(max_steps=0)
    with pytest.raises(ValueError, match=r"^max_steps must be an int >= 1, got -3"):
        CupboardSearchEnv(max_steps=-3)


@pytest.mark.parametrize(
    "make",
    [
        CupboardSearchEnv,
        lambda **kw: CupboardSearchVectorEnv(num_envs=2, **kw),
        lambda **kw: gym.make("tactile_search/CupboardSearch-v0", **kw),
    ],
)
def test_an_unknown_keyword_names_the_env_and_the_closest_settings(make: object) -> None:
    with pytest.raises(TypeError) as error:
        make(max_step=5)  # type: ignore[operator]
    message = str(error.value)
    assert "got an unexpected keyword argument 'max_step'" in message
    assert "did you mean 'max_steps'" in message
    assert "CupboardSearchConfig" not in message
    with pytest.raises(TypeError, match=r"the settings are task, max_steps, \w+"):
        make(zzzzzz=1)  # type: ignore[operator]


def test_gym_make_takes_every_setting_by_keyword() -> None:
    env = gym.make("tactile_search/CupboardSearch-v0", map="occupancy", jar_count=4)
    assert env.unwrapped.config.map == "occupancy"
    assert env.unwrapped.config.jar_count == 4
    env.reset(seed=1)
    assert len(env.unwrapped.render_state()["jars"]) == 4


def test_the_committed_stub_is_generated_from_the_core() -> None:
    result = subprocess.run(
        [sys.executable, str(ROOT / "scripts" / "generate_stub.py"), "--check"],
        capture_output=True,
        text=True,
    )
    assert result.returncode == 0, result.stderr
    stub = (ROOT / "python" / "tactile_search" / "_core.pyi").read_text()
    for s in EPISODE_SETTINGS:
        assert f"    {s['key']}: " in stub


def test_a_fresh_interpreter_makes_the_env_by_the_id_that_names_its_module() -> None:
    script = (
        "import sys, gymnasium as gym\n"
        "env = gym.make('tactile_search:tactile_search/CupboardSearch-v0', max_steps=5)\n"
        "env.reset(seed=0)\n"
        "assert 'tactile_search' in sys.modules\n"
        "vec = gym.make_vec('tactile_search:tactile_search/CupboardSearch-v0', num_envs=2,\n"
        "                   vectorization_mode='vector_entry_point')\n"
        "vec.reset(seed=0)\n"
        "print('made')\n"
    )
    result = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True)
    assert result.returncode == 0, result.stderr
    assert result.stdout.strip() == "made"
