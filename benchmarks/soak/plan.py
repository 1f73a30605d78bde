"""What a soak runs and what it must hold to: its scales (``FULL``, ``QUICK``), the
configurations stepped through the run, the core's settings they read (names and bounds come
from the settings table, so nothing the core owns is typed here) and the limits of the
memory and step-time checks."""

from __future__ import annotations

import dataclasses
import math
from typing import Any

from tactile_search import ENV_ID, ENV_IDS
from tactile_search.envs.config import MAP_MODES, SETTINGS

#: The warm-up: this fraction of the rounds (rounded up, at least one), chosen before any
#: run from what has to settle (see ``benchmarks.soak.analysis``), not from what passes.
WARM_UP_FRACTION = 0.3

ACTION_KINDS = ("random", "forward", "out_of_range", "invalid", "oracle")
#: The action kinds each other registered id's single env is stepped with: random actions
#: (the identify task's claim entry among them, so claims come often) and the oracle's.
TASK_KINDS = ("random", "oracle")

# ---- the limits the checks hold a run to (``benchmarks.soak.analysis``) -------------------
#: Largest growth after the warm-up of the live heap (the leak check) and of the resident
#: memory after ``malloc_trim`` ("within 2 % of the warm-up's"), as a fraction of the last
#: warm-up round's peak.
LIVE_GROWTH_LIMIT = 0.02
RSS_GROWTH_LIMIT = 0.02
#: Largest ratio of late to early median step time through the run (after the control).
RUN_DRIFT_LIMIT = 1.5
#: Action kinds whose episodes are free motion (the finger seldom touches a jar): only their
#: step time is expected to be flat by step index within an episode.
FREE_MOTION_KINDS = ("random", "out_of_range", "invalid")
#: Largest ratio of the last to the first step-index bin's median step time (free motion).
INDEX_DRIFT_LIMIT = 1.5
#: Width of a step-index bin, steps; fewest steps a bin (of either check) needs to count.
INDEX_BIN = 25
MIN_BIN_STEPS = 100


@dataclasses.dataclass(frozen=True)
class Scale:
    """How much a soak runs: ``rounds`` (the first ``warm_rounds`` are the warm-up), per
    round ``episodes`` per single-env configuration and ``batch_steps`` per vector-env
    configuration."""

    name: str
    rounds: int
    episodes: int
    batch_steps: int
    vector_sizes: tuple[int, ...] = (1, 4, 16)
    capacity_rows: tuple[int, ...] = (12, 30)  # the max_rows setting's lower bound is added
    gpis_capacities: tuple[int, ...] = (1, 7, 64, 300)
    #: Every round replays round 1's seeds (like-for-like timings from few episodes) instead
    #: of new ones; either way the first episode of each single-env configuration in every
    #: round replays its first seed, and must give the same rollout.
    replay: bool = False
    #: Checks this scale measures and prints but does not assert (too short to mean much).
    informational: tuple[str, ...] = ()

    @property
    def warm_rounds(self) -> int:
        """How many rounds the warm-up is: ``WARM_UP_FRACTION`` of them, at least one."""
        return min(self.rounds - 1, max(1, math.ceil(WARM_UP_FRACTION * self.rounds - 1e-9)))


FULL = Scale("full", rounds=10, episodes=50, batch_steps=100)
QUICK = Scale(
    "quick", rounds=3, episodes=3, batch_steps=20, replay=True,
    informational=(
        "resident memory flat", "step time flat through the run", "step time flat by step index"
    ),
)  # fmt: skip


@dataclasses.dataclass
class Config:
    """One configuration whose step times are compared through the run."""

    name: str
    mode: str
    kind: str
    num_envs: int | None = None  # None: the single env
    copy: bool = True
    settings: dict[str, Any] = dataclasses.field(default_factory=dict)
    env: Any = None
    #: The registered id (the task and tier) the configuration's env is made from.
    env_id: str = ENV_ID


def setting(key: str) -> dict[str, Any]:
    """The core's settings-table entry for ``key``."""
    found = [s for s in SETTINGS if s["key"] == key]
    if not found:
        raise KeyError(f"the core's settings table has no {key!r}")
    return found[0]


def range_lower_bound(entry: dict[str, Any]) -> int:
    """The smallest int a setting's range (e.g. ``"[1, inf)"``) allows."""
    text = entry["range"].strip()
    lower = float(text[1:].split(",")[0])
    return int(lower) if text[0] == "[" else math.floor(lower) + 1


def capacity_rows(scale: Scale) -> tuple[int, ...]:
    """The ``max_rows`` values of the capacity episodes: the scale's and the setting's lower
    bound."""
    return tuple(sorted({range_lower_bound(setting("max_rows")), *scale.capacity_rows}))


def configurations(scale: Scale, rows: tuple[int, ...]) -> list[Config]:
    """Every configuration of a round, in the order a round runs them: the single envs (each
    map mode and action kind), each other registered id's single env (the tasks and tiers:
    claims, dense layouts, the map task's score; ``TASK_KINDS``), the capacity episodes
    (``max_rows`` in ``rows``), then the vector envs (each map mode, size and action kind;
    the size-4 one with ``copy=False``)."""
    configs = [
        Config(f"single {mode} {kind}", mode, kind) for mode in MAP_MODES for kind in ACTION_KINDS
    ]
    configs += [
        Config(f"single {env_id.rpartition('/')[2]} {kind}", "gpis", kind, env_id=env_id)
        for env_id in ENV_IDS
        if env_id != ENV_ID
        for kind in TASK_KINDS
    ]
    configs += [
        Config(f"single gpis max_rows={r} forward", "gpis", "forward", settings={"max_rows": r})
        for r in rows
    ]
    for mode in MAP_MODES:
        for size in scale.vector_sizes:
            copy = size != 4
            for kind in ACTION_KINDS:
                label = f"vector {mode} x{size}{'' if copy else ' copy=False'} {kind}"
                configs.append(Config(label, mode, kind, num_envs=size, copy=copy))
    return configs


def power_range(bounds: tuple[int, int]) -> str:
    """``[low, high)`` as text, powers of two written as such (``[2**32, 2**63)``)."""

    def text(value: int) -> str:
        exponent = value.bit_length() - 1
        return f"2**{exponent}" if value > 1 and value == 1 << exponent else f"{value:,}"

    return f"[{text(bounds[0])}, {text(bounds[1])})"
