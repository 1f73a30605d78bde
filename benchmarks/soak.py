"""Soak test of CupboardSearch-v0: many steps, hostile actions, full GPIS maps; nothing leaks.

What it runs, in rounds (the first 30 % are the warm-up; every round does the same mix):

- one long-lived single env (``gymnasium.make``) per map mode (the list comes from the
  package, ``tactile_search.envs.config.MAP_MODES``) and action kind, reset with a new
  layout seed from the training range ``[2**32, 2**63)`` (DESIGN.md §7) for every episode:
  ``random`` (uniform in the action space), ``forward`` (random with the motion into the
  cupboard: contact-rich), ``out_of_range`` (finite components up to 1e300 and float32's
  largest: the env clips them, ``info["clipped"]``), ``invalid`` (about one step in ten is
  NaN, inf, a wrong shape, a string, None, a dict or an object array: each must raise the
  documented ``ValueError`` (or ``TypeError``) and change nothing) and ``oracle``
  (``env.unwrapped.oracle_action()``);
- GPIS maps filled to capacity in episodes: the GPIS mode with small values of the core's
  ``max_rows`` setting (its name and lower bound read from the settings table), ``forward``
  actions; the map must never hold more rows than ``max_rows`` and some episodes must reach it
  (``info["contacts_dropped"]`` counts the readings dropped at capacity);
- one long-lived vector env (``gymnasium.make_vec``, the package's vector entry point) per map
  mode and size (1, 4 and 16 episodes; the size-4 one with ``copy=False``), reset with
  training-range seeds at the start of each of its segments and then autoresetting (the
  autoreset episodes draw their layout seeds from the env's own generator), stepped with
  every action kind;
- a fresh "twin" env for some ``out_of_range`` and ``invalid`` episodes, stepped with the
  clipped valid actions only: its rollout must be bit-identical (clipping is all the env does
  to a large action, and a refused action leaves no trace);
- a standalone ``Gpis`` per capacity filled with repeated ``add_*`` calls until one raises the
  documented ``ValueError`` (nothing added), then topped up value by value to exactly
  ``max_rows``, checked, cleared and refilled;
- a few envs of every kind built, stepped and closed each round (construction churn).

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
    Its largest value after the warm-up at most 5 % above the last warm-up round's peak.
    Without glibc (or before 2.33) it is skipped with a printed note. Python's small objects
    live in pymalloc's own arenas, outside malloc: ``sys.getallocatedblocks()`` is printed
    beside it;
  - resident memory flat (the issue's check): RSS after ``malloc_trim(0)`` (from
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
  far): those are printed, not compared. The machine is shared and noisy, so two fixed
  reference workloads are timed through the run, and a slowdown they also show (machine
  load) is divided out: a single-threaded one (Python and numpy) for the single envs, and a
  fixed segment of a 16-env vector env without a map (same seeds, same free-motion actions;
  in a spawned process of its own, so it neither touches the heap being measured nor
  depends on it) for the vector envs, whose steps run on the core's worker threads and so
  also feel a load on the second core that the single-threaded workload does not (in one
  full run the late rounds took up to 45 % longer while single-env steps and the
  single-threaded workload did not change). Medians only, ``time.perf_counter_ns``;
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

    python benchmarks/soak.py            # the full soak: >= 10**6 steps, >= 10**4 seeds
    python benchmarks/soak.py --quick    # about 30 s (what tests/test_soak.py runs)
    python benchmarks/soak.py --rounds 4 --json results/soak.json

From Python: ``from benchmarks.soak import run_soak, FULL, QUICK``;
``result = run_soak(QUICK)``; ``result.passed``, ``result.checks``, ``result.figures``.
"""

from __future__ import annotations

import argparse
import dataclasses
import itertools
import json
import math
import os
import sys
import time
from collections import Counter
from pathlib import Path
from typing import Any

import gymnasium as gym
import numpy as np

import tactile_search  # noqa: F401  (registers the environment)
from tactile_search import Gpis
from tactile_search.envs.config import MAP_MODES, SETTINGS

ENV_ID = "tactile_search/CupboardSearch-v0"
#: Layout seeds for training (DESIGN.md §7; ``agents/train.py``'s ``TRAIN_LAYOUT_SEEDS``).
TRAIN_SEEDS = (2**32, 2**63)
#: The warm-up: this fraction of the rounds (rounded up, at least one), chosen before any
#: run from what has to settle (see the module docstring), not from what passes.
WARM_UP_FRACTION = 0.3
#: Largest growth after the warm-up of the live heap (the leak check) and of the resident
#: memory after ``malloc_trim`` (the issue's "resident memory flat"), as a fraction of the
#: last warm-up round's peak.
LIVE_GROWTH_LIMIT = 0.05
RSS_GROWTH_LIMIT = 0.05
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
#: Probability that a step of an ``invalid`` episode is an invalid action.
INVALID_RATE = 0.1
#: Every how many ``out_of_range`` / ``invalid`` episodes gets a twin.
TWIN_EVERY = 8
#: Seconds between timings of the reference workload.
CONTROL_EVERY_S = 0.5
#: Seconds between timings of the parallel reference workload (a fixed vector-env segment).
VECTOR_CONTROL_EVERY_S = 2.0
#: Its size and length: slots, timed batch steps.
VECTOR_CONTROL_SHAPE = (16, 10)
#: Failure messages kept (all are counted).
MAX_FAILURE_MESSAGES = 30

ACTION_KINDS = ("random", "forward", "out_of_range", "invalid", "oracle")


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


def rss_bytes() -> int:
    """Resident set size of this process now (``/proc/self/statm``; else the peak)."""
    try:
        with open("/proc/self/statm") as statm:
            return int(statm.read().split()[1]) * os.sysconf("SC_PAGE_SIZE")
    except OSError:  # not Linux: the peak so far is the best the standard library has
        import resource

        return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024


def _malloc_trim() -> Any:
    """glibc's ``malloc_trim`` (returns freed heap pages to the system), or None."""
    try:
        import ctypes

        return ctypes.CDLL("libc.so.6").malloc_trim
    except (OSError, AttributeError):
        return None


MALLOC_TRIM = _malloc_trim()


def live_rss_bytes() -> int:
    """RSS after glibc's ``malloc_trim(0)``: without the free memory the allocator can hand
    back (free pages in its per-thread arenas; the core's worker threads free big GPIS
    buffers there). What stays is memory in use plus the heap's fragmentation: free chunks
    the allocator cannot return because live ones sit on the same pages. Plain RSS where
    there is no glibc."""
    if MALLOC_TRIM is not None:
        MALLOC_TRIM(0)
    return rss_bytes()


def _mallinfo2() -> Any:
    """glibc's ``mallinfo2`` (glibc >= 2.33) through ctypes, or None."""
    try:
        import ctypes

        class MallInfo2(ctypes.Structure):
            _fields_ = [
                (name, ctypes.c_size_t)
                for name in ("arena", "ordblks", "smblks", "hblks", "hblkhd", "usmblks",
                             "fsmblks", "uordblks", "fordblks", "keepcost")
            ]  # fmt: skip

        function = ctypes.CDLL("libc.so.6").mallinfo2
        function.restype = MallInfo2
        function.argtypes = []
        return function
    except (OSError, AttributeError):
        return None


MALLINFO2 = _mallinfo2()
#: Why the live heap is not measured (None when it is).
LIVE_HEAP_NOTE = (
    None
    if MALLINFO2 is not None
    else "no glibc mallinfo2 here (not glibc, or glibc < 2.33): live heap not measured"
)


def live_heap_bytes() -> int:
    """Bytes the program holds from malloc now: glibc's ``mallinfo2`` (summed over every
    arena) in-use chunks ``uordblks`` plus directly mmapped blocks ``hblkhd``; -1 without
    glibc. Unlike RSS it does not count free memory the allocator keeps or cannot return
    (fragmentation), so growth here is memory still referenced: a leak. It covers the Rust
    core, numpy's buffers and Python's large objects; Python's small objects live in
    pymalloc's own mmapped arenas (``sys.getallocatedblocks()``, printed beside it)."""
    if MALLINFO2 is None:
        return -1
    info = MALLINFO2()
    return int(info.uordblks + info.hblkhd)


def control_ns(reps: int = 7) -> int:
    """Median time of a fixed CPU-bound workload (Python and numpy), ns: the machine's
    load, timed through the run beside the steps."""
    times = []
    values = np.arange(2000.0)
    for _ in range(reps):
        start = time.perf_counter_ns()
        total = 0
        for i in range(2000):
            total += i * i
        float((values * values).sum())
        times.append(time.perf_counter_ns() - start)
    return sorted(times)[reps // 2]


def vector_control_worker(conn: Any) -> None:
    """The parallel reference workload, in a process of its own (so that it neither touches
    the soak's heap nor depends on it): on each request, the median batch-step time (ns) of
    a fixed segment of a 16-env vector env without a map, the same seeds and free-motion
    actions every time, so only the machine differs. Its steps run on the core's worker
    threads, like the soak's vector envs, so it feels a load on the second core that the
    single-threaded reference workload does not."""
    size, length = VECTOR_CONTROL_SHAPE
    env = gym.make_vec(ENV_ID, num_envs=size, vectorization_mode="vector_entry_point", map="none")
    actions = np.random.default_rng(0).uniform(-1, 1, (length, size, 3))
    seeds = list(range(TRAIN_SEEDS[0], TRAIN_SEEDS[0] + size))
    conn.send("ready")
    while conn.recv():
        env.reset(seed=seeds)
        times = []
        for action in actions:
            start = time.perf_counter_ns()
            env.step(action)
            times.append(time.perf_counter_ns() - start)
        conn.send(sorted(times)[length // 2])
    env.close()


def nonfinite(value: Any) -> bool:
    """True if ``value`` (array, scalar, dict, list, tuple, nested) holds a NaN or inf."""
    if isinstance(value, np.ndarray):
        if value.dtype.kind in "fc":
            return not bool(np.isfinite(value).all())
        if value.dtype.kind == "O":
            return any(nonfinite(v) for v in value.flat)
        return False
    if isinstance(value, dict):
        return any(nonfinite(v) for v in value.values())
    if isinstance(value, list | tuple):
        return any(nonfinite(v) for v in value)
    if isinstance(value, float | np.floating):
        return not math.isfinite(value)
    if isinstance(value, complex | np.complexfloating):
        return not (math.isfinite(value.real) and math.isfinite(value.imag))
    return False


def out_of_range_action(rng: np.random.Generator, shape: tuple[int, ...]) -> np.ndarray:
    """Finite actions, about half their components outside [-1, 1] (up to 1e300), some in
    float32 at its largest or just past 1."""
    if rng.random() < 0.2:
        picks = np.array(
            [np.finfo(np.float32).max, np.nextafter(np.float32(1), np.float32(2)), 0.5],
            dtype=np.float32,
        )
        signs = rng.choice(np.array([-1, 1], dtype=np.float32), shape)
        return signs * rng.choice(picks, shape)
    action = rng.uniform(-1, 1, shape)
    wild = rng.random(shape) < 0.5
    magnitude = 10.0 ** rng.uniform(0, 300, shape)
    return np.where(wild, rng.choice([-1.0, 1.0], shape) * magnitude, action)


def invalid_action(rng: np.random.Generator, num_envs: int | None) -> tuple[str, Any]:
    """A (kind, action) the env must refuse; ``num_envs`` None for the single env."""
    shape = (3,) if num_envs is None else (num_envs, 3)
    valid = rng.uniform(-1, 1, shape)
    kind = str(
        rng.choice(
            ["nan", "inf", "-inf", "short", "long", "extra_dim", "str", "none", "dict", "object"]
        )
    )
    if kind in ("nan", "inf", "-inf"):
        valid[np.unravel_index(rng.integers(valid.size), shape)] = float(kind)
        return kind, valid
    if kind == "short":
        return kind, valid[..., :2]
    if kind == "long":
        return kind, np.zeros((*shape[:-1], 4))
    if kind == "extra_dim":
        return kind, valid[None] if num_envs is None else valid[..., None]
    if kind == "str":
        return kind, "left" if rng.random() < 0.5 else [["a", "b", "c"]] * (num_envs or 1)
    if kind == "none":
        return kind, None
    if kind == "dict":
        return kind, {"dx": 0.1}
    return kind, np.full(shape, None, dtype=object)


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


class Soak:
    """The state of one soak run (see the module docstring)."""

    def __init__(self, scale: Scale, seed_base: int = TRAIN_SEEDS[0], log: Any = print) -> None:
        self.scale = scale
        self.log = log
        self.rng = np.random.default_rng(seed_base % 2**32)
        self.seed_base = self.next_seed = self.max_seed = seed_base
        self.seeds_given = 0
        self.digests: dict[tuple[int, int], tuple] = {}
        max_rows = setting("max_rows")
        self.capacity_rows = tuple(sorted({range_lower_bound(max_rows), *scale.capacity_rows}))
        self.configs = self._configs()
        # Every record lives in arrays allocated (and touched) before the warm-up, so the
        # soak's own bookkeeping does not grow the RSS it measures.
        max_steps = setting("max_steps")["default"]
        single = sum(c.num_envs is None for c in self.configs)
        vector = len(self.configs) - single
        capacity = scale.rounds * (single * scale.episodes * max_steps + vector * scale.batch_steps)
        self.step_ns = np.full(capacity + 1, -1, dtype=np.int64)
        self.step_config = np.full(capacity + 1, -1, dtype=np.int16)
        self.step_index = np.full(capacity + 1, -1, dtype=np.int16)
        self.step_round = np.full(capacity + 1, -1, dtype=np.int16)
        self.step_total = np.full(capacity + 1, -1, dtype=np.int64)  # env steps so far
        # Bit 0: this step touched a jar (info["contacts"] > 0); bit 1: its episode did.
        self.step_touch = np.full(capacity + 1, 0, dtype=np.int8)
        self.records = 0
        samples = scale.rounds * (single * scale.episodes + 4 * len(self.configs) + 64) + 16
        #: Memory samples: elapsed s, env steps, RSS after malloc_trim, raw RSS, live heap
        #: bytes (mallinfo2), Python's allocated blocks, round.
        self.mem = np.full((samples, 7), -1.0)
        self.mem_count = 0
        controls = 20_000
        self.control = np.full((controls, 3), -1.0)  # elapsed s, round, ns
        self.control_count = 0
        self.last_control = -math.inf
        self.vcontrol = np.full((controls, 3), -1.0)  # the parallel one: the same
        self.vcontrol_count = 0
        self.last_vcontrol = -math.inf
        self.vcontrol_conn: Any = None  # the pipe to vector_control_worker's process
        self.vcontrol_process: Any = None
        self.vcontrol_ready = False
        self.steps = Counter()  # env steps by "single", "vector", "twin", "churn"
        self.episodes = Counter()  # episodes started by the same
        self.expected = Counter()  # documented exceptions: "ValueError: nan" ...
        self.unexpected = Counter()
        self.failures = Counter()
        self.messages: list[str] = []
        self.capacity_episodes = 0
        self.capacity_reached = 0
        self.gpis = Counter()
        self.round = 0
        self.start = time.perf_counter()

    # ---- the plan ------------------------------------------------------------------------
    def _configs(self) -> list[Config]:
        configs = [
            Config(f"single {mode} {kind}", mode, kind)
            for mode in MAP_MODES
            for kind in ACTION_KINDS
        ]
        configs += [
            Config(f"single gpis max_rows={rows} forward", "gpis", "forward",
                   settings={"max_rows": rows})
            for rows in self.capacity_rows
        ]  # fmt: skip
        for mode in MAP_MODES:
            for size in self.scale.vector_sizes:
                copy = size != 4
                for kind in ACTION_KINDS:
                    label = f"vector {mode} x{size}{'' if copy else ' copy=False'} {kind}"
                    configs.append(Config(label, mode, kind, num_envs=size, copy=copy))
        return configs

    def take_seeds(self, count: int) -> list[int]:
        """The next ``count`` layout seeds (in replay mode, round 1's again)."""
        seeds = list(range(self.next_seed, self.next_seed + count))
        if seeds[0] < TRAIN_SEEDS[0] or seeds[-1] >= TRAIN_SEEDS[1]:
            raise ValueError(f"seeds {seeds[0]}..{seeds[-1]} leave the training range")
        self.next_seed += count
        self.max_seed = max(self.max_seed, self.next_seed - 1)
        self.seeds_given = self.max_seed - self.seed_base + 1
        return seeds

    # ---- bookkeeping ---------------------------------------------------------------------
    def fail(self, check: str, message: str) -> None:
        self.failures[check] += 1
        if len(self.messages) < MAX_FAILURE_MESSAGES:
            self.messages.append(f"{check}: {message}")

    def total_steps(self) -> int:
        return sum(self.steps.values())

    def sample(self) -> None:
        """A memory sample, and now and then a timing of the reference workload."""
        now = time.perf_counter() - self.start
        if self.mem_count < len(self.mem):
            raw = rss_bytes()
            trimmed = live_rss_bytes()
            self.mem[self.mem_count] = (
                now, self.total_steps(), trimmed, raw, live_heap_bytes(),
                sys.getallocatedblocks(), self.round,
            )  # fmt: skip
            self.mem_count += 1
        if now - self.last_control >= CONTROL_EVERY_S and self.control_count < len(self.control):
            self.control[self.control_count] = (now, self.round, control_ns())
            self.control_count += 1
            self.last_control = now
        conn = self.vcontrol_conn
        if conn is not None and not self.vcontrol_ready and conn.poll():
            self.vcontrol_ready = conn.recv() == "ready"
        if (
            self.vcontrol_ready
            and now - self.last_vcontrol >= VECTOR_CONTROL_EVERY_S
            and self.vcontrol_count < len(self.vcontrol)
        ):
            try:
                conn.send(True)
                self.vcontrol[self.vcontrol_count] = (now, self.round, conn.recv())
            except (EOFError, OSError) as error:  # the worker died: carry on without it
                self.log(f"  the parallel reference workload stopped ({error!r})")
                self.vcontrol_ready = False
                return
            self.vcontrol_count += 1
            self.last_vcontrol = now

    def start_vector_control(self) -> None:
        """Starts vector_control_worker's process (spawned: the core has threads)."""
        import multiprocessing

        context = multiprocessing.get_context("spawn")
        self.vcontrol_conn, child = context.Pipe()
        self.vcontrol_process = context.Process(
            target=vector_control_worker, args=(child,), daemon=True
        )
        self.vcontrol_process.start()

    def stop_vector_control(self) -> None:
        if self.vcontrol_process is None:
            return
        try:
            self.vcontrol_conn.send(False)
        except OSError:
            pass
        self.vcontrol_process.join(timeout=10)
        if self.vcontrol_process.is_alive():
            self.vcontrol_process.terminate()
            self.vcontrol_process.join()
        self.vcontrol_conn.close()
        self.vcontrol_process = self.vcontrol_conn = None

    def record(self, config: int, elapsed_ns: int, index: int, touch: bool = False) -> None:
        if self.records < len(self.step_ns):
            r = self.records
            self.step_ns[r] = elapsed_ns
            self.step_config[r] = config
            self.step_index[r] = index
            self.step_round[r] = self.round
            self.step_total[r] = self.total_steps()
            self.step_touch[r] = touch
            self.records += 1

    def refuse(self, where: str, env: Any, bad_kind: str, action: Any) -> None:
        """Steps ``env`` with an invalid action, which must raise the documented error."""
        try:
            env.step(action)
        except (ValueError, TypeError) as error:
            self.expected[f"{type(error).__name__}: {bad_kind}"] += 1
            if "action" not in str(error):
                self.fail("error names the action", f"{where}: {bad_kind} -> {error!r}")
        except Exception as error:  # the soak's point: count, report, carry on
            self.unexpected[type(error).__name__] += 1
            self.fail("only documented exceptions", f"{where}: {bad_kind} -> {error!r}")
        else:
            self.fail("invalid actions refused", f"{where}: {bad_kind} {action!r} accepted")

    def check_output(self, where: str, obs: Any, reward: Any, info: Any) -> None:
        if nonfinite(obs) or nonfinite(reward) or nonfinite(info):
            self.fail("all finite", f"{where}: obs/reward/info holds NaN or inf")
        if not bool(np.all(np.abs(obs["proprio"]) <= 1)):
            self.fail("proprio in [-1, 1]", f"{where}: {obs['proprio']!r}")

    # ---- single env ----------------------------------------------------------------------
    def action(
        self, kind: str, env: Any, shape: tuple[int, ...], rng: np.random.Generator
    ) -> np.ndarray:
        if kind == "oracle":
            unwrapped = env.unwrapped
            if hasattr(unwrapped, "oracle_actions"):
                return unwrapped.oracle_actions()
            return unwrapped.oracle_action()
        if kind == "out_of_range":
            return out_of_range_action(rng, shape)
        action = rng.uniform(-1, 1, shape).astype(np.float32)
        if kind == "forward":
            action[..., 1] = np.abs(action[..., 1])
        return action

    def single_episode(self, index: int, config: Config, seed: int) -> None:
        """One episode of ``config`` on layout ``seed``: everything it does follows from
        ``(seed, index)``, so a failure's message is its reproducer."""
        env = config.env
        rng = np.random.default_rng([seed, index])
        twin = None
        if config.kind in ("out_of_range", "invalid") and rng.random() < 1 / TWIN_EVERY:
            twin = gym.make(ENV_ID, map=config.mode, **config.settings)
            twin.reset(seed=seed)
            self.episodes["twin"] += 1
        self.episodes[config.name] += 1
        self.episodes["single"] += 1
        obs, info = env.reset(seed=seed)
        where = f"{config.name} (config {index}) seed={seed}"
        self.check_output(where, obs, 0.0, info)
        max_steps = env.unwrapped.config.max_steps
        max_rows = config.settings.get("max_rows")
        steps, reached, total_reward = info["steps"], False, 0.0
        if steps != 0:
            self.fail("steps count", f"{where}: reset gives steps={steps}")
        first_record = self.records
        while True:
            if config.kind == "invalid" and rng.random() < INVALID_RATE:
                bad_kind, bad = invalid_action(rng, None)
                self.refuse(f"{where} step {steps}", env, bad_kind, bad)
                continue
            action = self.action(config.kind, env, (3,), rng)
            start = time.perf_counter_ns()
            obs, reward, terminated, truncated, info = env.step(action)
            elapsed = time.perf_counter_ns() - start
            self.steps["single"] += 1
            self.record(index, elapsed, steps, info["contacts"] > 0)
            at = f"{where} step {steps}"
            self.check_output(at, obs, reward, info)
            total_reward += reward
            if info["steps"] != steps + 1:
                self.fail("steps count", f"{at}: steps {steps} -> {info['steps']}")
            steps = info["steps"]
            if truncated != (steps >= max_steps and not terminated):
                self.fail("truncated at max_steps", f"{at}: truncated={truncated}")
            clipped = bool(np.any(np.abs(np.asarray(action, dtype=np.float64)) > 1))
            if info["clipped"] != clipped:
                self.fail("clipped flag", f"{at}: {action!r} gave clipped={info['clipped']}")
            if max_rows is not None:
                if info["gpis_rows"] > max_rows:
                    self.fail("max_rows respected", f"{at}: {info['gpis_rows']} > {max_rows}")
                reached |= info["contacts_dropped"] > 0 or info["gpis_rows"] + 3 > max_rows
            if twin is not None:
                self.twin_step(at, twin, action, obs, reward, terminated, truncated, info)
            if terminated or truncated:
                break
            if steps > max_steps:
                self.fail("episode ends", f"{at}: past max_steps={max_steps}")
                break
        if max_rows is not None:
            self.capacity_episodes += 1
            self.capacity_reached += reached
        records = self.step_touch[first_record : self.records]
        if records.any():  # the episode touched a jar: mark all its steps
            records |= 2
        if twin is not None:
            twin.close()
        maps = obs.get("map")
        digest = (steps, total_reward, obs["proprio"].tobytes(), maps is None or maps.tobytes())
        key = (index, seed)
        if key in self.digests and self.digests[key] != digest:
            self.fail("replayed episode identical", f"{where}: differs from its first run")
        elif self.round == 0:
            self.digests[key] = digest
        self.sample()

    def twin_step(
        self, at: str, twin: Any, action: Any, obs: dict, reward: float, terminated: bool,
        truncated: bool, info: dict,
    ) -> None:  # fmt: skip
        """Steps the twin with the clipped action: it must agree bit for bit."""
        t_obs, t_reward, t_terminated, t_truncated, t_info = twin.step(
            np.clip(np.asarray(action, dtype=np.float64), -1.0, 1.0)
        )
        self.steps["twin"] += 1
        same = (
            obs.keys() == t_obs.keys()
            and all(np.array_equal(obs[k], t_obs[k]) for k in obs)
            and reward == t_reward
            and (terminated, truncated) == (t_terminated, t_truncated)
            and {k: v for k, v in info.items() if k != "clipped"}
            == {k: v for k, v in t_info.items() if k != "clipped"}
        )
        if not same:
            self.fail("twin agrees (clipping, refused actions)", f"{at}: {action!r}")

    # ---- vector env ----------------------------------------------------------------------
    def vector_segment(self, index: int, config: Config) -> None:
        env, num_envs = config.env, config.num_envs
        seeds = self.take_seeds(num_envs)
        where = f"{config.name} (config {index}) seeds={seeds[0]}.."
        rng = np.random.default_rng([seeds[0], index])
        obs, info = env.reset(seed=seeds)
        self.episodes["vector"] += num_envs
        self.check_output(where, obs, 0.0, info)
        steps = info["steps"].copy()
        done = np.zeros(num_envs, dtype=bool)
        for b in range(self.scale.batch_steps):
            if config.kind == "invalid" and rng.random() < INVALID_RATE:
                bad_kind, bad = invalid_action(rng, num_envs)
                self.refuse(f"{where} batch step {b}", env, bad_kind, bad)
            action = self.action(config.kind, env, (num_envs, 3), rng)
            start = time.perf_counter_ns()
            obs, rewards, terminated, truncated, info = env.step(action)
            elapsed = time.perf_counter_ns() - start
            self.steps["vector"] += num_envs
            self.episodes["vector"] += int(done.sum())  # the autoresets of this step
            self.record(index, elapsed, -1)
            at = f"{where} batch step {b}"
            self.check_output(at, obs, rewards, info)
            expected = np.where(done, 0, steps + 1)
            if not np.array_equal(info["steps"], expected):
                self.fail("steps count", f"{at}: {steps} -> {info['steps']} (done {done})")
            if np.any(rewards[done] != 0) or np.any(terminated[done] | truncated[done]):
                self.fail("autoreset step", f"{at}: reset slots gave reward or flags")
            clipped = np.any(np.abs(np.asarray(action, dtype=np.float64)) > 1, axis=1)
            if not np.array_equal(info["clipped"][~done], clipped[~done]):
                self.fail("clipped flag", f"{at}: {action!r} gave {info['clipped']}")
            steps = info["steps"].copy()
            done = terminated | truncated
        self.sample()

    # ---- standalone GPIS -----------------------------------------------------------------
    def fill_gpis(self, capacity: int) -> None:
        """Fills a ``Gpis`` to ``max_rows`` with repeated adds, checks it, clears, refills."""
        width = setting("cupboard_width")["default"]
        depth = setting("cupboard_depth")["default"]
        bounds = ((-width / 2, width / 2), (0.0, depth))
        low, high = np.array([bounds[0][0], bounds[1][0]]), np.array([bounds[0][1], bounds[1][1]])
        gpis = Gpis(bounds=bounds, shape=setting("grid_shape")["default"], max_rows=capacity)
        where = f"Gpis(max_rows={capacity})"
        rng = self.rng
        for cycle in range(2):
            # Repeated mixed adds until one would exceed max_rows.
            for _ in range(100 * capacity):
                before = gpis.n_rows
                try:
                    choice = rng.integers(3)
                    if choice == 0:
                        points = rng.uniform(low, high, (int(rng.integers(1, 9)), 2))
                        noise = 0.0 if rng.random() < 0.2 else 0.002
                        if noise == 0.0:  # exact duplicates: rejected as degenerate
                            points = np.vstack([points, points[:1]])
                        gpis.add_values(points, noise_std=noise)
                    elif choice == 1:
                        count = int(rng.integers(1, 4))
                        normals = rng.normal(size=(count, 2)) + 1e-3
                        gpis.add_contacts(rng.uniform(low, high, (count, 2)), normals)
                    else:
                        gpis.add_circle_prior(rng.uniform(low + 0.05, high - 0.05))
                except ValueError as error:
                    what = "capacity" if "capacity" in str(error) else str(error)[:60]
                    self.expected[f"ValueError: Gpis {what}"] += 1
                    if gpis.n_rows != before:
                        self.fail("Gpis adds nothing at capacity", f"{where}: {error}")
                    break
                except Exception as error:
                    self.unexpected[type(error).__name__] += 1
                    self.fail("only documented exceptions", f"{where}: {error!r}")
                    break
            # Top up value by value to exactly max_rows.
            for _ in range(10 * capacity):
                if gpis.free_rows == 0:
                    break
                gpis.add_values(rng.uniform(low, high, (1, 2)))
            self.gpis["rows added"] += gpis.n_rows
            if gpis.n_rows != capacity or gpis.free_rows != 0:
                self.fail("Gpis fills to max_rows", f"{where}: n_rows={gpis.n_rows}")
            try:
                gpis.add_values(rng.uniform(low, high, (1, 2)))
            except ValueError:
                self.expected["ValueError: Gpis capacity"] += 1
            else:
                self.fail("Gpis refuses past max_rows", f"{where}: a value was added")
            if gpis.n_rows > capacity:
                self.fail("Gpis fills to max_rows", f"{where}: n_rows={gpis.n_rows}")
            mean, variance = gpis.predict(rng.uniform(low, high, (64, 2)))
            if nonfinite([gpis.mean, gpis.variance, mean, variance]):
                self.fail("all finite", f"{where}: the full map holds NaN or inf")
            if gpis.variance.min() < 0 or variance.min() < 0:
                self.fail("Gpis variance >= 0", f"{where}: negative variance")
            self.gpis["fills"] += 1
            gpis.clear()
            if gpis.n_rows != 0 or gpis.free_rows != capacity:
                self.fail("Gpis clears", f"{where} cycle {cycle}: n_rows={gpis.n_rows}")
        self.sample()

    # ---- construction churn --------------------------------------------------------------
    def churn(self) -> None:
        """Builds, steps and closes an env of every kind (a leak per env would show)."""
        for mode in MAP_MODES:
            env = gym.make(ENV_ID, map=mode)
            (seed,) = self.take_seeds(1)
            env.reset(seed=seed)
            self.episodes["churn"] += 1
            for _ in range(5):
                obs, reward, _, _, info = env.step(self.action("random", env, (3,), self.rng))
                self.check_output(f"churn {mode} seed={seed}", obs, reward, info)
                self.steps["churn"] += 1
            env.close()
            for size in self.scale.vector_sizes:
                vector = gym.make_vec(
                    ENV_ID, num_envs=size, vectorization_mode="vector_entry_point", map=mode
                )
                vector.reset(seed=self.take_seeds(size))
                self.episodes["churn"] += size
                for _ in range(5):
                    vector.step(self.action("random", vector, (size, 3), self.rng))
                    self.steps["churn"] += size
                vector.close()
        self.sample()

    # ---- the run -------------------------------------------------------------------------
    def build_envs(self) -> None:
        for config in self.configs:
            if config.num_envs is None:
                config.env = gym.make(ENV_ID, map=config.mode, **config.settings)
            else:
                config.env = self.vector_env(config)

    def vector_env(self, config: Config) -> Any:
        # One env per (mode, size, copy), shared by the action kinds.
        for other in self.configs:
            if (
                other.env is not None
                and other.num_envs == config.num_envs
                and other.mode == config.mode
                and other.copy == config.copy
            ):
                return other.env
        return gym.make_vec(
            ENV_ID,
            num_envs=config.num_envs,
            vectorization_mode="vector_entry_point",
            copy=config.copy,
            map=config.mode,
        )

    def run(self) -> None:
        self.start_vector_control()
        try:
            self._run()
        finally:
            self.stop_vector_control()

    def _run(self) -> None:
        self.sample()
        self.rss_start, self.live_start = live_rss_bytes(), live_heap_bytes()
        self.build_envs()
        first_seed = self.next_seed
        references: dict[int, int] = {}
        for round_ in range(self.scale.rounds):
            self.round = round_
            if self.scale.replay:
                self.next_seed = first_seed
            for index, config in enumerate(self.configs):
                if config.num_envs is None:
                    for episode in range(self.scale.episodes):
                        if episode == 0 and index in references and not self.scale.replay:
                            seed = references[index]  # the reference episode, replayed
                        else:
                            (seed,) = self.take_seeds(1)
                            references.setdefault(index, seed)
                        self.single_episode(index, config, seed)
                else:
                    self.vector_segment(index, config)
            for capacity in self.scale.gpis_capacities:
                self.fill_gpis(capacity)
            self.churn()
            self.sample()  # the end of the round: the same point every round
            if self.round == self.scale.warm_rounds - 1:
                self.warm_steps = self.total_steps()
                self.warm_time = time.perf_counter() - self.start
            _, _, trimmed, _, live, _, _ = self.mem[self.mem_count - 1]
            self.log(
                f"  round {self.round + 1}/{self.scale.rounds}"
                f"{' (warm-up)' if self.round < self.scale.warm_rounds else ''}: "
                f"{time.perf_counter() - self.start:7.1f} s, {self.total_steps():,} steps, "
                f"{sum(self.episodes[k] for k in ('single', 'vector', 'churn')):,} episodes, "
                f"RSS after trim {trimmed / 2**20:.1f} MiB"
                + (f", live heap {live / 2**20:.1f} MiB" if live >= 0 else "")
                + (f", {sum(self.failures.values())} failures" if self.failures else "")
            )
        self.elapsed = time.perf_counter() - self.start
        for config in self.configs:
            if config.env is not None:
                config.env.close()
                config.env = None


@dataclasses.dataclass
class SoakResult:
    """What a soak found: ``checks`` (name -> (passed, detail)), ``figures`` and ``text``."""

    checks: dict[str, tuple[bool, str]]
    figures: dict[str, Any]
    text: str
    soak: Soak | None = None

    @property
    def passed(self) -> bool:
        return all(ok for ok, _ in self.checks.values())


def median(values: np.ndarray) -> float:
    return float(np.median(values)) if len(values) else math.nan


def analyse(soak: Soak) -> SoakResult:
    """The checks and figures of a finished soak."""
    n = soak.records
    ns, cfg = soak.step_ns[:n], soak.step_config[:n]
    index, rounds = soak.step_index[:n], soak.step_round[:n]
    touch = soak.step_touch[:n]
    mem = soak.mem[: soak.mem_count]
    control = soak.control[: soak.control_count]
    scale, warm = soak.scale, soak.scale.warm_rounds
    lines: list[str] = []
    checks: dict[str, tuple[bool, str]] = {}
    informational: dict[str, tuple[bool, str]] = {}

    def check(name: str, ok: bool, detail: str) -> None:
        (informational if name in scale.informational else checks)[name] = (ok, detail)

    total = soak.total_steps()
    episodes = sum(soak.episodes[k] for k in ("single", "vector", "churn"))
    lines.append(
        f"soak ({scale.name}): {scale.rounds} rounds, rounds 1-{warm} the warm-up "
        f"({100 * WARM_UP_FRACTION:.0f} % of the rounds, rounded up); "
        f"{os.cpu_count()} cores, shared"
    )
    lines.append(
        f"steps: {total:,} in {soak.elapsed:.1f} s = {total / soak.elapsed:,.0f} steps/s "
        f"(single env {soak.steps['single']:,}, vector env {soak.steps['vector']:,}, "
        f"twins {soak.steps['twin']:,}, churn {soak.steps['churn']:,})"
    )
    lines.append(
        f"episodes: {episodes:,} (single {soak.episodes['single']:,}, vector "
        f"{soak.episodes['vector']:,} with autoresets, churn {soak.episodes['churn']:,}; "
        f"twins {soak.episodes['twin']:,}); seeds given: {soak.seeds_given:,} distinct, "
        f"{soak.seed_base}..{soak.max_seed} (training range [2**32, 2**63))"
    )
    lines.append(
        f"covered: map modes {', '.join(MAP_MODES)}; action kinds {', '.join(ACTION_KINDS)}; "
        f"vector sizes {', '.join(map(str, scale.vector_sizes))} (x4 with copy=False)"
    )
    lines.append(
        f"GPIS at capacity: {soak.capacity_episodes:,} episodes with max_rows in "
        f"{soak.capacity_rows}, {soak.capacity_reached:,} reached it; standalone Gpis: "
        f"{soak.gpis['fills']:,} fills to max_rows in {scale.gpis_capacities}, "
        f"{soak.gpis['rows added']:,} rows"
    )
    # Memory: per round, the peak of the round's samples and the value at its end.
    mib = 2**20
    mem_rounds = mem[:, 6]
    live_measured = bool((mem[:, 4] >= 0).all()) and LIVE_HEAP_NOTE is None
    lines.append(
        f"memory per round ({len(mem):,} samples after episodes, segments, fills and rounds; "
        f"MiB, peak of the round / at its end; rounds 1-{warm} the warm-up):"
    )
    lines.append(
        f"  {'round':>7s} {'steps':>10s}  {'live heap (mallinfo2)':>21s}  "
        f"{'RSS after malloc_trim':>21s}  {'Python blocks':>13s}  {'raw RSS peak':>12s}"
    )
    per_round: list[dict[str, float]] = []
    for r in range(scale.rounds):
        rows = mem[mem_rounds == r]
        if not len(rows):
            continue
        entry = {
            "round": r + 1,
            "steps": float(rows[-1, 1]),
            "live_peak_mib": float(rows[:, 4].max() / mib) if live_measured else math.nan,
            "live_end_mib": float(rows[-1, 4] / mib) if live_measured else math.nan,
            "rss_trim_peak_mib": float(rows[:, 2].max() / mib),
            "rss_trim_end_mib": float(rows[-1, 2] / mib),
            "python_blocks_end": float(rows[-1, 5]),
            "rss_raw_peak_mib": float(rows[:, 3].max() / mib),
        }
        per_round.append(entry)
        live_cell = (
            f"{entry['live_peak_mib']:9.1f} / {entry['live_end_mib']:9.1f}"
            if live_measured
            else f"{'-':>21s}"
        )
        lines.append(
            f"  {r + 1:5d}{' w' if r < warm else '  '} {entry['steps']:10,.0f}  {live_cell}  "
            f"{entry['rss_trim_peak_mib']:9.1f} / {entry['rss_trim_end_mib']:9.1f}  "
            f"{entry['python_blocks_end']:13,.0f}  {entry['rss_raw_peak_mib']:12.1f}"
        )
    reference_rows = mem[mem_rounds == warm - 1]
    after_rows = mem[mem_rounds >= warm]

    def memory_check(name: str, label: str, column: int, limit: float, start: float) -> dict:
        """Checks that a memory column's largest value after the warm-up is within
        ``limit`` of its peak in the warm-up's last round; returns its figures."""
        if not len(reference_rows) or not len(after_rows):
            reference = largest = grew = math.nan
        else:
            reference = float(reference_rows[:, column].max())
            largest = float(after_rows[:, column].max())
            grew = largest / reference - 1
        detail = (
            f"{label} peak {reference / mib:.1f} MiB in round {warm} (end of the warm-up), "
            f"largest after it {largest / mib:.1f} MiB: growth {100 * grew:+.2f} % "
            f"(limit {100 * limit:.0f} %)"
        )
        check(name, grew <= limit, detail)
        return {
            "start_mib": start / mib,
            "warm_up_peak_mib": reference / mib,
            "max_after_warm_up_mib": largest / mib,
            "growth_after_warm_up": grew,
        }

    memory_figures: dict[str, Any] = {"per_round": per_round, "samples": len(mem)}
    if live_measured:
        memory_figures["live_heap"] = memory_check(
            "no leak: live heap flat", "live heap", 4, LIVE_GROWTH_LIMIT, soak.live_start
        )
    else:
        lines.append(f"  note: {LIVE_HEAP_NOTE}; the leak check is skipped")
    memory_figures["rss_after_trim"] = {
        **memory_check(
            "resident memory flat",
            "RSS after malloc_trim",
            2,
            RSS_GROWTH_LIMIT,
            soak.rss_start,
        ),
        "end_mib": float(mem[-1, 2] / mib),
    }
    # Step time through the run, per configuration.
    post = list(range(warm, scale.rounds))
    third = max(1, math.ceil(len(post) / 3))
    early_rounds, late_rounds = post[:third], post[-third:]

    def control_ratio_of(table: np.ndarray) -> float:
        """A reference workload's late-window median over its early-window one."""
        table_rounds = table[:, 1]
        ratio = median(table[np.isin(table_rounds, late_rounds), 2]) / median(
            table[np.isin(table_rounds, early_rounds), 2]
        )
        return ratio if math.isfinite(ratio) else 1.0

    control_ratio = control_ratio_of(control)
    vector_ratio = control_ratio_of(soak.vcontrol[: soak.vcontrol_count])
    lines.append(
        f"step time by episode count (median µs per step call in rounds "
        f"{[r + 1 for r in early_rounds]} -> {[r + 1 for r in late_rounds]}; reference "
        f"workloads' ratios, divided out when above 1: single-threaded {control_ratio:.2f} "
        f"(single envs), 16-env vector segment {vector_ratio:.2f} (vector envs); limit "
        f"{RUN_DRIFT_LIMIT}; single envs: every kind, {scale.episodes} episodes a round; "
        f"vector envs: free-motion kinds, contact-rich ones shown only, a segment's few "
        f"episodes set how much of it touches jars):"
    )
    worst, compared = (0.0, ""), 0
    for i, config in enumerate(soak.configs):
        mine = cfg == i
        early = ns[mine & np.isin(rounds, early_rounds)]
        late = ns[mine & np.isin(rounds, late_rounds)]
        if len(early) < MIN_BIN_STEPS or len(late) < MIN_BIN_STEPS:
            lines.append(f"  {config.name:44s} too few steps ({len(early)}, {len(late)})")
            continue
        raw = median(late) / median(early)
        ratio = vector_ratio if config.num_envs is not None else control_ratio
        adjusted = raw / max(ratio, 1.0)
        shown = config.num_envs is not None and config.kind not in FREE_MOTION_KINDS
        if not shown:
            compared += 1
            worst = max(worst, (adjusted, config.name))
        lines.append(
            f"  {config.name:44s} {median(early) / 1e3:8.1f} -> {median(late) / 1e3:8.1f}"
            f"  x{raw:.2f}"
            + (f" (x{adjusted:.2f} after control)" if ratio > 1 else "")
            + (" (contact-rich, shown)" if shown else "")
        )
    check(
        "step time flat through the run",
        compared > 0 and worst[0] <= RUN_DRIFT_LIMIT,
        f"{compared} configurations compared, worst x{worst[0]:.2f} ({worst[1]}), "
        f"limit {RUN_DRIFT_LIMIT}",
    )
    # Step time by step index within the episode, single-env configurations.
    bins = int(setting("max_steps")["default"]) // INDEX_BIN
    lines.append(
        f"step time by step index (after the warm-up: share of steps touching a jar, episodes "
        f"used, median µs per bin of {INDEX_BIN} steps; free-motion kinds "
        f"({', '.join(FREE_MOTION_KINDS)}): only the episodes that never touched a jar, last "
        f"bin with >= {MIN_BIN_STEPS} steps over the first, limit {INDEX_DRIFT_LIMIT}; "
        f"contact-rich kinds: all episodes, shown only, their later steps touch jars and cost "
        f"more):"
    )
    worst, compared = (0.0, ""), 0
    for i, config in enumerate(soak.configs):
        if config.num_envs is not None:
            continue
        mine = (cfg == i) & (rounds >= warm)
        touching = f"{100 * (touch[mine] & 1).mean():3.0f} %" if mine.any() else "  - %"
        free = config.kind in FREE_MOTION_KINDS
        if free:  # only the episodes that never touched a jar
            mine &= (touch & 2) == 0
        kept = int((mine & (index == 0)).sum())  # episodes
        medians, counts = [], []
        for b in range(bins):
            in_bin = ns[mine & (index // INDEX_BIN == b)]
            medians.append(median(in_bin))
            counts.append(len(in_bin))
        usable = [b for b in range(bins) if counts[b] >= MIN_BIN_STEPS]
        cells = " ".join(
            f"{m / 1e3:6.0f}" if c >= MIN_BIN_STEPS else "     -"
            for m, c in zip(medians, counts, strict=True)
        )
        ratio = medians[usable[-1]] / medians[0] if len(usable) >= 2 and usable[0] == 0 else None
        label = f"  {config.name:40s} {touching} {kept:5d} {cells}"
        if not free:
            lines.append(f"{label}  x{ratio:.2f} (contact-rich, shown)" if ratio else label)
        elif ratio is None:
            lines.append(f"{label}  (too few)")
        else:
            compared += 1
            worst = max(worst, (ratio, config.name))
            lines.append(f"{label}  x{ratio:.2f}")
    check(
        "step time flat by step index",
        compared > 0 and worst[0] <= INDEX_DRIFT_LIMIT,
        f"{compared} free-motion configurations compared, worst x{worst[0]:.2f} "
        f"({worst[1]}), limit {INDEX_DRIFT_LIMIT}",
    )
    # Exceptions and the per-step checks.
    lines.append(
        "documented exceptions: "
        + (", ".join(f"{k} {v:,}" for k, v in sorted(soak.expected.items())) or "none")
    )
    lines.append(
        "other exceptions: "
        + (", ".join(f"{k} {v:,}" for k, v in sorted(soak.unexpected.items())) or "none")
    )
    per_step = [
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
    ]
    for name in [*per_step, *sorted(set(soak.failures) - set(per_step))]:
        count = soak.failures[name]
        checks[name] = (count == 0, f"{count:,} failures" if count else "no failures")
    reached = soak.capacity_reached > 0
    checks["GPIS reaches max_rows in episodes"] = (
        reached,
        f"{soak.capacity_reached:,} of {soak.capacity_episodes:,} episodes",
    )
    invalid = sum(soak.expected.values())
    checks["invalid actions tried"] = (invalid > 0, f"{invalid:,} documented errors raised")
    if soak.scale.name == "full":
        checks["size: >= 10**6 steps, >= 10**4 seeds"] = (
            total >= 10**6 and soak.seeds_given >= 10**4,
            f"{total:,} steps, {soak.seeds_given:,} seeds",
        )
    lines.append("checks:")
    for name, (ok, detail) in checks.items():
        lines.append(f"  {'PASS' if ok else 'FAIL'}  {name}: {detail}")
    if informational:
        lines.append(
            f"informational at the {scale.name} scale (measured, not asserted: too short to "
            "mean much; the full run asserts them):"
        )
        for name, (ok, detail) in informational.items():
            lines.append(f"  {'pass' if ok else 'over'}  {name}: {detail}")
    for message in soak.messages:
        lines.append(f"  failure: {message}")
    passed = all(ok for ok, _ in checks.values())
    lines.append(f"soak {'PASSED' if passed else 'FAILED'}")
    figures = {
        "scale": dataclasses.asdict(soak.scale),
        "steps": total,
        "steps_by_kind": dict(soak.steps),
        "episodes": episodes,
        "episodes_by_kind": dict(soak.episodes),
        "seeds_given": soak.seeds_given,
        "seconds": soak.elapsed,
        "steps_per_s": total / soak.elapsed,
        "warm_up_rounds": warm,
        "memory": memory_figures,
        "control_ratio": control_ratio,
        "vector_control_ratio": vector_ratio,
        "documented_exceptions": dict(soak.expected),
        "other_exceptions": dict(soak.unexpected),
        "failures": dict(soak.failures),
        "failure_messages": soak.messages,
        "capacity_episodes": soak.capacity_episodes,
        "capacity_reached": soak.capacity_reached,
        "gpis": dict(soak.gpis),
        "checks": {k: {"passed": ok, "detail": d} for k, (ok, d) in checks.items()},
        "informational": {
            k: {"within_limit": ok, "detail": d} for k, (ok, d) in informational.items()
        },
        "passed": passed,
    }
    return SoakResult(checks, figures, "\n".join(lines), soak)


def plot(result: SoakResult, out: Path) -> str:
    """Writes RSS and step time over the run to ``out``; returns what it did."""
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        return "matplotlib is not installed: no plot (pip install matplotlib)"
    soak = result.soak
    assert soak is not None
    mem = soak.mem[: soak.mem_count]
    n = soak.records
    ns, cfg, total = soak.step_ns[:n], soak.step_config[:n], soak.step_total[:n]
    fig, (top, bottom) = plt.subplots(2, 1, figsize=(9, 6.5), sharex=True)
    last_warm = mem[:, 6] == soak.scale.warm_rounds - 1
    series = [(2, "RSS after malloc_trim", "k", RSS_GROWTH_LIMIT)]
    if (mem[:, 4] >= 0).all():
        series.append((4, "live heap (mallinfo2)", "tab:blue", LIVE_GROWTH_LIMIT))
    for column, label, color, limit in series:
        top.plot(mem[:, 1], mem[:, column] / 2**20, lw=1, color=color, label=label)
        if last_warm.any():
            top.axhline(
                mem[last_warm, column].max() / 2**20 * (1 + limit), color=color, ls="--",
                lw=0.8, label=f"{label}: warm-up peak +{100 * limit:.0f} %",
            )  # fmt: skip
    top.axvline(soak.warm_steps, color="grey", ls=":", label="end of warm-up")
    top.set_ylabel("memory, MiB")
    top.legend(loc="lower right", fontsize=7)
    chunks = 60
    for label, chosen in [
        *[(f"single env, map={m}", [c.num_envs is None and c.mode == m for c in soak.configs])
          for m in MAP_MODES],
        ("vector env, per batch step", [c.num_envs is not None for c in soak.configs]),
    ]:  # fmt: skip
        mask = np.asarray(chosen)[cfg]
        if not mask.any():
            continue
        x, y = total[mask], ns[mask] / 1e3
        edges = np.linspace(0, len(x), chunks + 1).astype(int)
        xs = [x[a:b].mean() for a, b in itertools.pairwise(edges) if b > a]
        ys = [np.median(y[a:b]) for a, b in itertools.pairwise(edges) if b > a]
        bottom.plot(xs, ys, lw=1, marker=".", label=label)
    bottom.axvline(soak.warm_steps, color="grey", ls=":")
    bottom.set_yscale("log")
    bottom.set_ylabel("median step time, µs")
    bottom.set_xlabel("environment steps so far")
    bottom.legend(fontsize=8)
    top.set_title(
        f"CupboardSearch-v0 soak ({soak.scale.name}): {soak.total_steps():,} steps, "
        f"{soak.seeds_given:,} seeds",
        fontsize=10,
    )
    fig.tight_layout()
    out.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(out, dpi=110)
    plt.close(fig)
    return f"plot: {out}"


def run_soak(scale: Scale = QUICK, seed_base: int = TRAIN_SEEDS[0], log: Any = print) -> SoakResult:
    """Runs a soak of ``scale`` (``QUICK`` or ``FULL``) and returns its checks and figures."""
    soak = Soak(scale, seed_base=seed_base, log=log)
    log(
        f"soak ({scale.name}): {scale.rounds} rounds of {len(soak.configs)} configurations, "
        f"{scale.episodes} episodes per single-env one and {scale.batch_steps} batch steps "
        "per vector-env one"
    )
    soak.run()
    return analyse(soak)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="the ~30 s version")
    parser.add_argument("--rounds", type=int, help="override the number of rounds")
    parser.add_argument("--seed-base", type=int, default=TRAIN_SEEDS[0],
                        help="first layout seed (training range [2**32, 2**63))")  # fmt: skip
    parser.add_argument("--out", type=Path, default=Path("results/soak.png"), help="plot path")
    parser.add_argument("--json", type=Path, help="write the figures as JSON here")
    args = parser.parse_args(argv)
    scale = QUICK if args.quick else FULL
    if args.rounds is not None:
        if args.rounds < 2:
            parser.error("--rounds must be at least 2 (the warm-up and one more)")
        scale = dataclasses.replace(scale, rounds=args.rounds)
    result = run_soak(scale, seed_base=args.seed_base, log=lambda s: print(s, flush=True))
    print(result.text)
    print(plot(result, args.out))
    if args.json:
        args.json.parent.mkdir(parents=True, exist_ok=True)
        args.json.write_text(json.dumps(result.figures, indent=2, default=float) + "\n")
        print(f"figures: {args.json}")
    return 0 if result.passed else 1


if __name__ == "__main__":
    sys.exit(main())
