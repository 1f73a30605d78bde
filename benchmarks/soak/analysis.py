"""The checks and figures of a finished soak, one named step per kind of check.

It asserts (each check prints PASS or FAIL, and the exit status is 1 if any fails):

- no NaN or inf anywhere: every observation array, reward and info value is walked;
- proprioception within [-1, 1]; ``info["steps"]`` counts up by one per accepted step (so a
  refused action changed nothing) and restarts at 0 on (auto)reset; ``truncated`` exactly at
  ``max_steps``; ``info["clipped"]`` exactly when a component is outside [-1, 1];
- no exception other than the documented ones (counted by kind; an invalid action that is
  accepted is a failure too);
- memory flat, two ways, both sampled (after ``malloc_trim(0)``) after every episode,
  segment, fill and round, and printed per round (the peak of the round's samples and the
  value at its end):

  - no leak: the live heap, glibc's ``mallinfo2()`` through ctypes (in-use chunks
    ``uordblks`` plus mmapped blocks ``hblkhd``, over every arena): bytes still allocated.
    Its largest value after the warm-up at most 2 % above the last warm-up round's peak.
    Without glibc (or before 2.33) it is skipped with a printed note. Python's small objects
    live in pymalloc's own arenas, outside malloc: ``sys.getallocatedblocks()`` is printed
    beside it;
  - resident memory flat: RSS after ``malloc_trim(0)`` (from
    ``/proc/self/statm``), the same comparison. This also counts the heap's fragmentation:
    freed chunks glibc cannot return because live ones share their pages. Measured alone
    (16 GPIS envs, one worker thread, 4000 batch steps of forward-biased random actions),
    RSS after the trim rose by 12 to 15 MB over the first 2500 to 3000 batch steps and then
    levelled off while the live heap stayed flat: not a leak, but it takes the allocator a
    while to settle;

  like is compared with like: every round does the same mix, so a round's peak comes from
  the same phases every round;
- the warm-up is the first 30 % of the rounds (rounded up; 3 of the full run's 10, 1 of the
  quick run's 3), fixed before the runs reported from what has to settle, not picked from
  what passes: every slot's storage (a GPIS map keeps the storage its last episode needed,
  so it reaches its working size within the first round) and the allocator's heap. In the
  measurement above the heap's fragmentation levelled off after about 3000 batch steps of
  16 GPIS envs (48,000 env steps of that env alone); the full run's warm-up is about
  500,000 steps of every configuration, of which 1,500 batch steps of its 16-env GPIS env.
  If RSS after the trim still creeps after that while the live heap stays flat, it is the
  allocator settling, and the per-round series shows whether it levels off;
- step time flat by episode count (through the run): per configuration, the median step time
  of the last third of the rounds after the warm-up over that of the first third at most
  1.5, comparing like with like: every single-env configuration (50 episodes a round, so
  the mix of free and contact steps is the same in both windows), and the vector-env
  configurations of the free-motion kinds (below). A vector env's contact-rich segment is
  100 batch steps of a few episodes (one or two in the 1-env one), and how much of those
  touch jars sets its median (up to about 1.8 times apart between windows in the runs so
  far): those are printed, not compared. A slowdown the reference workloads
  (``benchmarks.soak.reference``) also show is machine load, and is divided out;
- step time flat by step index within the episode, comparing like with like: a contact-rich
  policy's later steps cost more because the finger is touching (and pushing) jars
  (``forward``: about 1.5 to 1.8 times its first steps; ``oracle``), which is physics, not a
  slowdown. So the check takes the free-motion action kinds (``random``, ``out_of_range``,
  ``invalid``) and, of those, only the episodes in which the finger never touched a jar
  (``info["contacts"]`` zero at every step): per single-env configuration, the median of the
  last 25-step bin with at least 100 steps over that of the first bin, at most 1.5 (a cost
  that accumulates with the steps of an episode would show here; one that accumulates over
  episodes shows in the check above). Each episode visits every bin within milliseconds, so
  machine load hits all bins alike; the contact-rich kinds' profiles, and the share of steps
  touching a jar, are printed beside it.
"""

from __future__ import annotations

import dataclasses
import math
import os
from typing import Any

import numpy as np

from benchmarks.soak.memory import LIVE_HEAP_NOTE
from benchmarks.soak.plan import (
    ACTION_KINDS,
    FREE_MOTION_KINDS,
    INDEX_BIN,
    INDEX_DRIFT_LIMIT,
    LIVE_GROWTH_LIMIT,
    MIN_BIN_STEPS,
    RSS_GROWTH_LIMIT,
    RUN_DRIFT_LIMIT,
    TASK_KINDS,
    WARM_UP_FRACTION,
    power_range,
    setting,
)
from benchmarks.soak.reference import load_ratio, median
from benchmarks.soak.report import SoakResult, verdict_lines
from benchmarks.soak.workloads import Soak
from tactile_search import ENV_ID, ENV_IDS
from tactile_search.envs.config import MAP_MODES
from tactile_search.seed_ranges import TRAINING

#: The registered ids besides v0 the soak steps (by their names without the namespace).
TASK_IDS = [env_id.rpartition("/")[2] for env_id in ENV_IDS if env_id != ENV_ID]

#: The checks counted by failures during the run, in the order they are printed.
PER_STEP_CHECKS = (
    "all finite",
    "proprio in [-1, 1]",
    "steps count",
    "truncated at max_steps",
    "clipped flag",
    "autoreset step",
    "invalid actions refused",
    "error names the action",
    "only documented exceptions",
    "twin agrees (clipping, refused actions)",
    "replayed episode identical",
    "episode ends",
    "max_rows respected",
    "Gpis adds nothing at capacity",
    "Gpis fills to max_rows",
    "Gpis refuses past max_rows",
    "Gpis variance >= 0",
    "Gpis clears",
)
MIB = 2**20


class Analysis:
    """The checks of a finished soak, step by step; each step appends its report lines
    to ``lines`` and its checks to ``checks`` (or, for what the scale only measures, to
    ``informational``)."""

    def __init__(self, soak: Soak) -> None:
        self.soak = soak
        n = soak.records
        self.ns, self.cfg = soak.step_ns[:n], soak.step_config[:n]
        self.index, self.rounds = soak.step_index[:n], soak.step_round[:n]
        self.touch = soak.step_touch[:n]
        self.mem = soak.mem[: soak.mem_count]
        self.scale, self.warm = soak.scale, soak.scale.warm_rounds
        self.total = soak.total_steps()
        self.episodes = sum(soak.episodes[k] for k in ("single", "vector", "churn"))
        self.lines: list[str] = []
        self.checks: dict[str, tuple[bool, str]] = {}
        self.informational: dict[str, tuple[bool, str]] = {}
        post = list(range(self.warm, self.scale.rounds))
        third = max(1, math.ceil(len(post) / 3))
        #: The rounds after the warm-up compared by the drift check: first and last third.
        self.early_rounds, self.late_rounds = post[:third], post[-third:]

    def check(self, name: str, ok: bool, detail: str) -> None:
        target = self.informational if name in self.scale.informational else self.checks
        target[name] = (ok, detail)

    # ---- what ran ------------------------------------------------------------------------
    def summary(self) -> None:
        """What the run covered: steps, episodes, seeds, modes, kinds, capacities."""
        soak, scale = self.soak, self.scale
        self.lines += [
            f"soak ({scale.name}): {scale.rounds} rounds, rounds 1-{self.warm} the warm-up "
            f"({100 * WARM_UP_FRACTION:.0f} % of the rounds, rounded up); "
            f"{os.cpu_count()} cores, shared",
            f"steps: {self.total:,} in {soak.elapsed:.1f} s = "
            f"{self.total / soak.elapsed:,.0f} steps/s "
            f"(single env {soak.steps['single']:,}, vector env {soak.steps['vector']:,}, "
            f"twins {soak.steps['twin']:,}, churn {soak.steps['churn']:,})",
            f"episodes: {self.episodes:,} (single {soak.episodes['single']:,}, vector "
            f"{soak.episodes['vector']:,} with autoresets, churn {soak.episodes['churn']:,}; "
            f"twins {soak.episodes['twin']:,}); seeds given: {soak.seeds_given:,} distinct, "
            f"{soak.seed_base}..{soak.max_seed} (training range {power_range(TRAINING)})",
            f"covered: map modes {', '.join(MAP_MODES)}; action kinds "
            f"{', '.join(ACTION_KINDS)}; vector sizes {', '.join(map(str, scale.vector_sizes))} "
            f"(x4 with copy=False); every other registered id ({', '.join(TASK_IDS)}) single, "
            f"{', '.join(TASK_KINDS)}",
            f"GPIS at capacity: {soak.capacity_episodes:,} episodes with max_rows in "
            f"{soak.capacity_rows}, {soak.capacity_reached:,} reached it; standalone Gpis: "
            f"{soak.gpis['fills']:,} fills to max_rows in {scale.gpis_capacities}, "
            f"{soak.gpis['rows added']:,} rows",
        ]

    # ---- memory --------------------------------------------------------------------------
    def live_measured(self) -> bool:
        return bool((self.mem[:, 4] >= 0).all()) and LIVE_HEAP_NOTE is None

    def memory_table(self) -> list[dict[str, float]]:
        """Per round, the peak of the round's samples and the value at its end."""
        mem, warm, live = self.mem, self.warm, self.live_measured()
        self.lines += [
            f"memory per round ({len(mem):,} samples after episodes, segments, fills and "
            f"rounds; MiB, peak of the round / at its end; rounds 1-{warm} the warm-up):",
            f"  {'round':>7s} {'steps':>10s}  {'live heap (mallinfo2)':>21s}  "
            f"{'RSS after malloc_trim':>21s}  {'Python blocks':>13s}  {'raw RSS peak':>12s}",
        ]
        per_round: list[dict[str, float]] = []
        for r in range(self.scale.rounds):
            rows = mem[mem[:, 6] == r]
            if not len(rows):
                continue
            entry = {
                "round": r + 1,
                "steps": float(rows[-1, 1]),
                "live_peak_mib": float(rows[:, 4].max() / MIB) if live else math.nan,
                "live_end_mib": float(rows[-1, 4] / MIB) if live else math.nan,
                "rss_trim_peak_mib": float(rows[:, 2].max() / MIB),
                "rss_trim_end_mib": float(rows[-1, 2] / MIB),
                "python_blocks_end": float(rows[-1, 5]),
                "rss_raw_peak_mib": float(rows[:, 3].max() / MIB),
            }
            per_round.append(entry)
            live_cell = (
                f"{entry['live_peak_mib']:9.1f} / {entry['live_end_mib']:9.1f}"
                if live
                else f"{'-':>21s}"
            )
            self.lines.append(
                f"  {r + 1:5d}{' w' if r < warm else '  '} {entry['steps']:10,.0f}  "
                f"{live_cell}  "
                f"{entry['rss_trim_peak_mib']:9.1f} / {entry['rss_trim_end_mib']:9.1f}  "
                f"{entry['python_blocks_end']:13,.0f}  {entry['rss_raw_peak_mib']:12.1f}"
            )
        return per_round

    def memory_growth(
        self, name: str, label: str, column: int, limit: float, start: float
    ) -> dict[str, float]:
        """Checks that a memory column's largest value after the warm-up is within
        ``limit`` of its peak in the warm-up's last round; returns its figures."""
        reference_rows = self.mem[self.mem[:, 6] == self.warm - 1]
        after_rows = self.mem[self.mem[:, 6] >= self.warm]
        if not len(reference_rows) or not len(after_rows):
            reference = largest = grew = math.nan
        else:
            reference = float(reference_rows[:, column].max())
            largest = float(after_rows[:, column].max())
            grew = largest / reference - 1
        detail = (
            f"{label} peak {reference / MIB:.1f} MiB in round {self.warm} (end of the "
            f"warm-up), largest after it {largest / MIB:.1f} MiB: growth {100 * grew:+.2f} % "
            f"(limit {100 * limit:.0f} %)"
        )
        self.check(name, grew <= limit, detail)
        return {
            "start_mib": start / MIB,
            "warm_up_peak_mib": reference / MIB,
            "max_after_warm_up_mib": largest / MIB,
            "growth_after_warm_up": grew,
        }

    def memory(self) -> dict[str, Any]:
        """The per-round table, the leak check (live heap) and resident memory after the
        trim; returns the memory figures."""
        soak = self.soak
        figures: dict[str, Any] = {"per_round": self.memory_table(), "samples": len(self.mem)}
        if self.live_measured():
            figures["live_heap"] = self.memory_growth(
                "no leak: live heap flat", "live heap", 4, LIVE_GROWTH_LIMIT, soak.live_start
            )
        else:
            self.lines.append(f"  note: {LIVE_HEAP_NOTE}; the leak check is skipped")
        figures["rss_after_trim"] = {
            **self.memory_growth(
                "resident memory flat",
                "RSS after malloc_trim",
                2,
                RSS_GROWTH_LIMIT,
                soak.rss_start,
            ),
            "end_mib": float(self.mem[-1, 2] / MIB),
        }
        return figures

    # ---- step time -----------------------------------------------------------------------
    def load_ratios(self) -> tuple[float, float]:
        """The reference workloads' late over early medians: single-threaded, vector."""
        reference = self.soak.reference
        return (
            load_ratio(reference.single_table(), self.early_rounds, self.late_rounds),
            load_ratio(reference.vector_table(), self.early_rounds, self.late_rounds),
        )

    def run_drift(self, control_ratio: float, vector_ratio: float) -> None:
        """Step time by episode count: each configuration's late over early median, the
        machine's load divided out."""
        soak, early_rounds, late_rounds = self.soak, self.early_rounds, self.late_rounds
        self.lines.append(
            f"step time by episode count (median µs per step call in rounds "
            f"{[r + 1 for r in early_rounds]} -> {[r + 1 for r in late_rounds]}; reference "
            f"workloads' ratios, divided out when above 1: single-threaded "
            f"{control_ratio:.2f} (single envs), 16-env vector segment {vector_ratio:.2f} "
            f"(vector envs); limit {RUN_DRIFT_LIMIT}; single envs: every kind, "
            f"{self.scale.episodes} episodes a round; vector envs: free-motion kinds, "
            f"contact-rich ones shown only, a segment's few episodes set how much of it "
            f"touches jars):"
        )
        worst, compared = (0.0, ""), 0
        for i, config in enumerate(soak.configs):
            mine = self.cfg == i
            early = self.ns[mine & np.isin(self.rounds, early_rounds)]
            late = self.ns[mine & np.isin(self.rounds, late_rounds)]
            if len(early) < MIN_BIN_STEPS or len(late) < MIN_BIN_STEPS:
                self.lines.append(f"  {config.name:44s} too few steps ({len(early)}, {len(late)})")
                continue
            raw = median(late) / median(early)
            ratio = vector_ratio if config.num_envs is not None else control_ratio
            adjusted = raw / max(ratio, 1.0)
            shown = config.num_envs is not None and config.kind not in FREE_MOTION_KINDS
            if not shown:
                compared += 1
                worst = max(worst, (adjusted, config.name))
            self.lines.append(
                f"  {config.name:44s} {median(early) / 1e3:8.1f} -> {median(late) / 1e3:8.1f}"
                f"  x{raw:.2f}"
                + (f" (x{adjusted:.2f} after control)" if ratio > 1 else "")
                + (" (contact-rich, shown)" if shown else "")
            )
        self.check(
            "step time flat through the run",
            compared > 0 and worst[0] <= RUN_DRIFT_LIMIT,
            f"{compared} configurations compared, worst x{worst[0]:.2f} ({worst[1]}), "
            f"limit {RUN_DRIFT_LIMIT}",
        )

    def index_drift(self) -> None:
        """Step time by step index within the episode, single-env configurations: the last
        usable bin over the first, free-motion episodes that never touched a jar."""
        bins = int(setting("max_steps")["default"]) // INDEX_BIN
        self.lines.append(
            f"step time by step index (after the warm-up: share of steps touching a jar, "
            f"episodes used, median µs per bin of {INDEX_BIN} steps; free-motion kinds "
            f"({', '.join(FREE_MOTION_KINDS)}): only the episodes that never touched a jar, "
            f"last bin with >= {MIN_BIN_STEPS} steps over the first, limit "
            f"{INDEX_DRIFT_LIMIT}; contact-rich kinds: all episodes, shown only, their later "
            f"steps touch jars and cost more):"
        )
        worst, compared = (0.0, ""), 0
        for i, config in enumerate(self.soak.configs):
            if config.num_envs is not None:
                continue
            mine = (self.cfg == i) & (self.rounds >= self.warm)
            touching = f"{100 * (self.touch[mine] & 1).mean():3.0f} %" if mine.any() else "  - %"
            free = config.kind in FREE_MOTION_KINDS
            if free:  # only the episodes that never touched a jar
                mine &= (self.touch & 2) == 0
            kept = int((mine & (self.index == 0)).sum())  # episodes
            medians, counts = self.bin_medians(mine, bins)
            usable = [b for b in range(bins) if counts[b] >= MIN_BIN_STEPS]
            cells = " ".join(
                f"{m / 1e3:6.0f}" if c >= MIN_BIN_STEPS else "     -"
                for m, c in zip(medians, counts, strict=True)
            )
            ratio = (
                medians[usable[-1]] / medians[0] if len(usable) >= 2 and usable[0] == 0 else None
            )
            label = f"  {config.name:40s} {touching} {kept:5d} {cells}"
            if not free:
                self.lines.append(
                    f"{label}  x{ratio:.2f} (contact-rich, shown)" if ratio else label
                )
            elif ratio is None:
                self.lines.append(f"{label}  (too few)")
            else:
                compared += 1
                worst = max(worst, (ratio, config.name))
                self.lines.append(f"{label}  x{ratio:.2f}")
        self.check(
            "step time flat by step index",
            compared > 0 and worst[0] <= INDEX_DRIFT_LIMIT,
            f"{compared} free-motion configurations compared, worst x{worst[0]:.2f} "
            f"({worst[1]}), limit {INDEX_DRIFT_LIMIT}",
        )

    def bin_medians(self, mine: np.ndarray, bins: int) -> tuple[list[float], list[int]]:
        """The median step time and the step count of each step-index bin of ``mine``."""
        medians, counts = [], []
        for b in range(bins):
            in_bin = self.ns[mine & (self.index // INDEX_BIN == b)]
            medians.append(median(in_bin))
            counts.append(len(in_bin))
        return medians, counts

    # ---- exceptions and the per-step checks ----------------------------------------------
    def exceptions(self) -> None:
        """The documented and the other exceptions, counted by kind."""
        soak = self.soak
        self.lines.append(
            "documented exceptions: "
            + (", ".join(f"{k} {v:,}" for k, v in sorted(soak.expected.items())) or "none")
        )
        self.lines.append(
            "other exceptions: "
            + (", ".join(f"{k} {v:,}" for k, v in sorted(soak.unexpected.items())) or "none")
        )

    def failure_checks(self) -> None:
        """The per-step checks (failures counted during the run), the capacity episodes,
        the invalid actions tried and, for the full run, its size."""
        soak = self.soak
        for name in [*PER_STEP_CHECKS, *sorted(set(soak.failures) - set(PER_STEP_CHECKS))]:
            count = soak.failures[name]
            self.checks[name] = (count == 0, f"{count:,} failures" if count else "no failures")
        self.checks["GPIS reaches max_rows in episodes"] = (
            soak.capacity_reached > 0,
            f"{soak.capacity_reached:,} of {soak.capacity_episodes:,} episodes",
        )
        invalid = sum(soak.expected.values())
        self.checks["invalid actions tried"] = (
            invalid > 0,
            f"{invalid:,} documented errors raised",
        )
        if soak.scale.name == "full":
            self.checks["size: >= 10**6 steps, >= 10**4 seeds"] = (
                self.total >= 10**6 and soak.seeds_given >= 10**4,
                f"{self.total:,} steps, {soak.seeds_given:,} seeds",
            )

    def figures(
        self, memory: dict[str, Any], control_ratio: float, vector_ratio: float, passed: bool
    ) -> dict[str, Any]:
        """Everything measured, as written to ``--json``."""
        soak = self.soak
        return {
            "scale": dataclasses.asdict(soak.scale),
            "steps": self.total,
            "steps_by_kind": dict(soak.steps),
            "episodes": self.episodes,
            "episodes_by_kind": dict(soak.episodes),
            "seeds_given": soak.seeds_given,
            "seconds": soak.elapsed,
            "steps_per_s": self.total / soak.elapsed,
            "warm_up_rounds": self.warm,
            "memory": memory,
            "control_ratio": control_ratio,
            "vector_control_ratio": vector_ratio,
            "documented_exceptions": dict(soak.expected),
            "other_exceptions": dict(soak.unexpected),
            "failures": dict(soak.failures),
            "failure_messages": soak.messages,
            "capacity_episodes": soak.capacity_episodes,
            "capacity_reached": soak.capacity_reached,
            "gpis": dict(soak.gpis),
            "checks": {k: {"passed": ok, "detail": d} for k, (ok, d) in self.checks.items()},
            "informational": {
                k: {"within_limit": ok, "detail": d} for k, (ok, d) in self.informational.items()
            },
            "passed": passed,
        }


def analyse(soak: Soak) -> SoakResult:
    """The checks and figures of a finished soak."""
    analysis = Analysis(soak)
    analysis.summary()
    memory = analysis.memory()
    control_ratio, vector_ratio = analysis.load_ratios()
    analysis.run_drift(control_ratio, vector_ratio)
    analysis.index_drift()
    analysis.exceptions()
    analysis.failure_checks()
    passed = all(ok for ok, _ in analysis.checks.values())
    analysis.lines += verdict_lines(
        soak.scale.name, analysis.checks, analysis.informational, soak.messages, passed
    )
    figures = analysis.figures(memory, control_ratio, vector_ratio, passed)
    return SoakResult(analysis.checks, figures, "\n".join(analysis.lines), soak)
