"""``experiments.paper`` and the core functions it measures with: the metrics measure what
they claim, bad arguments are refused with a clear error, the environment and the experiments
get the identical prior rows, and the tiny run of the script writes every figure and the
table."""

import csv
import math

import gymnasium as gym
import numpy as np
import pytest

from experiments.maps import env_settings, start_map
from experiments.paper import cli, episodes, scripted_touch
from experiments.paper.priors import PRIOR_OPTIONS
from tactile_search import ENV_ID, _core
from tactile_search.seed_ranges import VALIDATION

BOUNDS = ((-0.3, 0.3), (0.0, 0.3))


def grid(cell: float = 0.002) -> tuple[np.ndarray, tuple[int, int]]:
    """(H, W, 2) cell centres over x in [-0.3, 0.3], y in [0, 0.3], and (H, W)."""
    xs = np.arange(-0.3 + cell / 2, 0.3, cell)
    ys = np.arange(cell / 2, 0.3, cell)
    centres = np.stack(np.meshgrid(xs, ys), axis=-1)
    return centres, centres.shape[:2]


def jars(*entries: tuple[str, tuple[float, float], float, float]) -> dict:
    """A jars dict from (shape, centre, half width, yaw) entries."""
    return {
        "shapes": [e[0] for e in entries],
        "positions": np.array([e[1] for e in entries], dtype=float).reshape(-1, 2),
        "half_widths": np.array([e[2] for e in entries]),
        "yaws": np.array([e[3] for e in entries]),
    }


def disc_field(centres: np.ndarray, centre: tuple[float, float], radius: float) -> np.ndarray:
    return np.linalg.norm(centres - np.array(centre), axis=-1) - radius


def test_iou_of_a_known_disc() -> None:
    centres, shape = grid()
    truth = _core.footprint_mask(jars(("round", (0.0, 0.15), 0.025, 0.0)), BOUNDS, shape)
    iou = _core.interior_iou
    assert iou(disc_field(centres, (0.0, 0.15), 0.025), truth) == pytest.approx(1.0)
    # A disc of half the area inside the true one: IoU 0.5.
    half = 0.025 / math.sqrt(2.0)
    assert iou(disc_field(centres, (0.0, 0.15), half), truth) == pytest.approx(0.5, abs=0.02)
    # Shifted by one radius: the lens of two equal discs at distance r, area fraction known.
    r = 0.025
    lens = 2 * r**2 * math.acos(0.5) - 0.5 * r * math.sqrt(3 * r**2)
    expected = lens / (2 * math.pi * r**2 - lens)
    assert iou(disc_field(centres, (r, 0.15), r), truth) == pytest.approx(expected, abs=0.02)
    # Nothing inside: IoU 0.
    assert iou(np.ones(truth.shape), truth) == 0.0


def test_outline_distance_of_a_known_circle() -> None:
    centres, _ = grid()
    jar = jars(("round", (0.05, 0.12), 0.025, 0.0))

    def distance(field: np.ndarray) -> float:
        return _core.outline_distance(field, BOUNDS, jar, 64, episodes.MISS_DISTANCE)

    assert distance(disc_field(centres, (0.05, 0.12), 0.025)) < 3e-4
    # The estimated outline is a concentric circle 6 mm larger: every sample is 6 mm off.
    assert distance(disc_field(centres, (0.05, 0.12), 0.031)) == pytest.approx(0.006, abs=3e-4)
    # Shifted by 10 mm along x: for a shift d < r the nearest point of the shifted circle is
    # at mean distance (2/pi) * d to first order.
    shifted = distance(disc_field(centres, (0.06, 0.12), 0.025))
    assert shifted == pytest.approx(2 / math.pi * 0.01, rel=0.1)
    # No zero crossing at all scores the cap, in both directions.
    flat = np.ones(centres.shape[:2])
    assert distance(flat) == episodes.MISS_DISTANCE
    assert _core.spurious_distance(flat, BOUNDS, jar) == pytest.approx(0.05)


def test_square_footprint_and_support() -> None:
    square = jars(("square", (0.0, 0.1), 0.02, math.pi / 4))
    support = _core.jar_support(square, np.array([1.0, 0.0]))
    assert support[0] == pytest.approx(0.02 * math.sqrt(2.0))
    _, shape = grid(0.001)
    area = _core.footprint_mask(square, BOUNDS, shape).sum() * 1e-6
    assert area == pytest.approx(0.04**2, rel=0.03)
    outline = _core.jar_outlines(square, 40)
    assert outline.shape == (1, 40, 2)
    assert np.abs(_core.jar_signed_distance(square, outline[0])).max() < 1e-12


@pytest.mark.parametrize(
    ("call", "error", "words"),
    [
        (lambda: _core.jar_outlines({"shapes": ["oval"]}, 8), ValueError, "positions"),
        (
            lambda: _core.jar_outlines(jars(("oval", (0, 0.1), 0.02, 0.0)), 8),
            ValueError,
            "round",
        ),
        (lambda: _core.jar_outlines([1, 2], 8), TypeError, "dict"),
        (lambda: _core.jar_outlines(jars(("round", (0, 0.1), 0.02, 0.0)), -1), ValueError, "int"),
        (
            lambda: _core.jar_signed_distance(jars(("round", (0, 0.1), 0.02, 0.0)), np.ones(3)),
            TypeError,
            "(N, 2)",
        ),
        (
            lambda: _core.jar_signed_distance(
                jars(("round", (0, 0.1), 0.02, 0.0)), np.array([[np.nan, 0.0]])
            ),
            ValueError,
            "finite",
        ),
        (
            lambda: _core.jar_outlines(jars(("round", (0, 0.1), -0.02, 0.0)), 8),
            ValueError,
            "> 0",
        ),
        (lambda: _core.footprint_mask(jars(), BOUNDS, (0, 4)), ValueError, "positive"),
        (lambda: _core.footprint_mask(jars(), "bounds", (4, 4)), TypeError, "bounds"),
        (
            lambda: _core.interior_iou(np.zeros((2, 2)), np.zeros((2, 3), bool)),
            ValueError,
            "(2, 2)",
        ),
        (lambda: _core.interior_iou(np.zeros((2, 2)), np.zeros((2, 2))), TypeError, "bool"),
        (
            lambda: _core.outline_distance(np.zeros((2, 2)), BOUNDS, jars(), cap=0),
            ValueError,
            "cap",
        ),
        (lambda: _core.hand_geometry(finger_length="long"), TypeError, "finger_length"),
        (
            lambda: _core.depth_prior(np.zeros((3, 2)), [0, -0.2, 1], BOUNDS, (4, 8)),
            ValueError,
            "2",
        ),
        (
            lambda: _core.depth_prior(np.zeros((3, 2)), [0, -0.2], BOUNDS, (4, 8), psi=1.0),
            TypeError,
            "unexpected keyword argument 'psi'",
        ),
        (
            lambda: _core.depth_prior(
                np.zeros((3, 2)), [0, -0.2], BOUNDS, (4, 8), map_depth_noise_std=-1.0
            ),
            ValueError,
            "depth_noise_std",
        ),
        (
            lambda: _core.depth_prior(
                np.zeros((3, 2)), [0, -0.2], BOUNDS, (4, 8), prior_wall_clearance=-1.0
            ),
            ValueError,
            "prior_wall_clearance",
        ),
        (
            lambda: _core.depth_prior(np.zeros((3, 2)), [np.inf, -0.2], BOUNDS, (4, 8)),
            ValueError,
            "finite",
        ),
    ],
)
def test_bad_arguments_to_the_core_functions_raise_clear_errors(call, error, words) -> None:
    with pytest.raises(error, match=None) as raised:
        call()
    assert words in str(raised.value)


def test_metrics_of_an_empty_scene_are_numbers_not_nan() -> None:
    nothing = jars()
    mean = np.ones((4, 8))
    assert _core.outline_distance(mean, BOUNDS, nothing) == pytest.approx(0.05)
    assert _core.interior_iou(mean, _core.footprint_mask(nothing, BOUNDS, (4, 8))) == 1.0
    assert _core.zero_level_segments(mean, BOUNDS).shape == (0, 2, 2)


def test_hand_geometry_derives_the_joint_offset_from_the_scene() -> None:
    base = _core.hand_geometry()
    wider = _core.hand_geometry(wrist_half_extent=base["wrist_half_extent"] + 0.005)
    assert wider["joint_offset"] - base["joint_offset"] == pytest.approx(0.005)
    assert base["reach"] == pytest.approx(base["joint_offset"] + base["finger_length"])


@pytest.mark.parametrize("seed", [VALIDATION[0], VALIDATION[0] + 3])
@pytest.mark.parametrize(
    "overrides",
    [{}, {"circle_prior_diameter": 0.03, "free_space_offset": None, "prior_mean": 0.02}],
)
def test_the_environment_and_the_experiments_start_from_the_same_prior(seed, overrides) -> None:
    """One code path: the env's map after reset equals, bit for bit, a map started by the
    experiments from the same scene's slice with ``_core.depth_prior``."""
    env = gym.make(ENV_ID, **overrides)
    env.reset(seed=seed)
    state = env.unwrapped.render_state()
    scene_config = env.unwrapped.config.scene_dict()
    env.close()
    scene = _core.Scene(seed, config=scene_config)
    bounds = tuple(map(tuple, state["bounds"]))
    shape = state["map"]["mean"].shape
    gpis = start_map(scene.slice_points, scene.camera["position"][:2], bounds, shape, overrides)
    assert gpis.n_rows > 0
    np.testing.assert_array_equal(gpis.mean, state["map"]["mean"])
    np.testing.assert_array_equal(np.sqrt(gpis.variance), state["map"]["std"])


def test_depth_prior_rows_follow_the_settings() -> None:
    camera = np.array([0.0, -0.25])
    face = np.column_stack([np.linspace(-0.02, 0.02, 11), np.full(11, 0.1)])
    plain = _core.depth_prior(face, camera, BOUNDS, (40, 80), free_space_offset=None)
    assert len(plain) == 11 and plain.n_rows == 11 and not plain.is_contact.any()
    free = _core.depth_prior(face, camera, BOUNDS, (40, 80))
    assert len(free) == 22 and np.allclose(free.values[11:], env_settings()["free_space_offset"])
    circle = _core.depth_prior(
        face, camera, BOUNDS, (40, 80), free_space_offset=None, circle_prior_diameter=0.03
    )
    assert circle.is_contact.sum() == 4 and circle.n_rows == 11 + 12
    thinned = _core.depth_prior(face, camera, BOUNDS, (40, 80), max_prior_depth_points=5)
    assert (~thinned.is_contact).sum() == 10


def test_scripted_touch_keeps_the_hand_clear_of_a_jar() -> None:
    scene = _core.Scene(VALIDATION[0])
    hand = scripted_touch.Hand.of(scene)
    one = jars(("round", (0.0, 0.15), 0.025, 0.0))
    assert not scripted_touch.hand_clear((0.0, 0.15, 0.0), one, -1, hand)
    assert scripted_touch.hand_clear((0.2, 0.0, 0.0), one, -1, hand)


def test_tiny_run_writes_every_figure_and_the_table(tmp_path) -> None:
    md = tmp_path / "PAPER.md"
    md.write_text(f"before\n{cli.TABLE_START}\nold\n{cli.TABLE_END}\nafter\n")
    out = tmp_path / "paper"
    cli.main(["--out", str(out), "--tiny"])
    for name in (
        "fig3_depth.png",
        "fig4_measurements.png",
        "fig5_prior.png",
        "fig6_round.png",
        "fig7_square.png",
        "fig8_priors.png",
        "fig9_timing.png",
    ):
        assert (out / name).stat().st_size > 10_000, name
    with (out / "table.csv").open() as f:
        rows = list(csv.DictReader(f))
    settings = cli.Settings.tiny()
    assert len(rows) == len(settings.noise_levels) * 2 * len(PRIOR_OPTIONS) * 2
    assert {r["shape"] for r in rows} == {"round", "square"}
    assert all(0.0 <= float(r["iou_mean"]) <= 1.0 for r in rows)
    with (out / "table_seeds.csv").open() as f:
        per_seed = list(csv.DictReader(f))
    # Validation seeds, and real touch: the scripted finger touched jars in every episode.
    assert {int(r["seed"]) for r in per_seed} == {
        VALIDATION[0],
        VALIDATION[0] + 1,
    }
    assert all(int(r["contacts"]) > 0 for r in per_seed)
    text = md.read_text()
    assert "old" not in text and "Chosen default prior" in text and text.endswith("after\n")
