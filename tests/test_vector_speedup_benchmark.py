"""``benchmarks.env_throughput.vector_speedup`` (what ``make bench`` prints for the vector
env's speed-up) runs through episodes that reset and gives its figures for both thread
counts."""

from __future__ import annotations

import math

from benchmarks.env_throughput import vector_speedup


def test_the_speedup_benchmark_runs_through_resets_on_both_thread_counts() -> None:
    # Episodes of 3 steps over 12 batch steps: every round holds resets of every sub-env.
    figures = vector_speedup("none", 2, 12, rounds=3, action_mode="wrist", max_steps=3)
    assert set(figures) == {1, None}
    for threads in figures.values():
        assert threads["rate"] > 0 and math.isfinite(threads["rate"])
        assert threads["parallel_ms"] > 0 and threads["serial_ms"] >= 0
