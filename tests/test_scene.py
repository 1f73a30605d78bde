"""The compiled ``_core.Scene``: it builds, steps, reads arrays with the right shapes and
dtypes, is deterministic, and refuses bad input with ValueError/TypeError."""

import math

import numpy as np
import pytest

from tactile_search._core import Scene


@pytest.fixture(scope="module")
def scene() -> Scene:
    return Scene(seed=3)


def test_builds_with_default_config_and_reports_the_layout(scene: Scene) -> None:
    jars = scene.jars
    n = len(jars["shapes"])
    assert 3 <= n <= 7
    assert set(jars["shapes"]) <= {"round", "square"}
    assert 0 <= scene.target < n
    assert jars["is_target"].dtype == np.bool_ and jars["is_target"].sum() == 1
    assert jars["positions"].shape == (n, 3) and jars["positions"].dtype == np.float64
    assert jars["rotations"].shape == (n, 4)
    for key in ("half_widths", "heights", "masses", "yaws", "displacement", "vertical", "tilt"):
        assert jars[key].shape == (n,) and jars[key].dtype == np.float64
    assert 0.0 <= scene.visible_fraction <= 0.10
    silhouette, visible = scene.target_pixels
    assert silhouette > 0 and visible <= silhouette
    corridor = scene.corridor
    assert corridor is not None and corridor["side"] in (-1.0, 1.0)
    assert scene.cupboard == pytest.approx({"width": 0.6, "depth": 0.3, "height": 0.3})
    assert "Scene(seed=3" in repr(scene)


def test_depth_cloud_and_slice_have_the_right_shapes_and_dtypes(scene: Scene) -> None:
    camera = scene.camera
    h, w = camera["height"], camera["width"]
    depth = scene.depth_image
    assert depth.shape == (h, w) and depth.dtype == np.float64
    look = scene.first_look
    assert look["labels"].shape == (h, w) and look["labels"].dtype == np.int32
    cloud = scene.cloud
    assert cloud.ndim == 2 and cloud.shape[1] == 3 and cloud.dtype == np.float64
    assert cloud.shape[0] == np.isfinite(depth).sum()
    assert look["cloud_labels"].shape == (cloud.shape[0],)
    sl = scene.slice_points
    assert sl.ndim == 2 and sl.shape[1] == 2 and 0 < sl.shape[0] <= 256
    assert look["slice_clean"].shape == sl.shape
    assert camera["rotation"].shape == (3, 3)
    # The target's visible pixels in the label image match the reported count.
    assert (look["labels"] == scene.target).sum() == scene.target_pixels[1]


def test_stepping_moves_the_hand_and_reports() -> None:
    s = Scene(seed=1)
    x0, y0, yaw0 = s.hand_pose
    report = s.step(dx=0.0, dy=0.005, dyaw=0.0)
    assert report["blocked"] is None and report["clipped"] is False
    assert report["moved"] == pytest.approx((0.0, 0.005, 0.0))
    assert s.hand_pose == pytest.approx((x0, y0 + 0.005, yaw0))
    assert s.steps == 1
    clipped = s.step(dx=1.0)
    assert clipped["clipped"] is True and clipped["commanded"][0] == pytest.approx(0.01)
    contacts = s.contacts
    assert contacts["points"].shape[1] == 2 and contacts["normals"].shape[1] == 2
    assert contacts["jars"].dtype == np.int64
    s.idle(10)
    assert math.isfinite(s.finger_angle)
    assert s.capture()["depth"].shape == s.depth_image.shape


def test_walls_stop_the_hand_and_the_block_is_reported() -> None:
    s = Scene(seed=2, jar_count=3)
    blocked = [s.step(dy=-0.01)["blocked"] for _ in range(40)]
    assert "workspace" in blocked


def test_reaching_through_the_corridor_touches_the_target() -> None:
    s = Scene(seed=7)
    corridor = s.corridor
    target = s.jars["positions"][s.target]
    inner = corridor["x"][0] if corridor["side"] > 0 else corridor["x"][1]
    x = inner + corridor["side"] * 0.017
    reach = 0.015 + 0.002 + 0.10
    for _ in range(100):
        hx, hy, _ = s.hand_pose
        if abs(hx - x) < 1e-9 and abs(hy - (target[1] - reach)) < 1e-9:
            break
        if abs(hx - x) > 1e-9:
            s.step(dx=float(np.clip(x - hx, -0.01, 0.01)))
        else:
            s.step(dy=float(np.clip(target[1] - reach - hy, -0.01, 0.01)))
    touched = False
    for _ in range(30):
        s.step(dyaw=0.02 * corridor["side"])
        if s.target in s.true_contacts["jars"]:
            touched = True
            break
    assert touched
    assert s.finger_angle != 0.0


def test_same_seed_and_commands_are_bit_identical() -> None:
    def run() -> np.ndarray:
        s = Scene(seed=5, depth_noise_std=0.003)
        for k in range(30):
            s.step(dx=0.002 * (k % 3 - 1), dy=0.006, dyaw=0.01)
        return np.concatenate([s.state_vector, s.slice_points.ravel()])

    a, b = run(), run()
    assert a.tobytes() == b.tobytes()


def test_config_from_dict_and_keywords() -> None:
    s = Scene(
        seed=0,
        config={"jar_count": (4, 4), "camera_width": 64, "camera_height": 48},
        target_shape="round",
        max_slice_points=10,
    )
    assert len(s.jars["shapes"]) == 4
    assert s.target_shape == "round"
    assert s.depth_image.shape == (48, 64)
    assert s.slice_points.shape[0] <= 10
    assert "finger_stiffness" in Scene.config_keys()


@pytest.mark.parametrize(
    ("kwargs", "error", "needle"),
    [
        ({"jar_count": (5, 3)}, ValueError, "jar_count"),
        ({"jar_count": 17}, ValueError, "jar_count"),
        ({"depth_noise_std": -0.1}, ValueError, "noise_std"),
        ({"depth_noise_std": "big"}, TypeError, "float"),
        ({"finger_stiffness": float("nan")}, ValueError, "finger_stiffness must be finite"),
        (
            {"finger_stiffness": 0.0},
            ValueError,
            r"finger_stiffness must be from 0.000001 to 1000000",
        ),
        ({"camera_max_range": -1.0}, ValueError, "camera_max_range must be > 0"),
        ({"target_shape": "triangle"}, ValueError, "'round'"),
        ({"target_shape": 3}, TypeError, "'round'"),
        ({"camera_position": (0.0, 1.0)}, TypeError, "camera_position must be a sequence of 3"),
        ({"camera_position": "abc"}, TypeError, "3 floats"),
        ({"camera_look_at": (0.0, -0.25, 0.075)}, ValueError, "look_at"),
        ({"rigid_finger": 1}, TypeError, "bool"),
        ({"substeps": 2.5}, TypeError, "int"),
        ({"substeps": -1}, ValueError, r"substeps must be an int from 1 to 1000, got -1"),
        ({"no_such_key": 1}, TypeError, "unexpected keyword argument 'no_such_key'"),
        ({"hand_start": (0.29, 0.1, 0.0)}, ValueError, "hand_start"),
        ({"camera_hfov": 4.0}, ValueError, "camera_hfov"),
    ],
)
def test_bad_config_raises_with_a_message_naming_it(
    kwargs: dict[str, object], error: type[Exception], needle: str
) -> None:
    with pytest.raises(error, match=needle):
        Scene(seed=0, **kwargs)


def test_bad_arguments_raise() -> None:
    with pytest.raises(TypeError):
        Scene(seed=0, config=[("jar_count", 3)])  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="both"):
        Scene(seed=0, config={"jar_count": 3}, jar_count=4)
    with pytest.raises(ValueError, match="seed"):
        Scene(seed=-1)
    with pytest.raises(TypeError, match="seed"):
        Scene(seed=1.5)  # type: ignore[arg-type]
    s = Scene(seed=0)
    with pytest.raises(ValueError, match="dx must be finite"):
        s.step(dx=float("nan"))
    with pytest.raises(TypeError):
        s.step(dx="left")  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="non-negative"):
        s.idle(-3)


@pytest.mark.parametrize("key", Scene.config_keys())
def test_every_config_key_is_wired_and_type_checked(key: str) -> None:
    # A known key given an object of the wrong kind is a TypeError naming the key (an unknown
    # key would be a ValueError).
    with pytest.raises(TypeError, match=key):
        Scene(seed=0, **{key: object()})


def test_scene_config_lists_every_key_and_round_trips():
    scene = Scene(0, config={"finger_length": 0.12, "jar_count": (3, 5)})
    config = scene.config
    assert sorted(config) == sorted(Scene.config_keys())
    assert config["finger_length"] == 0.12 and list(config["jar_count"]) == [3, 5]
    assert Scene(0, config=config).config == config
