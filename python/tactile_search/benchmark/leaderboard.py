"""The leaderboard page: result files (``python -m tactile_search.benchmark --json``, and the
scripted baselines' from ``python -m agents.scripted_results``) as one markdown table per
registered id (a task and its tier), best first::

    python -m tactile_search.benchmark.leaderboard docs/results/leaderboard \\
        --out docs/LEADERBOARD.md

Each argument is a result file or a folder of them (its ``*.json``). The page is a function
of the files' contents and the command line alone (written at its top), so the same command
gives the same bytes. Needs only the package (no torch)."""

from __future__ import annotations

import argparse
import os
import shlex
import sys
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

from tactile_search import ENV_IDS
from tactile_search._core import registered_envs
from tactile_search.benchmark.result_file import read_result
from tactile_search.benchmark.runner import DEFAULT_EPISODES
from tactile_search.benchmark.summary_table import (
    MAP_TASK,
    TASKS,
    markdown_row,
    summary_cells,
    summary_columns,
)

PROG = "python -m tactile_search.benchmark.leaderboard"
# Digits of a model's digest a source cell shows.
DIGEST_SHOWN = 12


def result_paths(paths: Sequence[str | os.PathLike[str]]) -> list[Path]:
    """The result files ``paths`` name: each a file, or a folder whose ``*.json`` are
    taken (sorted); ``ValueError`` for a path that is neither, or a folder without one."""
    found: list[Path] = []
    for given in paths:
        path = Path(given)
        if path.is_dir():
            inside = sorted(path.glob("*.json"))
            if not inside:
                raise ValueError(f"{path} holds no result file (*.json)")
            found += inside
        elif path.is_file():
            found.append(path)
        else:
            raise ValueError(f"{path} is neither a result file nor a folder of them")
    return found


def source_cell(source: Mapping[str, Any]) -> str:
    """Where an agent came from: a model's path and digest (and whether that digest was
    checked against its record), a callable's or a scripted agent's name."""
    if source["kind"] == "model":
        checked = "verified" if source["verified"] else "unverified"
        return f"`{source['path']}` ({checked} digest `{str(source['digest'])[:DIGEST_SHOWN]}`)"
    if source["kind"] == "scripted":
        return f"scripted: `{source['name']}`"
    return f"`{source['name']}`"


def ranking_key(record: Mapping[str, Any]) -> tuple[Any, ...]:
    """Best first: the highest success (then the highest lower bound), or the map task's
    lowest distance over the motions; ties by agent and source."""
    summary = record["summary"]
    if record["task"] == MAP_TASK:
        score: tuple[float, ...] = (float(summary["map_score_area"]),)
    else:
        rate = int(summary["successes"]) / int(summary["episodes"])
        score = (-rate, -float(summary["success_low"]))
    return (*score, str(record["agent"]), source_cell(record["source"]))


def id_table(env_id: str, records: list[Mapping[str, Any]]) -> list[str]:
    """The table of one registered id under its heading and summary line (the core's)."""
    task = str(records[0]["task"])
    summary = next(env["summary"] for env in registered_envs() if env["id"] == env_id)
    header = ["agent", *summary_columns(task), "layouts", "source"]
    lines = [
        f"### `{env_id}`",
        "",
        summary[0].upper() + summary[1:] + ".",
        "",
        markdown_row(header),
        "|" + "---|" * len(header),
    ]
    for record in sorted(records, key=ranking_key):
        cells = [
            str(record["agent"]),
            *summary_cells(task, record["summary"]),
            f"{record['episodes']} {record['split']}",
            source_cell(record["source"]),
        ]
        lines.append(markdown_row(cells))
    return [*lines, ""]


def leaderboard_markdown(records: Sequence[Mapping[str, Any]], command: str) -> str:
    """The page: ``records`` (result files' objects) in a section per task (``TASKS``'
    order) and a table per registered id in it (``tactile_search.ENV_IDS``' order), under
    ``command`` (the one that made it), and the commands that made the result files."""
    if not records:
        raise ValueError("a leaderboard needs at least one result file")
    by_id: dict[str, list[Mapping[str, Any]]] = {}
    for record in records:
        if record["env_id"] not in ENV_IDS:
            raise ValueError(
                f"a result of {record['env_id']!r}: the leaderboard lists the registered ids "
                f"{list(ENV_IDS)}"
            )
        by_id.setdefault(str(record["env_id"]), []).append(record)
    for env_id, rows in by_id.items():
        tasks = {row["task"] for row in rows}
        if len(tasks) > 1:
            raise ValueError(f"the results of {env_id} name several tasks: {sorted(tasks)}")
    lines = [
        "# Leaderboard",
        "",
        "<!-- Generated: do not edit by hand; run the command below again. -->",
        "",
        f"Generated by `{command}` from result files: `python -m tactile_search.benchmark "
        "--json` writes one for any policy (`module:callable`) or published `model.zip`, "
        "`python -m agents.scripted_results` for the scripted baselines (the commands are "
        "listed at the end). A section per task, a table per registered id (the task's tier) "
        "in it, best first; each row is one result file, played on the first layouts of a "
        "held-out split (`python/tactile_search/seed_ranges.py`): rows of one table compare "
        "when their layouts do. Success: its 95 % Wilson interval. The map task has no "
        "success: its outline distance over the motions and at the end (lower is better), "
        "each with its 95 % interval (mean +- 1.96 standard errors). A model's source shows "
        "its path and digest, verified when it matched the digest recorded beside the model.",
        "",
    ]
    if any(int(record["episodes"]) < DEFAULT_EPISODES for record in records):
        lines += [
            f"Rows of fewer than {DEFAULT_EPISODES} layouts (the benchmark's default) are a "
            "quick sample: their intervals are wide, and the published results on the test "
            "layouts (`docs/RESULTS.md`) are the numbers to cite.",
            "",
        ]
    for task in TASKS:
        ids = [env_id for env_id in ENV_IDS if env_id in by_id and by_id[env_id][0]["task"] == task]
        if ids:
            lines += [f"## Task: {task}", ""]
            for env_id in ids:
                lines += id_table(env_id, by_id[env_id])
    made_by = sorted({str(record["command"]) for record in records})
    lines += ["## The result files' commands", "", *(f"- `{command}`" for command in made_by)]
    return "\n".join(lines) + "\n"


def main(argv: list[str] | None = None) -> str:
    parser = argparse.ArgumentParser(
        prog=PROG, description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    parser.add_argument(
        "results", nargs="+", metavar="RESULT", help="a result file, or a folder of them"
    )
    parser.add_argument("--out", type=Path, default=None, help="the page (default: stdout)")
    args = parser.parse_args(argv)
    command = f"{PROG} {shlex.join(sys.argv[1:] if argv is None else argv)}"
    try:
        records = [read_result(path) for path in result_paths(args.results)]
        page = leaderboard_markdown(records, command)
    except (ValueError, KeyError, TypeError) as error:  # one line: the input is at fault
        message = " ".join(str(error).split()) or type(error).__name__
        if isinstance(error, KeyError):
            message = f"a result file's summary or source lacks the field {message}"
        parser.exit(2, f"{PROG}: error: {message}\n")
    if args.out is None:
        sys.stdout.write(page)
    else:
        args.out.parent.mkdir(parents=True, exist_ok=True)
        args.out.write_text(page)
    return page


if __name__ == "__main__":
    main()
