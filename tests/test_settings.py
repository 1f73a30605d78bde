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

from tactile_search import CupboardSearchEnv, _core
from tactile_search.envs import CupboardSearchConfig

EPISODE_SETTINGS = list(_core.EpisodeBatch.settings())
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
    assert _core.EpisodeBatch.resolve_settings() == defaults


@pytest.mark.parametrize("setting", EPISODE_SETTINGS, ids=lambda s: s["key"])
def test_every_setting_round_trips_through_the_env(setting: dict) -> None:
    key = setting["key"]
    env_config = CupboardSearchConfig(**{key: setting["default"]})
    assert getattr(env_config, key) == setting["default"]
    batch = env_config.make_batch([0])
    assert batch.config[key] == setting["default"]
    assert _core.EpisodeBatch([0], config=batch.config).config == batch.config


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
    expected = "finite" if bad is None else f"in {setting['range']}"
    assert expected in str(error.value)


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
