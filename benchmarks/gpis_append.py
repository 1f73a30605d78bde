"""Time per GPIS update against the number of rows: incremental append vs full recompute.

The paper's Fig. 9 redone (``docs/DESIGN.md`` sections 3 and 5): for each map size n, the
time to add ONE contact (3 rows) through ``tactile_search.Gpis.add_contacts`` (the exact
incremental update) against ``Gpis.recompute_from_scratch()`` (what the paper does after
every new measurement) at the same n. The maps and the timing method are Fig. 9's,
``experiments.paper.gpis_timing`` (which documents them); this command prints the table,
checks the targets at n = 1000 and plots. The full-recompute map's ``memory_bytes`` is the
memory reported per n.

Method (one core, wall clock with ``time.perf_counter``, medians over repeats). The Rust
core runs its linear algebra with ``Par::Seq``, so thread settings (``OMP_NUM_THREADS`` and
the like) do not matter; the process is also pinned to one CPU where the OS allows it. The
host may be shared and noisy: compare medians, not single runs.

Usage (from the repository root)::

    python -m benchmarks.gpis_append --out results/gpis_append.png [--json results/gpis_append.json]
"""

from __future__ import annotations

import argparse
import os
import platform
import statistics
from pathlib import Path

import numpy as np

from benchmarks.performance_page import write_json
from experiments.paper.gpis_timing import (
    BOUNDS,
    DEFAULT_MAX_ROWS,
    build_map,
    time_appends,
    time_full,
)

TARGET_N = 1000
TARGET_APPEND_MS = 3.0
TARGET_RATIO = 50.0


def pin_to_one_cpu() -> str:
    """Pins this process to one CPU if the OS allows it; says what happened."""
    if not hasattr(os, "sched_setaffinity"):
        return "not pinned (no sched_setaffinity)"
    allowed = sorted(os.sched_getaffinity(0))
    os.sched_setaffinity(0, {allowed[-1]})
    return f"pinned to CPU {allowed[-1]} (of {len(allowed)} allowed)"


def plot(sizes: list[int], append_ms: list[float], full_ms: list[float], out: Path) -> None:
    """Saves time per update vs n (log time axis) as a PNG."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6.0, 4.0), dpi=150)
    ax.plot(sizes, full_ms, "o-", label="full recompute (paper)")
    ax.plot(sizes, append_ms, "s-", label="incremental append of one contact")
    ax.plot(
        [TARGET_N],
        [TARGET_APPEND_MS],
        "kx",
        markersize=9,
        label=f"append target: {TARGET_APPEND_MS:g} ms at n={TARGET_N}",
    )
    ax.set_yscale("log")
    ax.set_xlabel("number of rows n (measurements)")
    ax.set_ylabel("time per update [ms] (median)")
    ax.set_title("GPIS update time vs map size (one core)")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(loc="upper left")
    fig.tight_layout()
    out.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(out)
    plt.close(fig)


def parse_args(argv: list[str] | None = None) -> argparse.Namespace:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument(
        "--out", type=Path, default=Path("results/gpis_append.png"), help="PNG to write"
    )
    parser.add_argument(
        "--sizes",
        type=int,
        nargs="+",
        default=[100, 250, 500, 1000, 2000],
        help="numbers of rows n",
    )
    parser.add_argument("--repeats", type=int, default=15, help="timed appends per n")
    parser.add_argument("--full-repeats", type=int, default=5, help="timed full recomputes per n")
    parser.add_argument("--grid", type=int, default=64, help="grid side (grid x grid cells)")
    parser.add_argument("--seed", type=int, default=0, help="seed of the random rows")
    parser.add_argument("--json", type=Path, default=None, help="write the figures here too")
    args = parser.parse_args(argv)
    if args.repeats < 1 or args.full_repeats < 1:
        parser.error("--repeats and --full-repeats must be at least 1")
    if args.grid < 1 or any(n < 3 for n in args.sizes):
        parser.error("--grid must be positive and every size at least 3")
    if max(args.sizes) + 3 * max(1, max(args.sizes) // 150) > DEFAULT_MAX_ROWS:
        parser.error(f"sizes must leave room for the appends below {DEFAULT_MAX_ROWS} rows")
    return args


def main(argv: list[str] | None = None) -> None:
    args = parse_args(argv)
    sizes = sorted(set(args.sizes))
    pinning = pin_to_one_cpu()
    print(f"host: {platform.node()}, os.cpu_count() = {os.cpu_count()}, {pinning}")
    print("note: the machine is shared and noisy; numbers are medians of repeated runs")
    print(
        f"grid {args.grid}x{args.grid} = {args.grid**2} cells, bounds {BOUNDS}, "
        f"append repeats {args.repeats}, full-recompute repeats {args.full_repeats}"
    )
    header = (
        f"{'n':>6} {'append ms':>10} {'full ms':>10} {'full/append':>12} "
        f"{'memory MiB':>11} {'max|dmean|':>11}"
    )
    print(header)
    print("-" * len(header))
    append_ms, full_ms, rows = [], [], []
    for n in sizes:
        appends = time_appends(n, args.grid, args.repeats, args.seed)
        g = build_map(n, args.grid, max_rows=DEFAULT_MAX_ROWS, seed=args.seed)
        fulls = time_full(g, args.full_repeats)
        full_mean, _ = g.recompute_from_scratch()
        mismatch = float(np.max(np.abs(full_mean - g.mean)))
        append_ms.append(1e3 * statistics.median(appends))
        full_ms.append(1e3 * statistics.median(fulls))
        print(
            f"{n:>6} {append_ms[-1]:>10.3f} {full_ms[-1]:>10.2f} "
            f"{full_ms[-1] / append_ms[-1]:>12.1f} {g.memory_bytes / 2**20:>11.2f} "
            f"{mismatch:>11.2e}",
            flush=True,
        )
        rows.append({
            "n": n, "append_ms": append_ms[-1], "full_ms": full_ms[-1],
            "ratio": full_ms[-1] / append_ms[-1], "memory_mib": g.memory_bytes / 2**20,
            "max_abs_mean_difference": mismatch,
        })  # fmt: skip
    if TARGET_N in sizes:
        i = sizes.index(TARGET_N)
        ratio = full_ms[i] / append_ms[i]
        append_ok = "met" if append_ms[i] <= TARGET_APPEND_MS else "MISSED"
        ratio_ok = "met" if ratio >= TARGET_RATIO else "MISSED"
        print(
            f"targets at n={TARGET_N}: append {append_ms[i]:.3f} ms "
            f"(<= {TARGET_APPEND_MS} ms: {append_ok}), "
            f"full/append {ratio:.1f} (>= {TARGET_RATIO}: {ratio_ok})"
        )
    plot(sizes, append_ms, full_ms, args.out)
    print(f"saved {args.out}")
    if args.json is not None:
        figures = {"grid": args.grid, "pinning": pinning, "rows": rows}
        write_json(args.json, "benchmarks.gpis_append", argv, figures)


if __name__ == "__main__":
    main()
