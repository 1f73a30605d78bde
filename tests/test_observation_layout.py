"""One observation layout: the core's table names every proprio entry and map channel, and
the docstring, the decoders and the spaces follow from it."""

from __future__ import annotations

import numpy as np

from tactile_search import CupboardSearchEnv, CupboardSearchVectorEnv, _core
from tactile_search.envs.observation import (
    MAP_CHANNELS,
    PROPRIO,
    STEP_INFO,
    map_channel_table,
    proprio_table,
)

NAMES = [
    "x",
    "y",
    "cos_yaw",
    "sin_yaw",
    "deflection",
    "in_contact",
    "contact_dx",
    "contact_dy",
    "normal_x",
    "normal_y",
    "time_left",
]


def test_the_core_names_every_proprio_entry_in_order() -> None:
    layout = _core.observation_layout()
    assert [f["name"] for f in layout["proprio"]] == NAMES
    assert [f["index"] for f in layout["proprio"]] == list(range(len(NAMES)))
    assert all(f["scale"] and f["meaning"] for f in layout["proprio"])
    env = CupboardSearchEnv()
    assert env.observation_space["proprio"].shape == (len(PROPRIO),)
    assert env._batch.proprio_len == len(PROPRIO)


def test_the_map_channels_are_described_for_each_mode_with_a_map() -> None:
    assert set(MAP_CHANNELS) == {
        ("gpis", "mean"),
        ("gpis", "std"),
        ("occupancy", "occupied"),
        ("occupancy", "empty"),
    }
    assert sorted(MAP_CHANNELS.values()) == [0, 0, 1, 1]


def test_the_docstring_tables_are_generated_from_the_core() -> None:
    doc = CupboardSearchEnv.__doc__
    assert "{proprio_table}" not in doc and "{map_channel_table}" not in doc
    for table in (proprio_table(), map_channel_table()):
        for row in table.splitlines():
            assert row in doc
    assert f"Box(-1, 1, ({len(PROPRIO)},), float32)" in doc


def test_named_entries_decode_a_known_state() -> None:
    env = CupboardSearchEnv(map="none", max_steps=8)
    observation, _ = env.reset(seed=0)
    proprio = observation["proprio"]
    assert proprio[PROPRIO["time_left"]] == 1.0 and proprio[PROPRIO["in_contact"]] == 0.0
    yaw = np.arctan2(proprio[PROPRIO["sin_yaw"]], proprio[PROPRIO["cos_yaw"]])
    assert abs(yaw) < 1e-6  # the hand starts pointing into the cupboard
    for step in range(1, 4):
        observation, *_ = env.step(np.array([0.5, 0.0, 0.0]))
        assert observation["proprio"][PROPRIO["time_left"]] == np.float32(1 - step / 8)
    assert observation["proprio"][PROPRIO["x"]] > proprio[PROPRIO["x"]]  # moved along +x


def test_info_keys_and_types_come_from_the_cores_table() -> None:
    fields = _core.step_info_fields()
    names = [f["name"] for f in fields]
    env = CupboardSearchEnv(map="none")
    _, info = env.reset(seed=0)
    assert list(info) == names
    _, _, _, _, info = env.step(np.zeros(3))
    assert list(info) == names
    kinds = {"float64": float, "bool": bool, "int64": int}
    for name, value in info.items():
        assert type(value) is kinds[STEP_INFO[name][0]], name
    vector = CupboardSearchVectorEnv(num_envs=3, map="none")
    _, infos = vector.reset(seed=0)
    _, _, _, _, infos = vector.step(np.zeros((3, 3)))
    # one array per key, in the core's order, and gymnasium's "_key" mask for each; no
    # per-env dicts
    assert [key for key in infos if not key.startswith("_")] == names
    assert sorted(infos) == sorted([*names, *(f"_{name}" for name in names)])
    for name in names:
        values = infos[name]
        assert infos[f"_{name}"].all()
        assert values.shape == (3,) and values.dtype == np.dtype(STEP_INFO[name][0]), name
