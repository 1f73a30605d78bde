"""The result file of an evaluation (``python -m tactile_search.benchmark --json``), what a
leaderboard is made from (``tactile_search.benchmark.leaderboard``).

One JSON object. At its top, what a leaderboard row needs: the registered id and its task,
the agent's name, its ``source`` (a model file with its digest and whether that digest was
checked against the record beside the model; a ``module:callable``; a scripted agent of the
repository's ``agents``), the split and the number of its layouts (the split's first
seeds), and the command that made it. Then the ``summary`` (``statistics.Summary``: success
with its 95 % interval, steps to success, tips; the map task's scores with their
intervals; a NaN is null), the env settings it ran in and the per-episode ``rows``.
"""

from __future__ import annotations

import dataclasses
import json
import math
import os
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from tactile_search.benchmark.runner import BenchmarkResult
from tactile_search.benchmark.summary_table import TASKS
from tactile_search.seed_ranges import SPLITS

#: The layout of the file; a reader refuses another.
RESULT_FORMAT = 1
#: The top-level fields of a result file, in the order written.
RESULT_FIELDS = (
    "format", "env_id", "task", "agent", "source", "split", "episodes", "command", "summary",
    "env_kwargs", "rows",
)  # fmt: skip
#: Where an evaluated agent came from: a model file, a ``module:callable``, a scripted agent.
SOURCE_KINDS = ("model", "callable", "scripted")


def model_source(path: str | os.PathLike[str], digest: str, verified: bool) -> dict[str, Any]:
    """The source of a model file: its path as given, its digest (hex) and whether that
    digest was checked against the record beside the model (``model_digest``)."""
    return {"kind": "model", "path": os.fspath(path), "digest": digest, "verified": verified}


def named_source(kind: str, name: str) -> dict[str, Any]:
    """The source of a ``callable`` (its ``module:callable``) or a ``scripted`` agent (its
    name in the repository's ``agents.scripted``)."""
    if kind not in ("callable", "scripted"):
        raise ValueError(f"a named source is a 'callable' or a 'scripted' agent, got {kind!r}")
    return {"kind": kind, "name": name}


def _finite_or_none(value: Any) -> Any:
    return None if isinstance(value, float) and math.isnan(value) else value


def result_record(
    result: BenchmarkResult, source: Mapping[str, Any], command: str
) -> dict[str, Any]:
    """The result file's object for ``result`` (``evaluate``'s), made from ``source``
    (``model_source`` or ``named_source``) by ``command``."""
    summary = {
        key: _finite_or_none(value) for key, value in dataclasses.asdict(result.summary).items()
    }
    record = {
        "format": RESULT_FORMAT,
        "env_id": result.env_id,
        "task": result.task,
        "agent": result.summary.agent,
        "source": dict(source),
        "split": result.split,
        "episodes": result.summary.episodes,
        "command": command,
        "summary": summary,
        "env_kwargs": result.env_kwargs,
        "rows": result.rows,
    }
    _check(record, "the result")
    return record


def write_result(path: str | os.PathLike[str], record: Mapping[str, Any]) -> None:
    """Writes a result file (``result_record``'s object), its folder made if need be."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(json.dumps(record, indent=1, default=str) + "\n")


def read_result(path: str | os.PathLike[str]) -> dict[str, Any]:
    """A result file's object, checked: ``ValueError`` naming the file and what is wrong
    (not JSON, not of this format, a field missing or of the wrong kind)."""
    path = Path(path)
    try:
        record = json.loads(path.read_text())
    except (OSError, UnicodeDecodeError, json.JSONDecodeError) as error:
        raise ValueError(f"{path} is not a readable result file: {error}") from None
    _check(record, str(path))
    return dict(record)


def _check(record: Any, what: str) -> None:
    """``ValueError`` naming ``what`` unless ``record`` is a result file's object."""
    if not isinstance(record, dict):
        raise ValueError(f"{what} must hold a JSON object, got {type(record).__name__}")
    missing = [key for key in RESULT_FIELDS if key not in record]
    if missing:
        raise ValueError(
            f"{what} lacks the fields {missing} of a result file (python -m "
            "tactile_search.benchmark --json writes them)"
        )
    if record["format"] != RESULT_FORMAT:
        raise ValueError(
            f"{what} is a result file of format {record['format']!r}, this reads format "
            f"{RESULT_FORMAT}: write it again with this version"
        )
    if record["task"] not in TASKS:
        raise ValueError(f"{what}: task must be one of {list(TASKS)}, got {record['task']!r}")
    if record["split"] not in SPLITS:
        raise ValueError(f"{what}: split must be one of {sorted(SPLITS)}, got {record['split']!r}")
    source = record["source"]
    if not isinstance(source, dict) or source.get("kind") not in SOURCE_KINDS:
        raise ValueError(
            f"{what}: source must be an object whose kind is one of {list(SOURCE_KINDS)}, "
            f"got {source!r}"
        )
    needed = ("path", "digest", "verified") if source["kind"] == "model" else ("name",)
    if any(key not in source for key in needed):
        raise ValueError(f"{what}: a {source['kind']} source has the fields {needed}, got {source}")
    if not isinstance(record["summary"], dict) or not isinstance(record["rows"], list):
        raise ValueError(f"{what}: summary must be an object and rows a list")
    if not isinstance(record["episodes"], int) or record["episodes"] != len(record["rows"]):
        raise ValueError(
            f"{what}: episodes must count its rows ({len(record['rows'])}), got "
            f"{record['episodes']!r}"
        )
