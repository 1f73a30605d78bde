"""``python -m tactile_search.benchmark --policy module:callable``: the standard evaluation
of a policy (see ``tactile_search.benchmark``), printed as one summary row; ``--json`` and
``--csv`` keep the per-episode rows.

A ``model.zip`` is evaluated as it was trained (its run's ``config.yml``: algorithm, env
settings, the policy's mode or sampled); each ``--env`` setting overrides one of those, and
the summary names the env, its map and action mode, how actions were chosen and what was
overridden. Every failure is one line on stderr (exit status 2), never a traceback.
``--json`` writes the result file a leaderboard is made from
(``tactile_search.benchmark.result_file``, ``python -m tactile_search.benchmark.leaderboard``).

Security: a model.zip holds pickled Python objects, and a module:callable is Python code:
loading either runs code of its author's choosing, so take them only from a source you
trust. A model.zip whose digest is recorded beside it (model.digest) is checked against it
before it is loaded and refused if it changed; one without a record loads with a warning."""

from __future__ import annotations

import argparse
import ast
import csv
import math
import shlex
import sys
import warnings
from pathlib import Path
from typing import Any

from tactile_search import ENV_ID, ENV_IDS
from tactile_search.benchmark.model_digest import UnverifiedModelWarning
from tactile_search.benchmark.policies import SB3_ALGORITHMS, Sb3Policy, load_policy
from tactile_search.benchmark.result_file import (
    model_source,
    named_source,
    result_record,
    write_result,
)
from tactile_search.benchmark.runner import DEFAULT_EPISODES, ROW_KEYS, BenchmarkResult, evaluate
from tactile_search.envs.config import SETTINGS
from tactile_search.seed_ranges import SPLITS

#: Every setting's default (what an env made without it runs).
DEFAULTS: dict[str, Any] = {s["key"]: s["default"] for s in SETTINGS}


def setting(text: str) -> tuple[str, Any]:
    """argparse type of ``--env key=value``: the value as a Python literal, else a string."""
    key, sep, value = text.partition("=")
    if not sep or not key:
        raise argparse.ArgumentTypeError(f"expected key=value, got {text!r}")
    try:
        return key, ast.literal_eval(value)
    except (ValueError, SyntaxError):
        return key, value


def run_description(result: BenchmarkResult, actions: str, overridden: dict[str, Any]) -> str:
    """What ran: the env id, its map and action mode, how actions were chosen, and which
    settings the command line overrode."""
    settings = result.env_kwargs
    text = (
        f"{result.env_id}, map {settings.get('map', DEFAULTS['map'])}, action_mode "
        f"{settings.get('action_mode', DEFAULTS['action_mode'])}, actions: {actions}"
    )
    if overridden:
        text += "; overridden: " + ", ".join(f"{k}={v!r}" for k, v in overridden.items())
    return text


def summary_line(result: BenchmarkResult) -> str:
    """The summary as one line: success with its interval, steps, tips, displacement, IoU
    (and the wrong claims of the identify task); the map task's scores instead."""
    s = result.summary
    if result.task == "map":
        return (
            f"{s.agent} on {s.episodes} {result.split} layouts ({s.map_mode} map): outline "
            f"distance {s.map_score_mm:.1f} mm at the end, {s.map_score_area:.1f} mm over the "
            f"budget (area), IoU {s.map_score_iou:.3f}, tip rate {100 * s.tip_rate:.1f} %, "
            f"displacement {s.displacement_mm:.1f} mm"
        )
    steps = (
        "-"
        if math.isnan(s.steps_median)
        else f"{s.steps_median:g} ({s.steps_q1:g}, {s.steps_q3:g})"
    )
    return (
        f"{s.agent} on {s.episodes} {result.split} layouts ({s.map_mode} map): success "
        f"{100 * s.success_rate:.1f} % [{100 * s.success_low:.1f}, {100 * s.success_high:.1f}], "
        f"steps to success median (Q1, Q3) {steps}, tip rate {100 * s.tip_rate:.1f} %, "
        f"displacement in successes {s.success_displacement_mm:.1f} mm, final IoU {s.iou:.3f}"
        + (f", wrong claims {100 * s.wrong_claim_rate:.1f} %" if result.task == "identify" else "")
    )


def main(argv: list[str] | None = None) -> BenchmarkResult:
    parser = argparse.ArgumentParser(
        prog="python -m tactile_search.benchmark",
        description=__doc__,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    parser.add_argument(
        "--policy", required=True,
        help="module:callable, or an SB3 model.zip (either runs code when loaded: only from a "
        "source you trust)",
    )  # fmt: skip
    parser.add_argument(
        "--algo",
        default=None,
        choices=sorted(SB3_ALGORITHMS),
        help="a model.zip's algorithm (default: its run's config.yml, else ppo)",
    )
    parser.add_argument(
        "--env-id", default=None, choices=ENV_IDS,
        help="the registered task and tier (default: a model's run config's, else "
        f"{ENV_ID})",
    )  # fmt: skip
    parser.add_argument("--split", default="validation", choices=sorted(SPLITS))
    parser.add_argument("--episodes", type=int, default=DEFAULT_EPISODES)
    parser.add_argument("--final", action="store_true", help="the final evaluation (test split)")
    parser.add_argument("--num-envs", type=int, default=None)
    parser.add_argument("--name", default=None, help="the agent's name in the summary")
    parser.add_argument(
        "--env", type=setting, action="append", default=[], metavar="KEY=VALUE",
        help="an env setting, e.g. --env map=occupancy --env action_mode=probe",
    )  # fmt: skip
    parser.add_argument(
        "--json", type=Path, default=None,
        help="write the result file: the leaderboard's fields, the summary and the rows",
    )  # fmt: skip
    parser.add_argument("--csv", type=Path, default=None, help="write the rows")
    parser.add_argument("--no-progress", action="store_true")
    args = parser.parse_args(argv)
    command = f"{parser.prog} {shlex.join(sys.argv[1:] if argv is None else argv)}"
    overridden = dict(args.env)
    try:
        # A model without a recorded digest warns: one line, once it loaded (a failure to
        # load is its one line alone); other warnings go their usual way.
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always", UnverifiedModelWarning)
            policy = load_policy(args.policy, args.algo)
        for warning in caught:
            if issubclass(warning.category, UnverifiedModelWarning):
                print(f"{parser.prog}: warning: {warning.message}", file=sys.stderr)
            else:
                warnings.showwarning(
                    warning.message, warning.category, warning.filename, warning.lineno
                )
        actions = (
            "the policy's own"
            if not isinstance(policy, Sb3Policy)
            else ("the policy's mode" if policy.deterministic else "sampled from the policy")
        )
        # A model.zip runs in its run's settings, each --env overriding one (evaluate).
        result = evaluate(
            policy, args.split, args.episodes, final=args.final, name=args.name,
            num_envs=args.num_envs, progress=not args.no_progress, env_id=args.env_id,
            **overridden,
        )  # fmt: skip
    except Exception as error:  # one line, never a traceback: the user's input is at fault
        message = " ".join(str(error).split()) or type(error).__name__
        parser.exit(2, f"{parser.prog}: error: {message}\n")
    print(run_description(result, actions, overridden))
    print(summary_line(result))
    if args.json is not None:
        source = (
            model_source(args.policy, policy.digest, policy.verified)
            if isinstance(policy, Sb3Policy)
            else named_source("callable", args.policy)
        )
        write_result(args.json, result_record(result, source, command))
    if args.csv is not None:
        args.csv.parent.mkdir(parents=True, exist_ok=True)
        with args.csv.open("w", newline="") as file:
            writer = csv.DictWriter(file, fieldnames=ROW_KEYS)
            writer.writeheader()
            writer.writerows(result.rows)
    return result


if __name__ == "__main__":
    main()
