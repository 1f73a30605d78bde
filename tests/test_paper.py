"""``tactile_search.paper``: the metric helpers measure what they claim, and the tiny run of
the script writes every figure and the table."""

import csv
import math

import numpy as np
import pytest

from tactile_search import paper
from tactile_search.demo import Jar


def grid(cell: float = 0.002) -> np.ndarray:
    """(H, W, 2) cell centres over x in [-0.3, 0.3], y in [0, 0.3]."""
    xs = np.arange(-0.3 + cell / 2, 0.3, cell)
    ys = np.arange(cell / 2, 0.3, cell)
    return np.stack(np.meshgrid(xs, ys), axis=-1)


def disc_field(centres: np.ndarray, centre: tuple[float, float], radius: float) -> np.ndarray:
    return np.linalg.norm(centres - np.array(centre), axis=-1) - radius


def test_iou_of_a_known_disc() -> None:
    centres = grid()
    truth = paper.footprint_mask(centres, [Jar((0.0, 0.15), 0.05)])
    assert paper.interior_iou(disc_field(centres, (0.0, 0.15), 0.025), truth) == pytest.approx(1.0)
    # A disc of half the area inside the true one: IoU 0.5.
    half = 0.025 / math.sqrt(2.0)
    assert paper.interior_iou(disc_field(centres, (0.0, 0.15), half), truth) == pytest.approx(
        0.5, abs=0.02
    )
    # Shifted by one radius: the lens of two equal discs at distance r, area fraction known.
    r = 0.025
    lens = 2 * r**2 * math.acos(0.5) - 0.5 * r * math.sqrt(3 * r**2)
    expected = lens / (2 * math.pi * r**2 - lens)
    shifted = disc_field(centres, (r, 0.15), r)
    assert paper.interior_iou(shifted, truth) == pytest.approx(expected, abs=0.02)
    # Nothing inside: IoU 0.
    assert paper.interior_iou(np.ones(truth.shape), truth) == 0.0


def test_outline_distance_of_a_known_circle() -> None:
    centres = grid()
    jar = Jar((0.05, 0.12), 0.05)
    exact = paper.outline_distance(disc_field(centres, (0.05, 0.12), 0.025), centres, [jar])
    assert exact < 3e-4
    # The estimated outline is a concentric circle 6 mm larger: every sample is 6 mm off.
    bigger = paper.outline_distance(disc_field(centres, (0.05, 0.12), 0.031), centres, [jar])
    assert bigger == pytest.approx(0.006, abs=3e-4)
    # Shifted by 10 mm along x: distance |10 cos t| mm averaged over t... the nearest point of
    # the shifted circle, for a shift d < r, is at mean distance (2/pi) * d to first order.
    shifted = paper.outline_distance(disc_field(centres, (0.06, 0.12), 0.025), centres, [jar])
    assert shifted == pytest.approx(2 / math.pi * 0.01, rel=0.1)
    # No zero crossing at all scores the cap.
    assert paper.outline_distance(np.ones(centres.shape[:2]), centres, [jar]) == (
        paper.MISS_DISTANCE
    )


def test_square_footprint_and_support() -> None:
    jar = Jar((0.0, 0.1), 0.04, square=True, yaw=math.pi / 4)
    assert paper.support(jar, np.array([1.0, 0.0])) == pytest.approx(0.02 * math.sqrt(2.0))
    centres = grid(0.001)
    area = paper.footprint_mask(centres, [jar]).sum() * 1e-6
    assert area == pytest.approx(0.04**2, rel=0.03)


def test_clusters_and_circle_centres() -> None:
    a = np.column_stack([np.linspace(-0.1, -0.08, 10), np.full(10, 0.1)])
    b = np.column_stack([np.linspace(0.05, 0.07, 10), np.full(10, 0.15)])
    clusters = paper.cluster_points(np.vstack([a, b]))
    assert sorted(len(c) for c in clusters) == [10, 10]
    camera = np.array([0.0, -0.25])
    bounds = ((-0.3, 0.3), (0.0, 0.3))
    centres = paper.circle_centres(np.vstack([a, b]), camera, 0.03, bounds)
    for centre in centres:
        # Pushed 15 mm away from the camera from its cluster's centroid.
        centroid = min((a.mean(0), b.mean(0)), key=lambda c: np.linalg.norm(c - centre))
        assert np.linalg.norm(centre - centroid) == pytest.approx(0.015)
        assert np.linalg.norm(centre - camera) > np.linalg.norm(centroid - camera)
    # A 0.2 m circle is clamped so that it fits in the map.
    big = paper.circle_centres(a, camera, 0.2, bounds)
    assert 0.1 <= big[0, 1] <= 0.2


def test_tiny_run_writes_every_figure_and_the_table(tmp_path) -> None:
    md = tmp_path / "PAPER.md"
    md.write_text(f"before\n{paper.TABLE_START}\nold\n{paper.TABLE_END}\nafter\n")
    out = tmp_path / "paper"
    paper.main(["--out", str(out), "--tiny"])
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
    settings = paper.Settings.tiny()
    assert len(rows) == len(settings.noise_levels) * 2 * len(paper.PRIOR_OPTIONS) * 2
    assert {r["shape"] for r in rows} == {"round", "square"}
    assert all(0.0 <= float(r["iou_mean"]) <= 1.0 for r in rows)
    with (out / "table_seeds.csv").open() as f:
        per_seed = list(csv.DictReader(f))
    # Real touch: the scripted finger touched jars in every episode.
    assert all(int(r["contacts"]) > 0 for r in per_seed)
    text = md.read_text()
    assert "old" not in text and "Chosen default prior" in text and text.endswith("after\n")
