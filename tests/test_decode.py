"""The core's decoders and static geometry (``env.decode_map``, ``env.decode_proprio``,
``env.geometry``): the inverse of the encodings within their quantisation step, bit for bit
equal to the formulas written out here (what a planner would otherwise type by hand), the
geometry equal to what a ``Scene`` reports, and bad input refused with ``TypeError`` /
``ValueError`` naming what was expected and what came."""

from __future__ import annotations

import gymnasium as gym
import numpy as np
import pytest

import tactile_search  # noqa: F401  (registers the env)
from tactile_search import CupboardSearchEnv, _core
from tactile_search.envs.observation import MAP_CHANNELS, PROPRIO

MODES = ("gpis", "occupancy", "none")


def episode(mode: str, seed: int = 2, **settings) -> tuple[CupboardSearchEnv, list, list]:
    """An oracle episode (it ends touching the target, so the last proprio has a contact):
    the env, its observations and the render states beside them."""
    env = gym.make("tactile_search/CupboardSearch-v0", map=mode, **settings).unwrapped
    obs, _ = env.reset(seed=seed)
    observations, states = [obs], [env.render_state()]
    for _ in range(120):
        obs, _, terminated, truncated, _ = env.step(env.oracle_action())
        observations.append(obs)
        states.append(env.render_state())
        if terminated or truncated:
            break
    return env, observations, states


@pytest.fixture(scope="module")
def episodes() -> dict[str, tuple]:
    return {mode: episode(mode) for mode in MODES}


def test_gpis_map_decodes_as_the_hand_formula_and_within_a_step(episodes) -> None:
    env, observations, states = episodes["gpis"]
    mean_scale, std_scale = env.config.mean_scale, env.config.std_scale
    for obs, state in zip(observations, states, strict=True):
        decoded = env.decode_map(obs["map"])
        assert sorted(decoded) == ["mean", "std"]
        pixels = obs["map"].astype(np.float64)
        mean = (pixels[MAP_CHANNELS["gpis", "mean"]] - 128.0) / 127.0 * mean_scale
        std = pixels[MAP_CHANNELS["gpis", "std"]] / 255.0 * std_scale
        np.testing.assert_array_equal(decoded["mean"], mean)
        np.testing.assert_array_equal(decoded["std"], std)
        assert decoded["mean"].dtype == np.float64 and decoded["mean"].shape == (40, 80)
        true_mean = np.clip(state["map"]["mean"], -mean_scale, mean_scale)
        true_std = np.clip(state["map"]["std"], 0.0, std_scale)
        assert np.abs(decoded["mean"] - true_mean).max() <= 0.5 * mean_scale / 127 + 1e-12
        assert np.abs(decoded["std"] - true_std).max() <= 0.5 * std_scale / 255 + 1e-12


def test_occupancy_map_decodes_to_its_probability(episodes) -> None:
    env, observations, states = episodes["occupancy"]
    for obs, state in zip(observations, states, strict=True):
        decoded = env.decode_map(obs["map"])
        assert sorted(decoded) == ["occupied"]
        pixels = obs["map"].astype(np.float64)
        np.testing.assert_array_equal(
            decoded["occupied"], pixels[MAP_CHANNELS["occupancy", "occupied"]] / 255.0
        )
        truth = state["map"]["occupancy"].astype(np.float64)
        assert np.abs(decoded["occupied"] - truth).max() <= 0.5 / 255 + 1e-6


def test_none_has_no_map_to_decode(episodes) -> None:
    env, observations, _ = episodes["none"]
    assert "map" not in observations[0]
    with pytest.raises(ValueError, match="'none'"):
        env.decode_map(np.zeros((2, 40, 80), np.uint8))


@pytest.mark.parametrize("mode", MODES)
def test_proprio_decodes_as_the_hand_formulas(episodes, mode: str) -> None:
    env, observations, states = episodes[mode]
    g = env.geometry()
    (x0, x1), (y0, y1) = g["workspace"]
    p = PROPRIO
    contacts = 0
    for steps, (obs, state) in enumerate(zip(observations, states, strict=True)):
        proprio = obs["proprio"]
        d = env.decode_proprio(proprio)
        assert list(d) == [
            "x", "y", "yaw", "deflection", "in_contact", "contact_dx", "contact_dy",
            "normal_x", "normal_y", "time_left", "steps",
        ]  # fmt: skip
        # The planner's formulas (agents/scripted/gpis_probe_planner.py::_pose), bit for bit.
        assert d["x"] == x0 + (float(proprio[p["x"]]) + 1.0) * 0.5 * (x1 - x0)
        assert d["y"] == y0 + (float(proprio[p["y"]]) + 1.0) * 0.5 * (y1 - y0)
        # In f64 (the planner's arctan2 of the float32 entries ran in float32, whose rounding
        # is numpy's and platform-dependent; the f64 one is within it).
        sin_yaw, cos_yaw = float(proprio[p["sin_yaw"]]), float(proprio[p["cos_yaw"]])
        assert d["yaw"] == float(np.arctan2(sin_yaw, cos_yaw))
        f32_yaw = float(np.arctan2(proprio[p["sin_yaw"]], proprio[p["cos_yaw"]]))
        assert abs(d["yaw"] - f32_yaw) <= 4e-7 * max(1.0, abs(d["yaw"]))
        assert d["deflection"] == float(proprio[p["deflection"]]) * g["finger_limit"]
        assert d["in_contact"] is bool(proprio[p["in_contact"]] > 0.5)
        offset = np.asarray(proprio[[p["contact_dx"], p["contact_dy"]]], float)
        assert (d["contact_dx"], d["contact_dy"]) == tuple(g["finger_length"] * offset)
        normal = np.asarray(proprio[[p["normal_x"], p["normal_y"]]], float)
        assert (d["normal_x"], d["normal_y"]) == tuple(normal)
        assert d["time_left"] == float(proprio[p["time_left"]])
        assert d["steps"] == steps
        # And the physical truth, within the float32 rounding of the entries.
        hx, hy, hyaw = state["hand"]
        assert abs(d["x"] - hx) < 1e-6 and abs(d["y"] - hy) < 1e-6
        assert abs(np.angle(np.exp(1j * (d["yaw"] - hyaw)))) < 1e-6
        assert abs(d["deflection"] - (state["finger"][2] - hyaw)) < 1e-5
        assert d["in_contact"] == bool(state["contacts"])
        if d["in_contact"]:
            contacts += 1
            cx, cy, nx, ny = state["contacts"][0]
            length = g["finger_length"]
            assert abs(d["contact_dx"] - np.clip(cx - hx, -length, length)) < 1e-6
            assert abs(d["contact_dy"] - np.clip(cy - hy, -length, length)) < 1e-6
            assert abs(d["normal_x"] - nx) < 1e-6 and abs(d["normal_y"] - ny) < 1e-6
    assert contacts > 0


SETTINGS = [
    {},
    {
        "grid_shape": (36, 72),
        "mean_scale": 0.03,
        "finger_length": 0.09,
        "camera_position": (0.05, -0.3, 0.07),
        "round_diameter": (0.04, 0.06),
        "square_side": (0.04, 0.046),
        "workspace": (-0.4, 0.4, -0.25, 0.28),
        "hand_start": (0.02, -0.12, 0.1),
    },
]


@pytest.mark.parametrize("settings", SETTINGS)
def test_geometry_is_what_a_scene_reports(settings: dict) -> None:
    env = CupboardSearchEnv(**settings)
    g = env.geometry()
    scene = _core.Scene(0, config=env.config.scene_dict())
    value = scene.config
    hand = _core.hand_geometry(value)
    camera = scene.camera["position"]
    assert (g["width"], g["depth"]) == (scene.cupboard["width"], scene.cupboard["depth"])
    assert g["camera"] == (float(camera[0]), float(camera[1]))
    assert g["start"] == tuple(scene.hand_pose)
    (x0, x1), (y0, y1) = g["workspace"]
    assert [x0, x1, y0, y1] == list(np.ravel(value["workspace"]))
    for key in (
        "max_step_translation", "max_step_yaw", "wrist_half_extent", "arm_length",
        "arm_half_width", "finger_length", "finger_half_thickness", "finger_limit",
        "target_min_depth", "wall_gap",
    ):  # fmt: skip
        assert g[key] == float(value[key]), key
    assert g["joint_offset"] == hand["joint_offset"]
    assert g["reach"] == hand["reach"] == g["joint_offset"] + g["finger_length"]
    assert g["jar_radius"] == (
        0.5 * min(value["round_diameter"][0], value["square_side"][0]),
        0.5 * max(value["round_diameter"][1], np.sqrt(2.0) * value["square_side"][1]),
    )
    assert g["grid_shape"] == tuple(env.config.grid_shape)
    height, width = g["grid_shape"]
    assert g["cell"] == g["depth"] / height
    assert (g["mean_scale"], g["std_scale"]) == (env.config.mean_scale, env.config.std_scale)
    xs = -0.5 * g["width"] + (np.arange(width) + 0.5) * g["width"] / width
    ys = (np.arange(height) + 0.5) * g["depth"] / height
    gx, gy = np.meshgrid(xs, ys)
    assert g["xs"].dtype == np.float64 and g["xs"].shape == (height, width)
    np.testing.assert_array_equal(g["xs"], gx)
    np.testing.assert_array_equal(g["ys"], gy)
    # The same cells as the map's own grid.
    from tactile_search import Gpis

    centres = Gpis(bounds=env._batch.map_bounds, shape=(height, width)).cell_centres
    np.testing.assert_allclose(np.stack([g["xs"], g["ys"]], axis=-1), centres, atol=1e-12)


def test_decoders_round_trip_a_changed_config() -> None:
    env, observations, states = episode("gpis", seed=3, **SETTINGS[1])
    for obs, state in zip(observations, states, strict=True):
        decoded = env.decode_map(obs["map"])
        assert decoded["mean"].shape == (36, 72)
        true_mean = np.clip(state["map"]["mean"], -0.03, 0.03)
        assert np.abs(decoded["mean"] - true_mean).max() <= 0.5 * 0.03 / 127 + 1e-12
        d = env.decode_proprio(obs["proprio"])
        assert abs(d["x"] - state["hand"][0]) < 1e-6 and abs(d["y"] - state["hand"][1]) < 1e-6


def test_bad_input_is_refused_naming_expected_and_got() -> None:
    env = CupboardSearchEnv(map="gpis")
    obs, _ = env.reset(seed=0)
    with pytest.raises(TypeError, match=r"uint8 numpy array of shape \(2, 40, 80\).*float64"):
        env.decode_map(obs["map"].astype(np.float64))
    with pytest.raises(ValueError, match=r"shape \(2, 40, 80\), got shape \(40, 80\)"):
        env.decode_map(obs["map"][0])
    with pytest.raises(TypeError, match=r"uint8 numpy array.*got list"):
        env.decode_map([[1, 2]])
    with pytest.raises(TypeError, match=r"float32 numpy array of shape \(11,\).*float64"):
        env.decode_proprio(obs["proprio"].astype(np.float64))
    with pytest.raises(ValueError, match=r"shape \(11,\), got shape \(10,\)"):
        env.decode_proprio(obs["proprio"][:10])
    with pytest.raises(TypeError, match="float32 numpy array"):
        env.decode_proprio(None)
