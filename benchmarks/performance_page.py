"""``docs/PERFORMANCE.md``, rendered from the JSON the benchmarks write.

Every benchmark script that prints figures also writes them with ``--json PATH``
(``make bench`` writes them into ``results/``) through ``write_json``, which stamps each
file with the command that ran, the date, the commit and the machine. This module renders
whatever of those files a folder holds, each figure beside its command and stamp; a
benchmark whose file is absent gets a line naming the command that makes it, never a
number. Criterion's benchmarks leave ``target/criterion/**/new/estimates.json``, read from
``--criterion``. The page holds no date of its own, so the same files render the same page.

From the repository root::

    python -m benchmarks.performance_page --results results --out docs/PERFORMANCE.md

``make performance`` runs it on ``results/``; the page in the repository is rendered from
``docs/performance/``, whose JSON files are committed beside it.
"""

from __future__ import annotations

import argparse
import datetime
import json
import math
import os
import platform
import shlex
import subprocess
import sys
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

REFERENCE = "Pusher-v5"
#: How the page's header names its own command (the paths as given).
GENERATOR = "python -m benchmarks.performance_page"


# ---- writing: the stamp every benchmark's JSON carries ---------------------------------------
def cpu_model() -> str:
    """The CPU's model name (``/proc/cpuinfo``), or the platform's processor string."""
    try:
        with open("/proc/cpuinfo") as cpuinfo:
            for line in cpuinfo:
                if line.startswith("model name"):
                    return line.partition(":")[2].strip()
    except OSError:
        pass
    return platform.processor() or "?"


def git_commit() -> str | None:
    """The checkout's short commit, with ``+dirty`` when tracked files differ; None outside
    a git checkout."""
    try:
        commit = subprocess.run(
            ["git", "rev-parse", "--short", "HEAD"], capture_output=True, text=True, check=True
        ).stdout.strip()
        dirty = subprocess.run(
            ["git", "status", "--porcelain", "--untracked-files=no"],
            capture_output=True, text=True, check=True,
        ).stdout.strip()  # fmt: skip
    except (OSError, subprocess.CalledProcessError):
        return None
    return commit + ("+dirty" if dirty else "")


def stamp(command: str) -> dict[str, Any]:
    """What ran, when and where: ``command``, the UTC time, the commit, the CPU, its cores
    (all and usable), the OS, Python and the load average."""
    usable = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else None
    return {
        "command": command,
        "date": datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC"),
        "commit": git_commit(),
        "machine": {
            "cpu": cpu_model(),
            "cpu_count": os.cpu_count(),
            "usable_cpus": usable,
            "os": platform.platform(terse=True),
            "python": platform.python_version(),
            "load_average": os.getloadavg()[0] if hasattr(os, "getloadavg") else None,
        },
    }


def finite(value: Any) -> Any:
    """``value`` with every float NaN or infinity replaced by None (JSON has neither)."""
    if isinstance(value, float):
        return value if math.isfinite(value) else None
    if isinstance(value, dict):
        return {str(k): finite(v) for k, v in value.items()}
    if isinstance(value, list | tuple):
        return [finite(v) for v in value]
    return value


def plain(value: Any) -> Any:
    """JSON's fallback: a numpy scalar as its Python number, anything else as text."""
    return value.item() if hasattr(value, "item") else str(value)


def write_json(
    path: Path,
    module: str,
    argv: Sequence[str] | None,
    figures: dict[str, Any],
    command: str | None = None,
) -> None:
    """Writes ``figures`` to ``path``, stamped under ``"recorded"`` with the command that
    ran, ``python -m module argv...`` (``argv`` None: this process's own arguments) unless
    ``command`` names it, and when and where (``stamp``)."""
    if command is None:
        argv = sys.argv[1:] if argv is None else argv
        command = shlex.join(["python", "-m", module, *argv])
    path.parent.mkdir(parents=True, exist_ok=True)
    document = {"recorded": stamp(command), **finite(figures)}
    path.write_text(json.dumps(document, indent=2, default=plain) + "\n", encoding="utf-8")
    print(f"wrote {path}")


# ---- reading: one section per benchmark --------------------------------------------------------
def num(value: Any, spec: str = ".1f", suffix: str = "") -> str:
    """``value`` formatted, or ``-`` when absent."""
    if value is None or (isinstance(value, float) and not math.isfinite(value)):
        return "-"
    return f"{value:{spec}}{suffix}"


def table(header: Sequence[str], rows: Sequence[Sequence[str]]) -> list[str]:
    """A Markdown table."""
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    lines += ["| " + " | ".join(row) + " |" for row in rows]
    return lines


def render_peer_envs(doc: dict[str, Any]) -> list[str]:
    rows = []
    for label, f in doc.get("envs", {}).items():
        span = f"{num(f.get('steps_per_s_min'), ',.0f')}-{num(f.get('steps_per_s_max'), ',.0f')}"
        rows.append(
            [
                f"`{label}`",
                f"{num(f.get('steps_per_s_median'), ',.0f')} ({span})",
                num(f.get("ratio_to_reference_median"), ".4f", "x"),
                num(f.get("motions_per_s_median"), ",.0f"),
                num(f.get("motions_ratio_to_reference_median"), ".3f", "x"),
                num(f.get("reset_us_median"), ",.1f"),
                num(f.get("reset_in_reference_steps"), ".1f"),
                num(f.get("step_us_median"), ",.1f"),
            ]
        )
    header = ["env", "steps/s, median (min-max)", f"vs {REFERENCE}", "wrist motions/s"]
    header += [f"vs {REFERENCE}", "reset µs", f"reset in {REFERENCE} steps", "step µs"]
    lines = table(header, rows)
    lines += [
        "",
        f"A probe-mode env's steps are probes. Ratios: our rate over {REFERENCE}'s in the same "
        "round, median over the rounds; reset and step times: medians of single calls.",
    ]
    return lines


def render_env_throughput(doc: dict[str, Any]) -> list[str]:
    lines: list[str] = []
    controls = doc.get("controls", {})
    if controls:
        lines += [
            "Controls (the cores this process could get): two CPU-bound processes did "
            f"{num(controls.get('free_cores_before'), '.2f', 'x')} the work of one before, "
            f"{num(controls.get('free_cores_after'), '.2f', 'x')} after; meeting after every "
            f"burst, {num(controls.get('synced_free_cores'), '.2f', 'x')}.",
            "",
        ]
    single = doc.get("single", [])
    if single:
        header = ["map", "policy", "steps/s (resets included)", "step ms", "reset ms"]
        rows = [
            [
                r["map"],
                r["policy"],
                num(r.get("steps_per_s"), ",.0f"),
                num(r.get("step_ms"), ".3f"),
                num(r.get("reset_ms"), ".1f"),
            ]
            for r in single
        ]
        lines += [*table(header, rows), ""]
    vector = doc.get("vector", [])
    if vector:
        header = ["map", "action mode", "envs", "1 thread, steps/s", "all cores, steps/s"]
        header += ["speed-up", "load average before / after"]
        rows = [
            [
                r["map"],
                r["action_mode"] + (", copy=False" if r.get("copy") is False else ""),
                str(r["num_envs"]),
                num(r.get("rate_one_thread"), ",.0f"),
                num(r.get("rate_all_cores"), ",.0f"),
                num(r.get("speedup"), ".2f", "x"),
                f"{r.get('load_before', '?')} / {r.get('load_after', '?')}",
            ]
            for r in vector
        ]
        lines += table(header, rows)
        lines += [
            "",
            "Vector env: totals over alternating rounds, whole episodes with their resets, "
            "random actions; steps/s count every sub-env's steps.",
        ]
    memory = doc.get("memory_mib_per_env", {})
    if memory:
        per_mode = ", ".join(f"{m} {num(v, '.2f')} MiB" for m, v in memory.items())
        lines += ["", f"Resident memory added per env: {per_mode}."]
    return lines


def render_vector_overhead(doc: dict[str, Any]) -> list[str]:
    header = ["map", "action mode", "envs", "face µs", "batch alone µs", "face's cost µs"]
    rows = [
        [
            r["map"],
            r["action_mode"],
            str(r["num_envs"]),
            num(r.get("face_us"), ",.1f"),
            num(r.get("core_us"), ",.1f"),
            f"{num(r.get('cost_us'), '+,.1f')} ({num(r.get('ratio'), '.3f', 'x')})",
        ]
        for r in doc.get("rows", [])
    ]
    lines = table(header, rows)
    lines += ["", "Per batch step on one thread, medians over alternating rounds."]
    return lines


def render_env_threads(doc: dict[str, Any]) -> list[str]:
    header = ["processes", "threads=1, probes/s per machine", "threads=2", "ratio"]
    rows = [
        [
            str(r["processes"]),
            num(r.get("threads_1"), ",.1f"),
            num(r.get("threads_2"), ",.1f"),
            num(r.get("ratio"), ".2f", "x"),
        ]
        for r in doc.get("medians", [])
    ]
    lines = table(header, rows)
    lines += [
        "",
        f"Medians over {doc.get('rounds', '?')} rounds of {num(doc.get('seconds'), 'g')} s, "
        f"on {doc.get('cores', '?')} cores; random probes, GPIS map.",
    ]
    return lines


def render_learner_speed(doc: dict[str, Any]) -> list[str]:
    reference = doc.get("reference", "recipe")
    header = ["variant", "trained probes/s", f"vs {reference}", "env ms", "inference ms"]
    header += ["update ms", "update µs/sample", "parameters", f"vs {REFERENCE}"]
    rows = [
        [
            f"`{r['label']}`",
            num(r.get("probes_per_s"), ",.1f"),
            num(r.get("ratio_to_reference"), ".2f", "x"),
            num(r.get("env_ms"), ".2f"),
            num(r.get("infer_ms"), ".2f"),
            num(r.get("update_ms"), ".2f"),
            num(r.get("update_us_per_sample"), ",.0f"),
            num(r.get("params"), ",d"),
            num(r.get("ratio_to_pusher"), ".4f", "x"),
        ]
        for r in doc.get("variants", [])
    ]
    lines = table(header, rows)
    lines += [
        "",
        f"Medians over {doc.get('rounds', '?')} rounds of {doc.get('timesteps', '?')} probes; "
        f"ms per trained probe; torch threads {doc.get('torch_threads', '?')}, env threads "
        f"{doc.get('env_threads', '?')}, AMX {doc.get('amx', '?')}; {REFERENCE}: "
        f"{num(doc.get('pusher_steps_per_s'), ',.0f')} steps/s (random actions).",
    ]
    return lines


def render_train_arrangement(doc: dict[str, Any]) -> list[str]:
    header = ["arrangement", "trained probes/s per machine", f"vs {doc.get('base', '?')}"]
    rows = [
        [name, num(a.get("median"), ",.1f"), num(a.get("ratio"), ".2f", "x")]
        for name, a in doc.get("arrangements", {}).items()
    ]
    lines = table(header, rows)
    lines += [
        "",
        f"{doc.get('timesteps', '?')} probes per run, {doc.get('rounds', '?')} rounds, "
        f"{doc.get('cores', '?')} cores, the `{doc.get('map', '?')}` recipe.",
    ]
    return lines


def render_gpis_append(doc: dict[str, Any]) -> list[str]:
    header = ["rows n", "append one contact, ms", "full recompute, ms", "full / append"]
    header += ["memory MiB"]
    rows = [
        [
            str(r["n"]),
            num(r.get("append_ms"), ".3f"),
            num(r.get("full_ms"), ",.2f"),
            num(r.get("ratio"), ".1f"),
            num(r.get("memory_mib"), ".2f"),
        ]
        for r in doc.get("rows", [])
    ]
    grid = doc.get("grid", "?")
    return [*table(header, rows), "", f"Grid {grid} x {grid}, medians, one core."]


def render_prior_rows(doc: dict[str, Any]) -> list[str]:
    header = ["depth points", "rows", "reset ms", "prior IoU", "final IoU", "planner success"]
    rows = [
        [
            str(r["points"]),
            num(r.get("rows"), ".0f"),
            num(r.get("reset_ms"), ".2f"),
            f"{num(r.get('prior_iou'), '.3f')} ± {num(r.get('prior_iou_sd'), '.3f')}",
            f"{num(r.get('final_iou'), '.3f')} ± {num(r.get('final_iou_sd'), '.3f')}",
            f"{num(r.get('success'), '.0f')} % {r.get('success_ci', '')}",
        ]
        for r in doc.get("rows", [])
    ]
    seeds = doc.get("seeds", "?")
    return [*table(header, rows), "", f"Over {seeds} validation layouts; reset: medians."]


def percent(fraction: Any) -> str:
    """A fraction as a signed percentage, or ``-``."""
    return "-" if fraction is None else f"{100 * fraction:+.2f} %"


def render_soak(doc: dict[str, Any]) -> list[str]:
    memory = doc.get("memory", {})
    live = memory.get("live_heap", {}).get("growth_after_warm_up")
    rss = memory.get("rss_after_trim", {}).get("growth_after_warm_up")
    scale = doc.get("scale", {}).get("name", "?")
    checks = doc.get("checks", {})
    failed = [name for name, check in checks.items() if not check.get("passed")]
    informational = doc.get("informational", {})
    lines = [
        f"The `{scale}` soak: {num(doc.get('steps'), ',d')} steps, "
        f"{num(doc.get('seeds_given'), ',d')} layout seeds, {num(doc.get('seconds'), ',.0f')} "
        f"s. Growth after the warm-up: live heap {percent(live)}, resident memory after the "
        f"trim {percent(rss)} (limit 2 % each).",
        "",
        f"Checks: {len(checks) - len(failed)} of {len(checks)} passed"
        + (f" (failed: {', '.join(failed)})" if failed else "")
        + ".",
    ]
    if informational:
        shown = ", ".join(
            f"{name} {'within' if item.get('within_limit') else 'outside'} its limit"
            for name, item in informational.items()
        )
        lines += ["", f"Printed only at this scale, not asserted: {shown}."]
    return lines


def median(values: Any) -> float | None:
    """The median of the numbers in ``values``, or None."""
    ordered = sorted(v for v in values or [] if v is not None)
    if not ordered:
        return None
    middle = len(ordered) // 2
    return ordered[middle] if len(ordered) % 2 else (ordered[middle - 1] + ordered[middle]) / 2


def render_ray_grid(doc: dict[str, Any]) -> list[str]:
    grid, single = doc.get("grid_seconds", {}), doc.get("single_seconds", {})
    local, ray, split = (median(grid.get(k)) for k in ("local", "ray", "split"))
    ray_ratio = f" (**{local / ray:.2f}x**)" if local and ray else ""
    split_ratio = f" ({local / split:.2f}x)" if local and split else ""
    lines = [
        f"Four trials of PPO with the GPIS map ({num(doc.get('timesteps'), ',d')} steps each, "
        f"{doc.get('cores', '?')} cores): one after another {num(local, '.1f', ' s')}, on Ray "
        f"{num(ray, '.1f', ' s')}{ray_ratio}, in plain processes without Ray "
        f"{num(split, '.1f', ' s')}{split_ratio}. One trial: directly "
        f"{num(median(single.get('local')), '.1f', ' s')}, on Ray "
        f"{num(median(single.get('ray')), '.1f', ' s')}.",
    ]
    paper = doc.get("on_paper_seconds", {})
    if paper:
        rows = [
            [
                str(machines),
                num(p["training_s"] / 3600, ".2f"),
                num(p["evaluation_s"] / 3600, ".2f"),
                num((p["training_s"] + p["evaluation_s"]) / 3600, ".2f"),
            ]
            for machines, p in paper.items()
        ]
        lines += ["", "The documented grid on paper:", ""]
        lines += table(["machines", "training h", "evaluation h", "total h"], rows)
    return lines


@dataclass(frozen=True)
class Section:
    """One benchmark's part of the page: its JSON file, title, the command that writes the
    file (``{json}`` for its path) and how to render it."""

    file: str
    title: str
    command: str
    about: str
    render: Callable[[dict[str, Any]], list[str]]


#: In ``make bench``'s order. The commands are ``make bench``'s lines.
def render_construction(doc: dict[str, Any]) -> list[str]:
    seconds = doc.get("seconds", {})
    reference = seconds.get(REFERENCE)
    header = ["made", "ms", f"vs {REFERENCE}"]
    rows = [
        [
            f"`{name}`",
            num(1e3 * value, ",.2f"),
            num(value / reference if reference else None, ".2f", "x"),
        ]
        for name, value in seconds.items()
    ]
    lines = table(header, rows)
    lines += [
        "",
        f"Medians over {doc.get('rounds', '?')} alternating rounds, map `{doc.get('map', '?')}`.",
    ]
    return lines


SECTIONS = (
    Section(
        "construction.json",
        "Making an env",
        "python -m benchmarks.construction --json {json}",
        '`gym.make` and `gym.make_vec(..., 16, vectorization_mode="vector_entry_point")`: '
        "construction alone (no episode starts before `reset()`).",
        render_construction,
    ),
    Section(
        "gpis_append.json",
        "GPIS append against full recompute",
        "python -m benchmarks.gpis_append --out results/gpis_append.png --json {json}",
        "Time to add one contact (3 rows) to a map of n rows, incrementally and by "
        "recomputing from scratch (the paper's Fig. 9).",
        render_gpis_append,
    ),
    Section(
        "prior_rows.json",
        "Depth points in the GPIS prior",
        "python -m benchmarks.prior_rows --json {json}",
        "Map quality and reset time against `max_prior_depth_points`.",
        render_prior_rows,
    ),
    Section(
        "peer_envs.json",
        f"Beside MuJoCo's {REFERENCE} and Ant-v5",
        "python -m benchmarks.peer_envs --json {json}",
        "Whole episodes with their resets through `gym.make`, random actions, in alternating "
        "rounds in one process; both action modes.",
        render_peer_envs,
    ),
    Section(
        "peer_envs_threads.json",
        "The single env with and without its helper thread",
        "python -m benchmarks.peer_envs --maps gpis --probe-maps gpis --variant threads=1 "
        "--json {json}",
        "The same, GPIS map only, each env once more on one thread (`threads=1`).",
        render_peer_envs,
    ),
    Section(
        "env_threads_side_by_side.json",
        "The helper thread when processes fill the cores",
        "python -m benchmarks.env_threads_side_by_side --json {json}",
        "Probes/s per machine with N processes side by side, each env with `threads=1` and "
        "with `threads=2`.",
        render_env_threads,
    ),
    Section(
        "learner_speed.json",
        "PPO training speed per encoder and setting",
        "python -m benchmarks.learner_speed --json {json}",
        "Trained probes/s, and each probe's time in the environment, the rollout's "
        "inference and the PPO update.",
        render_learner_speed,
    ),
    Section(
        "env_throughput.json",
        "The vector env on every core over one thread",
        "python -m benchmarks.env_throughput --vector-only --action-modes wrist probe "
        "--json {json}",
        "One Rust batch on all cores against the same batch on one thread, through Python.",
        render_env_throughput,
    ),
    Section(
        "vector_overhead.json",
        "The vector env's Python per batch step",
        "python -m benchmarks.vector_overhead --json {json}",
        "The gymnasium face's serial work per batch step beyond the core's own step.",
        render_vector_overhead,
    ),
    Section(
        "soak.json",
        "Memory and step time over a long run",
        "python -m benchmarks.soak --out results/soak.png --json {json}",
        "Every map mode, single and vector envs, random, invalid and oracle actions; memory "
        "and step time stay flat.",
        render_soak,
    ),
    Section(
        "ray_grid.json",
        "The training grid on Ray",
        "python -m benchmarks.ray_grid --json {json}",
        "Ray against the same trials one after another, each a fresh process timed whole.",
        render_ray_grid,
    ),
    Section(
        "train_arrangement.json",
        "Placing training on the cores (run by hand)",
        "python -m benchmarks.train_arrangement --json {json}",
        "Trained probes/s per machine: one run on one core, one run on every core, a run "
        "per core side by side.",
        render_train_arrangement,
    ),
)


def criterion_estimates(criterion: Path, benches: Path = Path("env_core/benches")) -> list:
    """Every criterion benchmark under ``criterion`` (the ``estimates.json`` of its ``new``
    folder and the ``benchmark.json`` beside it): its id, the bench whose source names its
    group (None if none does), the median and the mean in ns with the mean's 95 % interval."""
    sources = {
        name: (benches / f"{name}.rs").read_text() if (benches / f"{name}.rs").is_file() else ""
        for name in CRITERION_BENCHES
    }
    found = []
    for estimates in sorted(criterion.glob("**/new/estimates.json")):
        meta_path = estimates.with_name("benchmark.json")
        data = json.loads(estimates.read_text())
        meta = json.loads(meta_path.read_text()) if meta_path.is_file() else {}
        full_id = meta.get("full_id") or estimates.parent.parent.relative_to(criterion).as_posix()
        group = meta.get("group_id") or full_id.partition("/")[0]
        bench = next((name for name, text in sources.items() if f'"{group}' in text), None)
        mean = data["mean"]
        found.append(
            {
                "id": full_id,
                "bench": bench,
                "median_ns": data["median"]["point_estimate"],
                "mean_ns": mean["point_estimate"],
                "mean_low_ns": mean["confidence_interval"]["lower_bound"],
                "mean_high_ns": mean["confidence_interval"]["upper_bound"],
            }
        )
    return found


def duration(ns: float) -> str:
    """A time in ns in the unit that reads best."""
    for unit, scale in (("s", 1e9), ("ms", 1e6), ("µs", 1e3)):
        if ns >= scale:
            return f"{ns / scale:.3g} {unit}"
    return f"{ns:.3g} ns"


def render_criterion(doc: dict[str, Any]) -> list[str]:
    rows = [
        [
            f"`{e['id']}`",
            f"`cargo bench -p env_core --bench {e['bench']}`"
            if e.get("bench")
            else "`cargo bench -p env_core`",
            duration(e["median_ns"]),
            f"{duration(e['mean_ns'])} [{duration(e['mean_low_ns'])}, "
            f"{duration(e['mean_high_ns'])}]",
        ]
        for e in doc.get("benchmarks", [])
    ]
    return table(["benchmark", "command", "median", "mean [95 % interval]"], rows)


#: The criterion benches ``make bench`` runs; their estimates are collected into one file.
CRITERION_BENCHES = ("gpis_append", "scene", "probe")
CRITERION_COMMAND = (
    " && ".join(f"cargo bench -p env_core --bench {b}" for b in CRITERION_BENCHES)
    + " && python -m benchmarks.performance_page --collect-criterion {criterion} "
    "--results {results}"
)
CRITERION = Section(
    "criterion.json",
    "The Rust core alone (criterion)",
    CRITERION_COMMAND,
    "Criterion's estimates, collected from `target/criterion/` once `cargo bench` has run; "
    "the date is the collection's.",
    render_criterion,
)
#: The Rust examples that print their figures and write none.
PRINTED_ONLY = (
    (
        "cargo run --release -p env_core --example physics_tradeoffs",
        "what each physics setting costs and what it trades",
    ),
    (
        "cargo run --release -p env_core --example batch_scaling",
        "the batch of 16 episodes on 2 threads over 1 with no Python in the loop, every mode",
    ),
)


def stamp_lines(doc: dict[str, Any], fallback_command: str) -> list[str]:
    """The command that wrote ``doc`` and when and where, as recorded in it."""
    recorded = doc.get("recorded")
    if not isinstance(recorded, dict):
        return [f"Command: `{fallback_command}` (the file records neither command nor date)."]
    machine = recorded.get("machine", {})
    cores, usable = machine.get("cpu_count") or "?", machine.get("usable_cpus")
    if usable is not None and usable != cores:
        cores_text = f"{cores} cores ({usable} usable by the process)"
    else:
        cores_text = f"{cores} cores"
    where = (
        f"{machine.get('cpu', '?')}, {cores_text}, {machine.get('os', '?')}, Python "
        f"{machine.get('python', '?')}, load average "
        f"{num(machine.get('load_average'), '.2f')} at the end"
    )
    lines = [
        f"Command: `{recorded.get('command', fallback_command)}`  ",
        f"Recorded {recorded.get('date', '?')} at commit `{recorded.get('commit') or '?'}` "
        f"on {where}.",
    ]
    load = machine.get("load_average")
    if isinstance(load, int | float) and isinstance(cores, int) and load > cores:
        lines += [
            "",
            f"**Other work shared the machine** (load average {load:.1f} on {cores} cores): "
            "rates are low and scaling over threads or processes is not this code's; read the "
            "ratios measured in the same rounds, and the controls where the benchmark has them.",
        ]
    return lines


def render_section(section: Section, results: Path) -> list[str]:
    """A section: its title and what it measures, then its figures under the command and
    stamp that produced them, or the line naming the command that writes its file."""
    path = results / section.file
    command = section.command.format(
        json=path.as_posix(), results=results.as_posix(), criterion="target/criterion"
    )
    lines = [f"## {section.title}", "", section.about, ""]
    if not path.is_file():
        return [*lines, f"_Not measured for this page: `{command}` writes `{path.as_posix()}`._"]
    try:
        doc = json.loads(path.read_text(encoding="utf-8"))
        body = section.render(doc)
    except (ValueError, KeyError, TypeError, AttributeError) as error:
        unreadable = f"_`{path.as_posix()}` could not be read ({error!r}): `{command}` writes it._"
        return [*lines, unreadable]
    return [*lines, *stamp_lines(doc, command), "", *body]


def render_page(results: Path, out: Path = Path("docs/PERFORMANCE.md")) -> str:
    """The whole page from the JSON files in ``results`` (``out``: where it goes, for the
    command the page names)."""
    command = f"{GENERATOR} --results {results.as_posix()} --out {out.as_posix()}"
    lines = [
        "# Performance",
        "",
        f"<!-- Generated by `{command}`: edit benchmarks/performance_page.py, not this file. -->",
        "",
        f"What the benchmarks measured, rendered by `{command}` from the JSON files the "
        "benchmarks wrote with `--json` (`make bench` writes them into `results/` and ends "
        "by rendering this page from there; `make performance` renders it again without "
        "running anything). Each figure stands beside the command that produced it, with "
        "the date, the commit and the machine it ran on. The budgets these figures are held "
        "to are in [DESIGN.md §5](DESIGN.md#5-performance-budgets).",
        "",
        "The machines are shared and noisy: figures are medians from one run, and the "
        f"ratios to MuJoCo's `{REFERENCE}` (random actions through `gym.make`) are measured "
        "in the same run, so they carry across machines where absolute rates do not.",
    ]
    for section in (*SECTIONS, CRITERION):
        lines += ["", *render_section(section, results)]
    lines += ["", "## Printed only", "", "These print their figures and write no JSON:", ""]
    lines += [f"- `{printed}`: {about}." for printed, about in PRINTED_ONLY]
    known = {section.file for section in (*SECTIONS, CRITERION)}
    others = sorted(p.name for p in results.glob("*.json") if p.name not in known)
    if others:
        names = ", ".join(f"`{name}`" for name in others)
        lines += ["", f"Other JSON files in `{results.as_posix()}/`, not rendered: {names}."]
    return "\n".join(lines) + "\n"


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    parser.add_argument("--results", type=Path, default=Path("results"), help="the JSON files")
    parser.add_argument("--out", type=Path, default=Path("docs/PERFORMANCE.md"))
    parser.add_argument(
        "--collect-criterion",
        type=Path,
        default=None,
        metavar="DIR",
        help="first write RESULTS/criterion.json from criterion's estimates in DIR",
    )
    args = parser.parse_args(argv)
    if args.collect_criterion is not None:
        estimates = criterion_estimates(args.collect_criterion)
        if not estimates:
            parser.error(f"no criterion estimates under {args.collect_criterion}/**/new/")
        command = CRITERION_COMMAND.format(
            results=args.results.as_posix(), criterion=args.collect_criterion.as_posix()
        )
        figures = {"source": args.collect_criterion.as_posix(), "benchmarks": estimates}
        write_json(args.results / CRITERION.file, GENERATOR, argv, figures, command=command)
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text(render_page(args.results, args.out), encoding="utf-8")
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
