"""The driver: runs the episodes, writes the table and the figures, updates the table block
of ``docs/PAPER.md``.

CLI: ``python -m experiments.paper --out docs/paper [--seeds N] [--first-seed S] [--tiny]``
(``make paper``). Layout seeds default to the first of the validation range
(``tactile_search.seed_ranges.VALIDATION``, ``docs/DESIGN.md`` §7), since the default prior is
chosen on them.
"""

from __future__ import annotations

import argparse
import statistics
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from experiments.paper.episodes import (
    DEFAULT_DEPTH_NOISE,
    DEPTH_NOISE_LEVELS,
    SHAPES,
    evaluate,
    maps_for,
    run_episode,
)
from experiments.paper.figures import fig3, fig4, fig9, fig_maps
from experiments.paper.gpis_timing import DEFAULT_MAX_ROWS, build_map, time_appends, time_full
from experiments.paper.priors import POSITIVE_MEAN, option_named
from experiments.paper.tables import (
    choose_default,
    headline,
    markdown_table,
    summarise,
    write_csv,
)
from tactile_search.seed_ranges import VALIDATION

TABLE_START = "<!-- paper-table:start -->"
TABLE_END = "<!-- paper-table:end -->"
CELL = 0.005  # grid cell side (m) of the table's maps


@dataclass
class Settings:
    seeds: int = 20
    first_seed: int = VALIDATION[0]
    noise_levels: tuple[float, ...] = DEPTH_NOISE_LEVELS
    table_cell: float = CELL
    figure_cell: float = 0.004
    timing_sizes: tuple[int, ...] = (100, 250, 500, 1000, 2000)
    timing_grid: int = 64
    timing_repeats: int = 9
    timing_full_repeats: int = 3
    jar_limit: int | None = None

    @classmethod
    def tiny(cls) -> Settings:
        return cls(
            seeds=2,
            noise_levels=(0.001, DEFAULT_DEPTH_NOISE),
            table_cell=0.01,
            figure_cell=0.01,
            timing_sizes=(30, 90),
            timing_grid=16,
            timing_repeats=3,
            timing_full_repeats=1,
            jar_limit=3,
        )

    @property
    def seed_range(self) -> str:
        last = self.first_seed + self.seeds - 1
        return f"{self.first_seed:,}-{last:,}".replace(",", " ")


def time_updates(
    sizes: tuple[int, ...], grid: int, repeats: int, full_repeats: int, seed: int = 0
) -> list[dict[str, float]]:
    """Fig. 9: median time (ms) of appending one contact and of the full recompute, per n,
    by the method of ``experiments.paper.gpis_timing`` (``benchmarks.gpis_append``'s too)."""
    out = []
    for n in sizes:
        appends = time_appends(n, grid, repeats, seed)
        fulls = time_full(build_map(n, grid, max(DEFAULT_MAX_ROWS, n + 3), seed), full_repeats)
        out.append(
            {
                "n": n,
                "append_ms": 1e3 * statistics.median(appends),
                "full_ms": 1e3 * statistics.median(fulls),
            }
        )
    return out


def run(out: Path, settings: Settings, paper_md: Path | None = None) -> dict[str, object]:
    """Runs everything and writes the figures, ``table.csv``, ``table_seeds.csv`` and
    ``table.md`` into ``out``; updates the table block of ``paper_md`` if given."""
    out.mkdir(parents=True, exist_ok=True)
    started = time.perf_counter()
    seeds = range(settings.first_seed, settings.first_seed + settings.seeds)
    episodes = [
        run_episode(seed, shape, settings.noise_levels, settings.jar_limit)
        for seed in seeds
        for shape in SHAPES
    ]
    simulated = time.perf_counter() - started
    rows = evaluate(episodes, settings.noise_levels, settings.table_cell)
    summary = summarise(rows)
    default = choose_default(summary)
    write_csv(rows, out / "table_seeds.csv")
    write_csv(summary, out / "table.csv")
    table = headline(summary, default, settings.seed_range) + "\n" + markdown_table(summary)
    (out / "table.md").write_text(table)

    first = {ep.shape: ep for ep in episodes if ep.seed == settings.first_seed}
    fig3(first["round"].scene, first["round"].jars, out / "fig3_depth.png")
    fig4(first, out / "fig4_measurements.png")
    option = option_named(default)
    maps = {
        shape: maps_for(first[shape], option, DEFAULT_DEPTH_NOISE, settings.figure_cell)
        for shape in SHAPES
    }
    fig_maps(
        [(maps[s][0], first[s], False, f"{s} jars, depth only ({default})") for s in SHAPES],
        out / "fig5_prior.png",
    )
    fig_maps(
        [(maps["round"][1], first["round"], True, f"round, depth + touch ({default})")],
        out / "fig6_round.png",
    )
    fig_maps(
        [(maps["square"][1], first["square"], True, f"square, depth + touch ({default})")],
        out / "fig7_square.png",
    )
    fig8_options = [
        option_named("circle 0.2"),
        option_named("circle 0.03"),
        option_named(f"mean +{POSITIVE_MEAN:g}"),
    ]
    fig_maps(
        [
            (
                maps_for(first["square"], o, DEFAULT_DEPTH_NOISE, settings.figure_cell)[1],
                first["square"],
                True,
                f"square, depth + touch, {o.name}",
            )
            for o in fig8_options
        ],
        out / "fig8_priors.png",
    )
    timings = time_updates(
        settings.timing_sizes,
        settings.timing_grid,
        settings.timing_repeats,
        settings.timing_full_repeats,
    )
    write_csv(timings, out / "fig9_timing.csv")
    fig9(timings, out / "fig9_timing.png")

    if paper_md is not None and paper_md.exists():
        text = paper_md.read_text()
        if TABLE_START in text and TABLE_END in text:
            head, rest = text.split(TABLE_START, 1)
            _, tail = rest.split(TABLE_END, 1)
            paper_md.write_text(f"{head}{TABLE_START}\n{table}{TABLE_END}{tail}")
    return {
        "default": default,
        "summary": summary,
        "timings": timings,
        "seconds_simulating": simulated,
        "seconds_total": time.perf_counter() - started,
        "touch_steps": sum(ep.log.steps for ep in episodes),
        "contacts_kept": [len(ep.touch["points"]) for ep in episodes],
        "mean_jar_displacement_mm": 1e3
        * statistics.fmean(float(np.mean(ep.scene.jars["displacement"])) for ep in episodes),
    }


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=Path("docs/paper"))
    parser.add_argument("--seeds", type=int, default=None, help="seeds per jar shape (20)")
    parser.add_argument(
        "--first-seed",
        type=int,
        default=VALIDATION[0],
        help=f"first layout seed (default {VALIDATION[0]}, the validation range)",
    )
    parser.add_argument("--tiny", action="store_true", help="2 seeds, coarse grids (a smoke run)")
    parser.add_argument(
        "--paper-md",
        type=Path,
        default=None,
        help="markdown file whose table block is replaced (default: PAPER.md beside --out)",
    )
    args = parser.parse_args(argv)
    settings = Settings.tiny() if args.tiny else Settings()
    if args.seeds is not None:
        if args.seeds < 1:
            parser.error("--seeds must be at least 1")
        settings.seeds = args.seeds
    if args.first_seed < 0:
        parser.error("--first-seed must be a non-negative int")
    settings.first_seed = args.first_seed
    paper_md = args.paper_md if args.paper_md is not None else args.out.parent / "PAPER.md"
    result = run(args.out, settings, paper_md)
    print((args.out / "table.md").read_text())
    print(
        f"default prior: {result['default']}; seeds {settings.seed_range}; touch steps "
        f"{result['touch_steps']}, contacts kept per episode {result['contacts_kept']}, mean "
        f"jar displacement {result['mean_jar_displacement_mm']:.2f} mm; simulation "
        f"{result['seconds_simulating']:.1f} s, total {result['seconds_total']:.1f} s"
    )
    for t in result["timings"]:
        print(f"n={t['n']:>5}: append {t['append_ms']:.3f} ms, full {t['full_ms']:.2f} ms")


if __name__ == "__main__":
    main()
