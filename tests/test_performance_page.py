"""``docs/PERFORMANCE.md`` is rendered from the benchmarks' JSON (``benchmarks.performance_page``):
each figure appears beside the command that produced it, a benchmark without its file gets
the command that makes it and no number, and the page in the repository is what its
committed JSON renders."""

from __future__ import annotations

import json
from pathlib import Path

from benchmarks import performance_page
from benchmarks.performance_page import SECTIONS, render_page, write_json

REPO = Path(__file__).resolve().parent.parent


def peer_envs_document() -> dict:
    envs = {
        "CupboardSearch-v0 map=gpis probe": {
            "steps_per_s_median": 1111.4, "steps_per_s_min": 1000.0, "steps_per_s_max": 1200.0,
            "ratio_to_reference_median": 0.04354, "motions_per_s_median": 25000.0,
            "motions_ratio_to_reference_median": 0.98, "reset_us_median": 1234.5,
            "reset_in_reference_steps": 30.7, "step_us_median": 900.0,
        },
        "Pusher-v5": {
            "steps_per_s_median": 25530.0, "steps_per_s_min": 25000.0,
            "steps_per_s_max": 26000.0, "reset_us_median": 50.0, "step_us_median": 39.0,
        },
    }  # fmt: skip
    return {"meta": {}, "settings": {}, "envs": envs}


def test_figures_appear_beside_their_commands_and_stamps(tmp_path: Path) -> None:
    results = tmp_path / "results"
    write_json(
        results / "peer_envs.json", "benchmarks.peer_envs", ["--rounds", "2"], peer_envs_document()
    )
    overhead = {
        "steps": 100, "rounds": 2,
        "rows": [{"map": "gpis", "action_mode": "wrist", "num_envs": 16, "face_us": 345.6,
                  "core_us": 321.0, "cost_us": 24.6, "ratio": 1.0766, "batch_steps": 100}],
    }  # fmt: skip
    write_json(results / "vector_overhead.json", "benchmarks.vector_overhead", [], overhead)
    page = render_page(results)
    peer = page.split("## Beside MuJoCo's Pusher-v5")[1].split("\n## ")[0]
    assert "Command: `python -m benchmarks.peer_envs --rounds 2`" in peer
    assert "| `CupboardSearch-v0 map=gpis probe` | 1,111 (1,000-1,200) | 0.0435x |" in peer
    assert "30.7" in peer  # the reset in Pusher-v5 steps
    recorded = json.loads((results / "peer_envs.json").read_text())["recorded"]
    assert f"Recorded {recorded['date']}" in peer  # the date, the commit and the machine
    assert (
        recorded["machine"]["cpu"] in peer and f"{recorded['machine']['cpu_count']} cores" in peer
    )
    overhead_part = page.split("## The vector env's Python per batch step")[1].split("\n## ")[0]
    assert "Command: `python -m benchmarks.vector_overhead`" in overhead_part
    assert "| gpis | wrist | 16 | 345.6 | 321.0 | +24.6 (1.077x) |" in overhead_part


def test_a_missing_file_is_reported_with_the_command_that_writes_it(tmp_path: Path) -> None:
    results = tmp_path / "nothing"
    page = render_page(results)
    for section in (*SECTIONS, performance_page.CRITERION):
        part = page.split(f"## {section.title}\n")[1].split("\n## ")[0]
        path = (results / section.file).as_posix()
        assert "_Not measured for this page: `" in part
        assert f"writes `{path}`" in part
        assert "Command:" not in part
    throughput = page.split("## The vector env on every core over one thread")[1]
    assert f"--json {(results / 'env_throughput.json').as_posix()}`" in throughput


def test_non_finite_figures_are_written_as_null_and_shown_as_a_dash(tmp_path: Path) -> None:
    row = {"processes": 2, "threads_1": 500.0, "threads_2": float("nan"), "ratio": float("inf")}
    figures = {"medians": [row], "rounds": 1, "seconds": 1.0, "cores": 2}
    path = tmp_path / "env_threads_side_by_side.json"
    write_json(path, "benchmarks.env_threads_side_by_side", [], figures)
    document = json.loads(path.read_text())  # strict JSON: no NaN
    assert document["medians"][0]["threads_2"] is None
    page = render_page(tmp_path)
    assert "| 2 | 500.0 | - | - |" in page


def test_criterion_estimates_are_collected_with_their_bench(tmp_path: Path) -> None:
    benches = tmp_path / "benches"
    benches.mkdir()
    (benches / "scene.rs").write_text('c.bench_function("scene_step_free_motion", |b| {});')
    new = tmp_path / "criterion" / "scene_step_free_motion" / "new"
    new.mkdir(parents=True)
    interval = {"lower_bound": 28_000.0, "upper_bound": 30_500.0}
    estimate = {"point_estimate": 29_000.0, "confidence_interval": interval}
    (new / "estimates.json").write_text(json.dumps({"mean": estimate, "median": estimate}))
    (new / "benchmark.json").write_text(
        json.dumps({"group_id": "scene_step_free_motion", "full_id": "scene_step_free_motion"})
    )
    (found,) = performance_page.criterion_estimates(tmp_path / "criterion", benches)
    assert found["bench"] == "scene" and found["median_ns"] == 29_000.0
    results = tmp_path / "results"
    write_json(results / "criterion.json", "x", [], {"benchmarks": [found]}, command="cargo bench")
    page = render_page(results)
    assert (
        "| `scene_step_free_motion` | `cargo bench -p env_core --bench scene` | 29 µs | "
        "29 µs [28 µs, 30.5 µs] |" in page
    )


def test_the_committed_page_is_what_its_committed_json_renders(monkeypatch) -> None:
    """``docs/PERFORMANCE.md`` comes from ``docs/performance/`` (``make performance
    PERFORMANCE_RESULTS=docs/performance``), not from a hand edit."""
    monkeypatch.chdir(REPO)
    expected = render_page(Path("docs/performance"), Path("docs/PERFORMANCE.md"))
    assert (REPO / "docs/PERFORMANCE.md").read_text(encoding="utf-8") == expected, (
        "docs/PERFORMANCE.md is stale: python -m benchmarks.performance_page "
        "--results docs/performance --out docs/PERFORMANCE.md"
    )


def test_a_loaded_machine_is_said_beside_its_figures(tmp_path: Path) -> None:
    document = peer_envs_document()
    machine = {"cpu": "X", "cpu_count": 2, "usable_cpus": 2, "load_average": 9.5}
    document["recorded"] = {"command": "python -m benchmarks.peer_envs", "date": "d",
                            "commit": "abc", "machine": machine}  # fmt: skip
    (tmp_path / "peer_envs.json").write_text(json.dumps(document))
    assert "**Other work shared the machine** (load average 9.5 on 2 cores)" in render_page(
        tmp_path
    )
    machine["load_average"] = 1.5
    (tmp_path / "peer_envs.json").write_text(json.dumps(document))
    assert "Other work shared the machine" not in render_page(tmp_path)
