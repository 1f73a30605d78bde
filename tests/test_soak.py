"""The quick soak (``python -m benchmarks.soak --quick``, about 30 s): every asserted check
passes.

At the quick scale the live-heap leak check and every correctness check are asserted; resident
memory after ``malloc_trim`` and step time through the run and by step index are measured
and printed but only asserted by the full run (30 s is too short for the allocator's heap to
settle or for a few replayed episodes to say anything about step time; see the module
docstrings of ``benchmarks.soak`` and ``benchmarks.soak.analysis``).
"""

from __future__ import annotations

from benchmarks.soak import LIVE_HEAP_NOTE, QUICK, run_soak


def test_quick_soak_passes_every_check() -> None:
    result = run_soak(QUICK, log=lambda line: None)
    print(result.text)
    failed = {name: detail for name, (ok, detail) in result.checks.items() if not ok}
    assert not failed, f"soak checks failed: {failed}\n{result.text}"
    figures = result.figures
    assert figures["steps"] > 10_000 and figures["other_exceptions"] == {}
    assert sum(figures["documented_exceptions"].values()) > 0
    assert figures["capacity_reached"] > 0
    assert set(figures["informational"]) == set(QUICK.informational)
    if LIVE_HEAP_NOTE is None:  # glibc: the leak check ran
        assert "no leak: live heap flat" in result.checks
