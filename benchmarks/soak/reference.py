"""The two fixed reference workloads timed through the run, and the load normalisation
they give.

The machine is shared and noisy, so a slowdown the reference workloads also show (machine
load) is divided out of the step-time drift: a single-threaded one (Python and numpy) for
the single envs, and a fixed segment of a 16-env vector env without a map (same seeds, same
free-motion actions; in a spawned process of its own, so it neither touches the heap being
measured nor depends on it) for the vector envs, whose steps run on the core's worker
threads and so also feel a load on the second core that the single-threaded workload does
not (in one full run the late rounds took up to 45 % longer while single-env steps and the
single-threaded workload did not change). Medians only, ``time.perf_counter_ns``.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from typing import Any

import gymnasium as gym
import numpy as np

from tactile_search import ENV_ID
from tactile_search.seed_ranges import TRAINING

#: Seconds between timings of the reference workload.
CONTROL_EVERY_S = 0.5
#: Seconds between timings of the parallel reference workload (a fixed vector-env segment).
VECTOR_CONTROL_EVERY_S = 2.0
#: Its size and length: slots, timed batch steps.
VECTOR_CONTROL_SHAPE = (16, 10)
#: Rows of each timing table (elapsed s, round, ns), allocated before the run.
CONTROL_ROWS = 20_000


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
    seeds = list(range(TRAINING[0], TRAINING[0] + size))
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


class ReferenceTimings:
    """Both reference workloads' timings through a run: ``control`` (single-threaded) and
    ``vcontrol`` (the vector segment in its own process), each rows of (elapsed s, round,
    ns) in a table allocated up front."""

    def __init__(self, log: Callable[[str], Any]) -> None:
        self.log = log
        self.control = np.full((CONTROL_ROWS, 3), -1.0)
        self.control_count = 0
        self.last_control = -math.inf
        self.vcontrol = np.full((CONTROL_ROWS, 3), -1.0)  # the parallel one: the same
        self.vcontrol_count = 0
        self.last_vcontrol = -math.inf
        self.vcontrol_conn: Any = None  # the pipe to vector_control_worker's process
        self.vcontrol_process: Any = None
        self.vcontrol_ready = False

    def single_table(self) -> np.ndarray:
        """The single-threaded workload's rows so far."""
        return self.control[: self.control_count]

    def vector_table(self) -> np.ndarray:
        """The vector workload's rows so far."""
        return self.vcontrol[: self.vcontrol_count]

    def maybe_time(self, now: float, round_: int) -> None:
        """Times each workload if its interval has passed since its last timing."""
        if now - self.last_control >= CONTROL_EVERY_S and self.control_count < len(self.control):
            self.control[self.control_count] = (now, round_, control_ns())
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
                self.vcontrol[self.vcontrol_count] = (now, round_, conn.recv())
            except (EOFError, OSError) as error:  # the worker died: carry on without it
                self.log(f"  the parallel reference workload stopped ({error!r})")
                self.vcontrol_ready = False
                return
            self.vcontrol_count += 1
            self.last_vcontrol = now

    def start_vector(self) -> None:
        """Starts vector_control_worker's process (spawned: the core has threads)."""
        import multiprocessing

        context = multiprocessing.get_context("spawn")
        self.vcontrol_conn, child = context.Pipe()
        self.vcontrol_process = context.Process(
            target=vector_control_worker, args=(child,), daemon=True
        )
        self.vcontrol_process.start()

    def stop_vector(self) -> None:
        """Stops the vector workload's process (terminated if it does not end in 10 s)."""
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


def median(values: np.ndarray) -> float:
    """The median, NaN for no values."""
    return float(np.median(values)) if len(values) else math.nan


def load_ratio(table: np.ndarray, early_rounds: list[int], late_rounds: list[int]) -> float:
    """A reference workload's late-window median over its early-window one (1 when either
    window has no timing): the machine's slowdown, divided out of the step times."""
    table_rounds = table[:, 1]
    ratio = median(table[np.isin(table_rounds, late_rounds), 2]) / median(
        table[np.isin(table_rounds, early_rounds), 2]
    )
    return ratio if math.isfinite(ratio) else 1.0
