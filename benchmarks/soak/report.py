"""A soak's result and how it is shown: ``SoakResult`` (checks, figures, text), the
PASS / FAIL lines that end the text, and the plot of the live heap, RSS after the trim and
step time over the run (``--out``, if matplotlib is installed)."""

from __future__ import annotations

import dataclasses
import itertools
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from benchmarks.soak.plan import LIVE_GROWTH_LIMIT, RSS_GROWTH_LIMIT
from tactile_search import ENV_ID
from tactile_search.envs.config import MAP_MODES

if TYPE_CHECKING:
    from benchmarks.soak.workloads import Soak

#: The env's name without its namespace, in the plot's title.
ENV_NAME = ENV_ID.rpartition("/")[2]


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


def verdict_lines(
    scale_name: str,
    checks: dict[str, tuple[bool, str]],
    informational: dict[str, tuple[bool, str]],
    messages: list[str],
    passed: bool,
) -> list[str]:
    """Each check's PASS or FAIL, the informational ones, the failure messages kept and the
    verdict."""
    lines = ["checks:"]
    for name, (ok, detail) in checks.items():
        lines.append(f"  {'PASS' if ok else 'FAIL'}  {name}: {detail}")
    if informational:
        lines.append(
            f"informational at the {scale_name} scale (measured, not asserted: too short to "
            "mean much; the full run asserts them):"
        )
        for name, (ok, detail) in informational.items():
            lines.append(f"  {'pass' if ok else 'over'}  {name}: {detail}")
    for message in messages:
        lines.append(f"  failure: {message}")
    lines.append(f"soak {'PASSED' if passed else 'FAILED'}")
    return lines


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
    fig, (top, bottom) = plt.subplots(2, 1, figsize=(9, 6.5), sharex=True)
    plot_memory(top, soak)
    plot_step_time(bottom, soak)
    top.set_title(
        f"{ENV_NAME} soak ({soak.scale.name}): {soak.total_steps():,} steps, "
        f"{soak.seeds_given:,} seeds",
        fontsize=10,
    )
    fig.tight_layout()
    out.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(out, dpi=110)
    plt.close(fig)
    return f"plot: {out}"


def plot_memory(ax: Any, soak: Soak) -> None:
    """RSS after the trim and the live heap against the steps, with each one's limit."""
    mem = soak.mem[: soak.mem_count]
    last_warm = mem[:, 6] == soak.scale.warm_rounds - 1
    series = [(2, "RSS after malloc_trim", "k", RSS_GROWTH_LIMIT)]
    if (mem[:, 4] >= 0).all():
        series.append((4, "live heap (mallinfo2)", "tab:blue", LIVE_GROWTH_LIMIT))
    for column, label, color, limit in series:
        ax.plot(mem[:, 1], mem[:, column] / 2**20, lw=1, color=color, label=label)
        if last_warm.any():
            ax.axhline(
                mem[last_warm, column].max() / 2**20 * (1 + limit), color=color, ls="--",
                lw=0.8, label=f"{label}: warm-up peak +{100 * limit:.0f} %",
            )  # fmt: skip
    ax.axvline(soak.warm_steps, color="grey", ls=":", label="end of warm-up")
    ax.set_ylabel("memory, MiB")
    ax.legend(loc="lower right", fontsize=7)


def plot_step_time(ax: Any, soak: Soak, chunks: int = 60) -> None:
    """Median step time over the run in ``chunks`` chunks: single envs by map mode, and
    the vector envs per batch step."""
    n = soak.records
    ns, cfg, total = soak.step_ns[:n], soak.step_config[:n], soak.step_total[:n]
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
        ax.plot(xs, ys, lw=1, marker=".", label=label)
    ax.axvline(soak.warm_steps, color="grey", ls=":")
    ax.set_yscale("log")
    ax.set_ylabel("median step time, µs")
    ax.set_xlabel("environment steps so far")
    ax.legend(fontsize=8)
