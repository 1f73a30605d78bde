"""Soak test of every registered id: many steps, hostile actions, full GPIS maps; no leaks.

What it runs, in rounds (the first 30 % are the warm-up; every round does the same mix):
single envs per map mode (the list comes from the package,
``tactile_search.envs.config.MAP_MODES``) and action kind, reset with a new layout seed from
the training range (``tactile_search.seed_ranges.TRAINING``, ``docs/DESIGN.md`` §7) for
every episode; the single env of every other registered id (the identify task's claims, the
dense layouts, the map task's score) with random and oracle actions; GPIS maps filled to
capacity in episodes; vector envs per map mode and size
(1, 4 and 16 episodes; the size-4 one with ``copy=False``); twin envs that must replay the
clipped actions bit for bit; standalone ``Gpis`` maps filled to ``max_rows``; and envs built,
stepped and closed each round. It asserts that every output is finite and only documented
errors are raised, that memory stays flat (the live heap, the leak check, and RSS after
``malloc_trim``) and that step time stays flat through the run and by step index within an
episode, the machine's load divided out by two reference workloads.

The modules, one concept each:

- ``plan``: the scales (``FULL``, ``QUICK``), the configurations and the checks' limits;
- ``actions``: the action kinds, hostile ones included;
- ``memory``: RSS, ``malloc_trim`` and the live heap (``mallinfo2``);
- ``reference``: the reference workloads and the load normalisation;
- ``records``: what the run records (preallocated) and the per-step checks;
- ``workloads``: ``Soak``, the rounds that drive the envs;
- ``analysis``: ``analyse``, the checks and figures step by step (what each asserts);
- ``report``: ``SoakResult``, the PASS / FAIL lines and the plot;
- ``run``: ``run_soak``; ``__main__``: the command line.

The quick version (``--quick``, ``tests/test_soak.py``, about 30 s on this 2-core machine)
runs 3 rounds of 3 episodes per single-env configuration, each round replaying the same
layout seeds. It asserts the leak check (the same episodes every round: the live heap must
come back to the same size) and every correctness check. It measures and prints, but does
not assert, the other three: in 30 s the allocator's heap has not settled (RSS after the
trim still grows a few per cent), two rounds of a few episodes say little about a drift
through the run, and with 3 layouts the step-index bins of the few free-motion episodes
mostly say where those random walks went (step cost depends on the finger's place, not only
on contacts). The full run asserts all of them.

It prints the figures and, if matplotlib is installed, writes a plot of the live heap, RSS
after the trim and step time over the run (``--out``, default ``results/soak.png``);
``--json`` writes the figures.

Usage::

    python -m benchmarks.soak            # the full soak: >= 10**6 steps, >= 10**4 seeds
    python -m benchmarks.soak --quick    # about 30 s (what tests/test_soak.py runs)
    python -m benchmarks.soak --rounds 4 --json results/soak.json

From Python: ``from benchmarks.soak import run_soak, FULL, QUICK``;
``result = run_soak(QUICK)``; ``result.passed``, ``result.checks``, ``result.figures``.
"""

from benchmarks.soak.analysis import analyse
from benchmarks.soak.memory import LIVE_HEAP_NOTE
from benchmarks.soak.plan import FULL, QUICK, Scale
from benchmarks.soak.report import SoakResult, plot
from benchmarks.soak.run import run_soak
from benchmarks.soak.workloads import Soak

__all__ = [
    "FULL",
    "LIVE_HEAP_NOTE",
    "QUICK",
    "Scale",
    "Soak",
    "SoakResult",
    "analyse",
    "plot",
    "run_soak",
]
