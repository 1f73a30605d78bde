"""What a soak records as it runs: every step's time (with its configuration, step index,
round and whether it touched a jar) and the memory samples, in arrays allocated before the
warm-up so that the soak's own bookkeeping does not grow the memory it measures; the
counters of steps, episodes, exceptions and failures; the layout seeds handed out (from the
training range, ``tactile_search.seed_ranges.TRAINING``); and the checks every output and
every refused action must pass."""

from __future__ import annotations

import math
import sys
import time
from collections import Counter
from collections.abc import Callable
from typing import Any

import numpy as np

from benchmarks.soak.memory import live_heap_bytes, live_rss_bytes, rss_bytes
from benchmarks.soak.plan import Config, Scale, setting
from benchmarks.soak.reference import ReferenceTimings
from tactile_search.seed_ranges import TRAINING

#: Failure messages kept (all are counted).
MAX_FAILURE_MESSAGES = 30


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


class Records:
    """The records of one soak run of ``configs`` at ``scale``; seeds from ``seed_base``."""

    def __init__(
        self, scale: Scale, configs: list[Config], seed_base: int, log: Callable[[str], Any]
    ) -> None:
        self.scale = scale
        self.configs = configs
        self.log = log
        self.seed_base = self.next_seed = self.max_seed = seed_base
        self.seeds_given = 0
        self.digests: dict[tuple[int, int], tuple] = {}
        self._allocate_steps()
        self._allocate_samples()
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

    def _allocate_steps(self) -> None:
        """One slot per step the run can take (every episode at ``max_steps``)."""
        max_steps = setting("max_steps")["default"]
        single = sum(c.num_envs is None for c in self.configs)
        vector = len(self.configs) - single
        scale = self.scale
        capacity = scale.rounds * (single * scale.episodes * max_steps + vector * scale.batch_steps)
        self.step_ns = np.full(capacity + 1, -1, dtype=np.int64)
        self.step_config = np.full(capacity + 1, -1, dtype=np.int16)
        self.step_index = np.full(capacity + 1, -1, dtype=np.int16)
        self.step_round = np.full(capacity + 1, -1, dtype=np.int16)
        self.step_total = np.full(capacity + 1, -1, dtype=np.int64)  # env steps so far
        # Bit 0: this step touched a jar (info["contacts"] > 0); bit 1: its episode did.
        self.step_touch = np.full(capacity + 1, 0, dtype=np.int8)
        self.records = 0

    def _allocate_samples(self) -> None:
        """The memory samples and the reference workloads' timings."""
        single = sum(c.num_envs is None for c in self.configs)
        scale = self.scale
        samples = scale.rounds * (single * scale.episodes + 4 * len(self.configs) + 64) + 16
        #: Memory samples: elapsed s, env steps, RSS after malloc_trim, raw RSS, live heap
        #: bytes (mallinfo2), Python's allocated blocks, round.
        self.mem = np.full((samples, 7), -1.0)
        self.mem_count = 0
        self.reference = ReferenceTimings(self.log)

    # ---- seeds ---------------------------------------------------------------------------
    def take_seeds(self, count: int) -> list[int]:
        """The next ``count`` layout seeds (in replay mode, round 1's again)."""
        seeds = list(range(self.next_seed, self.next_seed + count))
        if seeds[0] < TRAINING[0] or seeds[-1] >= TRAINING[1]:
            raise ValueError(f"seeds {seeds[0]}..{seeds[-1]} leave the training range")
        self.next_seed += count
        self.max_seed = max(self.max_seed, self.next_seed - 1)
        self.seeds_given = self.max_seed - self.seed_base + 1
        return seeds

    # ---- counts and samples --------------------------------------------------------------
    def fail(self, check: str, message: str) -> None:
        self.failures[check] += 1
        if len(self.messages) < MAX_FAILURE_MESSAGES:
            self.messages.append(f"{check}: {message}")

    def total_steps(self) -> int:
        return sum(self.steps.values())

    def sample(self) -> None:
        """A memory sample, and now and then a timing of the reference workloads."""
        now = time.perf_counter() - self.start
        if self.mem_count < len(self.mem):
            raw = rss_bytes()
            trimmed = live_rss_bytes()
            self.mem[self.mem_count] = (
                now, self.total_steps(), trimmed, raw, live_heap_bytes(),
                sys.getallocatedblocks(), self.round,
            )  # fmt: skip
            self.mem_count += 1
        self.reference.maybe_time(now, self.round)

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

    # ---- the checks of every output and refused action -----------------------------------
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
