"""The quick soak (``python -m benchmarks.soak --quick``, about 30 s): every asserted check
passes.

At the quick scale the live-heap leak check and every correctness check are asserted; resident
memory after ``malloc_trim`` and step time through the run and by step index are measured
and printed but only asserted by the full run (30 s is too short for the allocator's heap to
settle or for a few replayed episodes to say anything about step time; see the module
docstrings of ``benchmarks.soak`` and ``benchmarks.soak.analysis``).
"""

from __future__ import annotations

import gc
import multiprocessing
from concurrent.futures import ProcessPoolExecutor
from types import SimpleNamespace

import pytest

from benchmarks.soak import LIVE_HEAP_NOTE, QUICK, run_soak
from benchmarks.soak.memory import live_heap_bytes
from tactile_search import CupboardSearchVectorEnv, _core


def quick_soak() -> SimpleNamespace:
    """The quick soak's checks, figures and text (what crosses back from its process)."""
    result = run_soak(QUICK, log=lambda line: None)
    return SimpleNamespace(checks=result.checks, figures=result.figures, text=result.text)


def test_quick_soak_passes_every_check() -> None:
    # In a fresh process: the live heap is the whole process's (mallinfo2 and the core's
    # count), so in the test worker it would also count what earlier tests left to settle.
    spawn = multiprocessing.get_context("spawn")
    with ProcessPoolExecutor(max_workers=1, mp_context=spawn) as pool:
        result = pool.submit(quick_soak).result()
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


@pytest.mark.skipif(LIVE_HEAP_NOTE is not None, reason=str(LIVE_HEAP_NOTE))
def test_the_live_heap_counts_the_cores_blocks_and_sees_them_returned() -> None:
    """The core's allocator (``env_core::allocator``) takes its blocks from mimalloc, where
    glibc's ``mallinfo2`` sees none of them: the soak's live heap adds
    ``_core.allocated_bytes()``, the core's own count. GPIS episodes hold big blocks (the
    grid cache is 8 bytes per cell and row) and small ones (their scenes), so building a
    batch raises the count by them, and dropping it lowers it again."""
    gc.collect()
    live_before, held_before = live_heap_bytes(), _core.allocated_bytes()
    env = CupboardSearchVectorEnv(num_envs=4, max_steps=30)
    env.reset(seed=3)
    for _ in range(30):
        env.step(env.oracle_actions())
    held = _core.allocated_bytes() - held_before
    assert held >= 4 * 2**20, f"4 GPIS episodes hold only {held} bytes"
    assert live_heap_bytes() - live_before >= held
    env.close()
    del env
    gc.collect()
    assert _core.allocated_bytes() - held_before < held / 4
