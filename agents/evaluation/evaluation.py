"""The evaluation of trained models and scripted baselines on held-out layouts:
``evaluate``, under the thin CLI ``python -m agents.evaluate``::

    python -m agents.evaluate --runs runs/ppo_gpis_seed0 runs/ppo_none_seed0 \\
        --scripted random gpis_probe_planner oracle --episodes 200 --out results

Every agent meets the same held-out layouts: the first seeds of the validation range
(``tactile_search.seed_ranges``: 1,000,000 and up, never drawn in training), or of the test range
(2,000,000 and up) in the final evaluation only (``--split test --final``: ``make results``
does it), in the environment's default reward (no shaping) with the map mode the agent was
trained with (scripted agents use the GPIS map). Writes to ``--out``:

- ``results.md``: the table (success rate with its 95 % Wilson interval, steps to success
  as median and quartiles, jar displacement, tips, final map IoU);
- ``episodes.csv``: one row per agent and episode, each written as soon as its episode ends;
- ``success.png``, ``steps.png``, ``learning_curves.png`` (from each run's ``progress.csv``);
- ``gifs/<agent>.gif``: one example episode per agent (the first held-out seed; of a learned
  agent trained with several seeds, the first of its runs given).

An interrupted evaluation resumes: run the same command again and the rows already in
``episodes.csv`` are reused, only the missing (agent, seed) episodes run, and the files
come out as an uninterrupted run writes them. A row is reused only if its ``fingerprint``
(a hash of the installed tactile_search package, the agents' code and, for a learned agent,
its model's contents) matches, and a GIF only if the provenance stored in it does;
``--fresh`` runs everything again.
"""

from __future__ import annotations

import csv
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import gymnasium

from agents.command_args import settings_label
from agents.evaluation.agent_specs import make_agent, unique_names
from agents.evaluation.ensemble import ensemble_members
from agents.evaluation.episodes_csv import (
    EPISODE_COLUMNS,
    episode_row,
    reusable_rows,
    write_episodes_csv,
)
from agents.evaluation.fingerprints import code_fingerprints
from agents.evaluation.gifs import gif_drawn_by, gif_provenance, record_gif
from agents.evaluation.report import markdown_table, plot_learning_curves, plot_steps, plot_success
from agents.rollout import evaluate_agent
from agents.run_dir import write_atomically
from agents.scripted import SCRIPTED_AGENTS
from tactile_search import ENV_ID, ENV_IDS
from tactile_search._core import registered_envs
from tactile_search._validation import as_bool
from tactile_search.benchmark.statistics import Summary, summarize
from tactile_search.benchmark.summary_table import MAP_TASK
from tactile_search.envs.config import SETTINGS
from tactile_search.seed_ranges import held_out_seeds


def evaluation_seeds(split: str, episodes: int, final: bool = False) -> list[int]:
    """The first ``episodes`` layout seeds of the held-out range ``split``; the test range
    only for the final evaluation (``final=True``), so that nothing is chosen on it."""
    if split == "test" and final is not True:
        raise ValueError(
            "the test layouts are read only by the final results (make results, "
            "agents.pipeline --budget full): develop on split='validation', or pass "
            "final=True (--final) for the final evaluation"
        )
    return held_out_seeds(split, episodes)


def prepare_evaluation(
    agent_specs: Sequence[str],
    out: Path,
    seeds: Sequence[int],
    resume: bool,
    actions: str = "recipe",
    blanked: Sequence[str] = (),
    env_settings: Mapping[str, Any] | None = None,
    env_id: str | None = None,
) -> tuple[list[tuple[Any, dict[str, Any]]], list[str], dict[str, str], dict]:
    """What an evaluation of ``agent_specs`` on ``seeds`` into ``out`` starts from: each
    agent with its env settings (``make_agent``, then the registered ``env_id``'s settings
    and ``env_settings`` over them), their unique names (with the id's name and the
    ``env_settings``' label), their fingerprints by spec, and the rows of
    ``<out>/episodes.csv`` it reuses (none without ``resume``), by (name, seed);
    ``episodes.csv`` is rewritten to hold just those, agents as given, seeds ascending."""
    out.mkdir(parents=True, exist_ok=True)
    env_settings = checked_env_settings(env_settings)
    id_settings = env_id_settings(env_id)
    settings = {**id_settings, **env_settings}
    made = [
        (agent, {**env_kwargs, **settings})
        for agent, env_kwargs in (make_agent(spec, actions, blanked) for spec in agent_specs)
    ]
    names = unique_names([agent for agent, _ in made], agent_specs)
    if env_id not in (None, ENV_ID):
        names = [f"{name} [{env_id.split('/')[-1]}]" for name in names]
    if env_settings:
        names = [f"{name} [{settings_label(env_settings)}]" for name in names]
    fingerprints = code_fingerprints(agent_specs, actions, blanked, settings)
    map_modes = [env_kwargs["map"] for _, env_kwargs in made]
    csv_path = out / "episodes.csv"
    done = (
        reusable_rows(csv_path, names, map_modes, [fingerprints[s] for s in agent_specs], seeds)
        if resume
        else {}
    )
    kept = [done[name, seed] for name in names for seed in seeds if (name, seed) in done]
    write_episodes_csv(csv_path, kept)
    return made, names, fingerprints, done


def task_of(env_id: str) -> str:
    """The task (the ``task`` setting) registered id ``env_id`` asks, from the core's
    registry; ``ValueError`` for an id that is not registered."""
    for env in registered_envs():
        if env["id"] == env_id:
            return str(env["task"])
    raise ValueError(f"env_id must be one of {list(ENV_IDS)}, got {env_id!r}")


def env_id_settings(env_id: str | None) -> dict[str, Any]:
    """The settings a registered id (``tactile_search.ENV_IDS``) makes its env with
    (``gymnasium.spec(env_id).kwargs``), ``{}`` for None; ``ValueError`` for an id that is
    not registered. Every one is a setting of the core (``checked_env_settings``)."""
    if env_id is None:
        return {}
    if env_id not in ENV_IDS:
        raise ValueError(f"env_id must be one of {list(ENV_IDS)}, got {env_id!r}")
    return checked_env_settings(gymnasium.spec(env_id).kwargs)


def evaluated_task(env_id: str | None, env_settings: Mapping[str, Any] | None = None) -> str:
    """The task (the ``task`` setting) an evaluation on ``env_id`` with ``env_settings`` over
    it plays: the core's default where neither sets it."""
    settings = {**env_id_settings(env_id), **checked_env_settings(env_settings)}
    default = next(entry["default"] for entry in SETTINGS if entry["key"] == "task")
    return str(settings.get("task", default))


def checked_env_settings(env_settings: Mapping[str, Any] | None) -> dict[str, Any]:
    """``env_settings`` as a dict, each key a setting of the environment's core
    (``tactile_search.envs.config.SETTINGS``), else ``ValueError`` naming it; ``map`` and
    ``action_mode`` are refused, being what an agent was made for. The values are checked
    where every setting is, when the environment is made."""
    settings = dict(env_settings or {})
    known = {entry["key"] for entry in SETTINGS}
    for key in settings:
        if key in ("map", "action_mode"):
            raise ValueError(f"env_settings may not change {key!r}: each agent is made for its own")
        if key not in known:
            raise ValueError(
                f"env_settings: {key!r} is not a setting of the environment "
                "(tactile_search.CupboardSearchEnv's keyword arguments)"
            )
    return settings


def example_gif(
    out: Path,
    agent: Any,
    env_kwargs: dict[str, Any],
    seed: int,
    steps: int,
    provenance: str,
    reuse: bool,
) -> Path:
    """``out/gifs/<agent>.gif``: the agent's first ``steps`` on layout ``seed``, drawn unless
    ``reuse`` and the GIF there stores the same ``provenance`` (``gif_drawn_by``)."""
    file_name = agent.name.replace(" ", "_").replace("(", "").replace(")", "")
    path = out / "gifs" / f"{file_name.replace(',', '')}.gif"
    if not reuse or gif_drawn_by(path) != provenance:
        path.parent.mkdir(exist_ok=True)
        record_gif(path, agent, env_kwargs, seed, max_steps=steps, drawn_by=provenance)
    return path


def evaluate(
    agent_specs: Sequence[str],
    *,
    out: Path = Path("results"),
    episodes: int = 200,
    split: str = "validation",
    final: bool = False,
    gifs: bool = True,
    gif_steps: int = 200,
    torch_threads: int = 1,
    resume: bool = True,
    actions: str = "recipe",
    blanked: Sequence[str] = (),
    env_settings: Mapping[str, Any] | None = None,
    env_id: str | None = None,
) -> list[Summary]:
    """Runs every agent on the same held-out layouts and writes the table, plots and GIFs.

    ``split``: ``validation`` or ``test`` (``tactile_search.seed_ranges``; the test range only with
    ``final=True``, ``evaluation_seeds``); the first ``episodes`` seeds of it.

    ``agent_specs``: scripted agent names (``random``, ``gpis_probe_planner``, ``oracle``) and run
    directories of ``agents.train``. ``gif_steps`` caps the steps an example GIF shows.
    ``torch_threads``: one thread predicts a single observation fastest (more threads only
    add synchronisation, and spin against anything else running). ``actions``: how learned
    agents act (``ACTIONS``: as each recipe says, the policy's mode, sampled, or the mode
    until a probe changes nothing, then sampled).
    ``blanked``: map channels every agent reads held at a pixel value (``NAME=VALUE`` each,
    ``agents.evaluation.map_ablation``; the agents' names say so).
    ``env_settings``: settings of the environment's core every agent is evaluated with over
    its own (such as ``{"fast_free_motion": True}``; not ``map`` or ``action_mode``); the
    agents' names end with them in brackets.
    ``env_id``: a registered id (``tactile_search.ENV_IDS``) whose task and tier every agent
    is evaluated in: its settings (``gymnasium.spec(env_id).kwargs``) go over each agent's
    own and under ``env_settings``; the agents' names end with the id's name in brackets
    (none for the default id, ``tactile_search.ENV_ID``, whose settings are the defaults).

    Each episode's row is appended to ``<out>/episodes.csv`` (and flushed) as the episode
    ends. With ``resume`` (the default) the rows already there whose agent, map, held-out
    seed and fingerprint (``code_fingerprints``) match are reused and only the other
    episodes run; the other rows are dropped. An agent's GIF is kept if its stored
    provenance (``gif_provenance``: the same fingerprint, layout and length) matches,
    otherwise drawn (always drawn without ``resume``). At the
    end ``episodes.csv`` is rewritten in the order an uninterrupted run writes it (agents as
    given, seeds ascending), so a resumed evaluation's files equal an uninterrupted one's.
    """
    if not agent_specs:
        raise ValueError("give at least one agent (a scripted name or a run directory)")
    as_bool("resume", resume)
    if any(spec not in SCRIPTED_AGENTS for spec in agent_specs):
        import torch

        torch.set_num_threads(torch_threads)
    out = Path(out)
    seeds = evaluation_seeds(split, episodes, final)
    task = evaluated_task(env_id, env_settings)
    made, names, fingerprints, done = prepare_evaluation(
        agent_specs, out, seeds, resume, actions, blanked, env_settings, env_id
    )
    csv_path = out / "episodes.csv"

    def ordered(name: str) -> list[dict[str, Any]]:
        return [done[name, seed] for seed in seeds if (name, seed) in done]

    summaries, all_episodes = [], []
    runs: list[tuple[str, Path]] = []  # (agent, run directory) of each learned run
    shown: set[str] = set()  # the agents with a GIF: one per agent, not per training seed
    with csv_path.open("a", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=list(EPISODE_COLUMNS))
        for spec, name, (agent, env_kwargs) in zip(agent_specs, names, made, strict=True):
            map_mode = env_kwargs["map"]

            def keep(
                result: dict[str, Any],
                name: str = name,
                map_mode: str = map_mode,
                fingerprint: str = fingerprints[spec],
            ) -> None:
                row = episode_row(name, map_mode, result, fingerprint)
                writer.writerow(row)
                f.flush()
                done[name, row["seed"]] = row

            todo = [seed for seed in seeds if (name, seed) not in done]
            if todo:
                evaluate_agent(agent, todo, on_episode=keep, **env_kwargs)
            results = ordered(name)
            summaries.append(summarize(name, map_mode, results))
            all_episodes.append(results)
            # agent.name: the agent without its training seed (unique_names adds it to name)
            if spec not in SCRIPTED_AGENTS and ensemble_members(spec) is None:
                runs.append((agent.name, Path(spec)))
            if gifs and agent.name not in shown:
                shown.add(agent.name)
                provenance = gif_provenance(fingerprints[spec], seeds[0], gif_steps)
                example_gif(out, agent, env_kwargs, seeds[0], gif_steps, provenance, resume)
            print(markdown_table(summaries[-1:], task).splitlines()[-1], flush=True)
    write_episodes_csv(csv_path, [row for name in names for row in ordered(name)])
    table = markdown_table(summaries, task)
    where = "" if env_id is None else f" of {env_id}"
    write_atomically(
        out / "results.md",
        f"Held-out {split} layout seeds {seeds[0]}..{seeds[-1]}{where} ({episodes} per agent)."
        f"\n\n{table}",
    )
    if task != MAP_TASK:  # the map task has no success to plot (its scores: curves.png)
        plot_success(out / "success.png", summaries)
        plot_steps(out / "steps.png", names, all_episodes)
    plot_learning_curves(out / "learning_curves.png", runs)
    return summaries
