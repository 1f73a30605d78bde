"""Where each task stands: random, the scripted baselines and the oracle on the first
validation layouts of every registered task and tier::

    python -m benchmarks.task_standings --episodes 200 --out docs/results/task_standings

Per id (``tactile_search.ENV_IDS``) it runs the scripted agents that play its task
(``agents.scripted.SCRIPTED_TASKS``: ``random``, ``gpis_probe_planner`` and ``oracle`` in the
search tiers, ``random_identify``, ``identify_planner`` and ``oracle`` in the identify tiers),
each in its own action mode and the GPIS map, with the id's settings over them, on the same
first ``--episodes`` validation layouts (``tactile_search.seed_ranges``; never the test
range). It reports success with its 95 % Wilson interval, wrong claims (identify), wrist
motions to success (median and quartiles) and the share of episodes with a tip, and per
tier how far the best baseline is below the oracle.

Writes to ``--out``: ``<out>/standings.md`` (the tables, with the command, date and commit),
``<out>/standings.json`` (the figures, with the same stamp) and ``<out>/rows/<id>__<agent>.json``
(each agent's episode rows, reused by a later run of the same episodes and code unless
``--fresh``, so an interrupted run resumes).
"""

from __future__ import annotations

import argparse
import json
import math
import shlex
import sys
import time
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import gymnasium

from agents.evaluation.agent_specs import make_agent
from agents.evaluation.evaluation import task_of
from agents.evaluation.fingerprints import code_fingerprints
from agents.rollout import evaluate_agent
from agents.run_dir import write_atomically
from agents.scripted import ORACLE, scripted_agents_for
from benchmarks.arguments import positive_int
from benchmarks.performance_page import stamp
from tactile_search import ENV_IDS
from tactile_search.benchmark.statistics import Summary, summarize
from tactile_search.seed_ranges import held_out_seeds

#: Tasks scored by success against the oracle here; the map task has no success (its scores
#: are distances: ``benchmarks.map_standings``).
SUCCESS_TASKS = ("search", "identify")


def standing_ids() -> list[str]:
    """The registered ids of a task scored by success (``SUCCESS_TASKS``) that a scripted
    baseline other than the oracle plays (an id of another task has nothing to stand against
    the oracle yet)."""
    return [
        env_id
        for env_id in ENV_IDS
        if task_of(env_id) in SUCCESS_TASKS
        and any(a != ORACLE for a in scripted_agents_for(task_of(env_id)))
    ]


def tier_agents(env_id: str) -> list[str]:
    """The scripted agents run on ``env_id``: those that play its task, the oracle last."""
    agents = scripted_agents_for(task_of(env_id))
    return [a for a in agents if a != ORACLE] + [ORACLE]


def agent_rows(
    env_id: str, spec: str, seeds: Sequence[int], out: Path, fresh: bool
) -> tuple[list[dict[str, Any]], str, str]:
    """One scripted agent's rows on ``env_id``'s layouts ``seeds`` (reused from
    ``out/rows`` when the seeds and the code's fingerprint match, unless ``fresh``), its
    env's action mode and map."""
    agent, env_kwargs = make_agent(spec)
    settings = dict(gymnasium.spec(env_id).kwargs)
    env_kwargs = {**env_kwargs, **settings}
    fingerprint = code_fingerprints([spec], env_settings=settings)[spec]
    path = out / "rows" / f"{env_id.split('/')[-1]}__{spec}.json"
    mode = env_kwargs.get("action_mode", "wrist")
    if not fresh and path.exists():
        kept = json.loads(path.read_text())
        if kept["fingerprint"] == fingerprint and kept["seeds"] == list(seeds):
            return kept["rows"], mode, env_kwargs["map"]
    started = time.perf_counter()
    rows = evaluate_agent(agent, list(seeds), **env_kwargs)
    seconds = time.perf_counter() - started
    path.parent.mkdir(parents=True, exist_ok=True)
    record = {"env_id": env_id, "agent": spec, "fingerprint": fingerprint, "seeds": list(seeds)}
    write_atomically(path, json.dumps({**record, "seconds": seconds, "rows": rows}))
    return rows, mode, env_kwargs["map"]


def standing(env_id: str, spec: str, summary: Summary, mode: str) -> dict[str, Any]:
    """One row of the standings: the summary's figures that matter across tasks."""
    return {
        "env_id": env_id,
        "agent": spec,
        "action_mode": mode,
        "map": summary.map_mode,
        "episodes": summary.episodes,
        "successes": summary.successes,
        "success": summary.success_rate,
        "success_low": summary.success_low,
        "success_high": summary.success_high,
        "wrong_claim_rate": summary.wrong_claim_rate,
        "steps_median": summary.steps_median,
        "steps_q1": summary.steps_q1,
        "steps_q3": summary.steps_q3,
        "tip_rate": summary.tip_rate,
    }


def headroom(rows: Sequence[dict[str, Any]]) -> list[dict[str, Any]]:
    """Per id: the best baseline (the highest success, the oracle aside), the oracle and the
    difference in success (points)."""
    result = []
    for env_id in dict.fromkeys(r["env_id"] for r in rows):
        tier = [r for r in rows if r["env_id"] == env_id]
        oracle = next(r for r in tier if r["agent"] == ORACLE)
        best = max((r for r in tier if r["agent"] != ORACLE), key=lambda r: r["success"])
        result.append(
            {
                "env_id": env_id,
                "best_baseline": best["agent"],
                "best_success": best["success"],
                "oracle_success": oracle["success"],
                "gap_points": 100 * (oracle["success"] - best["success"]),
            }
        )
    return result


def _steps(r: dict[str, Any]) -> str:
    if math.isnan(r["steps_median"]):
        return "-"
    return f"{r['steps_median']:.0f} [{r['steps_q1']:.0f}, {r['steps_q3']:.0f}]"


def markdown(rows: Sequence[dict[str, Any]], gaps: Sequence[dict[str, Any]], info: dict) -> str:
    """The standings and the headroom as markdown, under the command, date and commit."""
    lines = [
        "# Where each task stands",
        "",
        f"`{info['command']}` ({info['date']}, commit {info['commit']}, "
        f"{info['machine']['cpu']}). The first {rows[0]['episodes']} validation layouts "
        "of each id, the same for every agent; scripted agents on the GPIS map, each in its own "
        "action mode, the id's settings over it. Steps: wrist motions (the time limit's count, "
        "200) to success. Wrong claims: episodes ended by a claim that did not name the target.",
        "",
        "| id | agent | action mode | success | 95 % CI | wrong claims "
        "| steps to success, median [Q1, Q3] | episodes with a tip |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for r in rows:
        identify = task_of(r["env_id"]) == "identify"
        wrong = f"{r['wrong_claim_rate']:.1%}" if identify else "-"
        lines.append(
            f"| {r['env_id'].split('/')[-1]} | {r['agent']} | {r['action_mode']} "
            f"| {r['success']:.1%} | [{r['success_low']:.1%}, {r['success_high']:.1%}] "
            f"| {wrong} | {_steps(r)} | {r['tip_rate']:.1%} |"
        )
    lines += [
        "",
        "Headroom: the best baseline (the oracle aside) below the oracle.",
        "",
        "| id | best baseline | its success | oracle | gap (points) |",
        "|---|---|---|---|---|",
    ]
    for g in gaps:
        lines.append(
            f"| {g['env_id'].split('/')[-1]} | {g['best_baseline']} | {g['best_success']:.1%} "
            f"| {g['oracle_success']:.1%} | {g['gap_points']:.1f} |"
        )
    return "\n".join(lines) + "\n"


def run(
    env_ids: Sequence[str], episodes: int, out: Path, fresh: bool = False, command: str = ""
) -> dict[str, Any]:
    """Runs every tier's agents, writes ``<out>/standings.md`` and ``<out>/standings.json``;
    returns what the JSON holds."""
    seeds = held_out_seeds("validation", episodes)
    rows = []
    for env_id in env_ids:
        for spec in tier_agents(env_id):
            episode_rows, mode, map_mode = agent_rows(env_id, spec, seeds, out, fresh)
            rows.append(standing(env_id, spec, summarize(spec, map_mode, episode_rows), mode))
            r = rows[-1]
            print(
                f"{env_id}: {spec}: success {r['success']:.1%}, "
                f"wrong claims {r['wrong_claim_rate']:.1%}",
                flush=True,
            )
    gaps = headroom(rows)
    info = {**stamp(command), "episodes": episodes, "seeds": [seeds[0], seeds[-1]]}
    result = {**info, "standings": rows, "headroom": gaps}
    out.mkdir(parents=True, exist_ok=True)
    write_atomically(out / "standings.json", json.dumps(result, indent=2) + "\n")
    table = markdown(rows, gaps, info)
    write_atomically(out / "standings.md", table)
    print(table)
    return result


def main(argv: list[str] | None = None) -> dict[str, Any]:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--episodes", type=positive_int, default=200)
    parser.add_argument("--out", type=Path, default=Path("results/task_standings"))
    parser.add_argument(
        "--env-ids",
        nargs="+",
        choices=standing_ids(),
        default=standing_ids(),
        help="the registered ids to run (default: every one whose task a scripted baseline plays)",
    )
    parser.add_argument("--fresh", action="store_true", help="run again the rows kept in --out")
    args = parser.parse_args(argv)
    command = "python -m benchmarks.task_standings " + shlex.join(
        sys.argv[1:] if argv is None else argv
    )
    return run(args.env_ids, args.episodes, args.out, args.fresh, command.strip())


if __name__ == "__main__":
    main()
