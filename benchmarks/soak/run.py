"""``run_soak``: a soak of a given scale, from its plan to its checked result."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from benchmarks.soak.analysis import analyse
from benchmarks.soak.plan import QUICK, Scale
from benchmarks.soak.report import SoakResult
from benchmarks.soak.workloads import Soak
from tactile_search.seed_ranges import TRAINING


def run_soak(
    scale: Scale = QUICK, seed_base: int = TRAINING[0], log: Callable[[str], Any] = print
) -> SoakResult:
    """Runs a soak of ``scale`` (``QUICK`` or ``FULL``) and returns its checks and figures."""
    soak = Soak(scale, seed_base=seed_base, log=log)
    log(
        f"soak ({scale.name}): {scale.rounds} rounds of {len(soak.configs)} configurations, "
        f"{scale.episodes} episodes per single-env one and {scale.batch_steps} batch steps "
        "per vector-env one"
    )
    soak.run()
    return analyse(soak)
