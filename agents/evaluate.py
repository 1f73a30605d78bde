"""Evaluate trained models and scripted baselines on held-out layouts.

Importable functions under a thin CLI::

    python -m agents.evaluate --runs runs/ppo_gpis_seed0 runs/ppo_none_seed0 \\
        --scripted random gpis_planner oracle --episodes 200 --out results

Every agent meets the same held-out layouts: the first seeds of the validation range
(``agents.seed_ranges``: 1,000,000 and up, never drawn in training), or of the test range
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

import argparse
import csv
import hashlib
import inspect
import json
import math
import os
import statistics
import zipfile
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

import tactile_search  # also registers the environment
from agents.learned import evaluation_env_kwargs
from agents.scripted import SCRIPTED_AGENTS
from agents.scripted.rollout import run_episodes
from agents.seed_ranges import SPLITS, held_out_seeds
from agents.train import read_run_config, write_atomically
from tactile_search import CupboardSearchEnv

# The z of a two-sided 95 % interval.
Z_95 = 1.959963984540054


@dataclass(frozen=True)
class Summary:
    """One agent's results over the held-out episodes."""

    agent: str
    map_mode: str
    episodes: int
    successes: int
    success_low: float
    success_high: float
    steps_median: float
    steps_q1: float
    steps_q3: float
    displacement_mm: float
    # Mean over the successful episodes alone (NaN without one): measured per episode, not
    # the episode mean divided by the success rate.
    success_displacement_mm: float
    max_displacement_mm: float
    tip_rate: float
    iou: float

    @property
    def success_rate(self) -> float:
        return self.successes / self.episodes


def wilson_interval(successes: int, n: int, z: float = Z_95) -> tuple[float, float]:
    """The Wilson score interval of a binomial proportion (95 % by default)."""
    if n <= 0:
        raise ValueError(f"n must be positive, got {n}")
    if not 0 <= successes <= n:
        raise ValueError(f"successes must be in [0, {n}], got {successes}")
    p = successes / n
    denominator = 1 + z * z / n
    centre = (p + z * z / (2 * n)) / denominator
    half = z * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / denominator
    # The interval always holds p (at p = 0 or 1 rounding could leave it a hair outside).
    return max(0.0, min(p, centre - half)), min(1.0, max(p, centre + half))


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


def summarize(agent: str, map_mode: str, episodes: Sequence[dict[str, Any]]) -> Summary:
    """The table row of one agent's per-episode results (``run_episodes`` dicts)."""
    n = len(episodes)
    successes = sum(bool(e["success"]) for e in episodes)
    low, high = wilson_interval(successes, n)
    steps = sorted(e["steps"] for e in episodes if e["success"])
    if len(steps) >= 2:
        q1, median, q3 = statistics.quantiles(steps, n=4, method="inclusive")
    elif steps:
        q1 = median = q3 = float(steps[0])
    else:
        q1 = median = q3 = math.nan
    succeeded = [e["jar_displacement"] for e in episodes if e["success"]]
    return Summary(
        agent=agent,
        map_mode=map_mode,
        episodes=n,
        successes=successes,
        success_low=low,
        success_high=high,
        steps_median=median,
        steps_q1=q1,
        steps_q3=q3,
        displacement_mm=1000 * statistics.fmean(e["jar_displacement"] for e in episodes),
        success_displacement_mm=1000 * statistics.fmean(succeeded) if succeeded else math.nan,
        max_displacement_mm=1000 * statistics.fmean(e["max_jar_displacement"] for e in episodes),
        tip_rate=statistics.fmean(e["tips"] > 0 for e in episodes),
        iou=statistics.fmean(e["iou"] for e in episodes),
    )


def markdown_table(summaries: Sequence[Summary]) -> str:
    """The results as a markdown table."""
    lines = [
        "| agent | map | episodes | success | 95 % CI | steps to success, median [Q1, Q3] "
        "| jar displacement (mm, sum over jars) | in successful episodes (mm) "
        "| largest jar displacement (mm) | episodes with a tip "
        "| final map IoU (the map's own reading) |",
        "|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for s in summaries:
        steps = (
            "-"
            if math.isnan(s.steps_median)
            else f"{s.steps_median:.0f} [{s.steps_q1:.0f}, {s.steps_q3:.0f}]"
        )
        iou = "-" if s.map_mode == "none" else f"{s.iou:.3f}"
        in_successes = (
            "-" if math.isnan(s.success_displacement_mm) else f"{s.success_displacement_mm:.1f}"
        )
        lines.append(
            f"| {s.agent} | {s.map_mode} | {s.episodes} | {s.success_rate:.1%} "
            f"| [{s.success_low:.1%}, {s.success_high:.1%}] | {steps} "
            f"| {s.displacement_mm:.1f} | {in_successes} | {s.max_displacement_mm:.1f} "
            f"| {s.tip_rate:.1%} "
            f"| {iou} |"
        )
    return "\n".join(lines) + "\n"


# How a learned agent picks its actions: as its recipe says (deterministic_evaluation), the
# policy's mode, or a sample from it (seeded per episode).
ACTIONS = ("recipe", "mode", "sample")


def _deterministic(actions: str) -> bool | None:
    if actions not in ACTIONS:
        raise ValueError(f"actions must be one of {ACTIONS}, got {actions!r}")
    return {"recipe": None, "mode": True, "sample": False}[actions]


def make_agent(spec: str, actions: str = "recipe") -> tuple[Any, dict[str, Any]]:
    """An agent and the settings of the env it is evaluated in (with its ``map``) from a
    scripted name (the GPIS map) or a run directory (its recipe's env settings without the
    reward terms: ``agents.learned.evaluation_env_kwargs``), its actions chosen as
    ``actions`` says (``ACTIONS``).

    A scripted agent that takes a ``seed`` (the random agent) is made afresh for every
    episode, seeded with the episode's layout seed (``SeededPerEpisode``)."""
    if spec in SCRIPTED_AGENTS:
        factory = SCRIPTED_AGENTS[spec]
        if "seed" in inspect.signature(factory).parameters:
            return SeededPerEpisode(factory), {"map": "gpis"}
        return factory(), {"map": "gpis"}
    from agents.learned import LearnedAgent

    agent = LearnedAgent(Path(spec), deterministic=_deterministic(actions))
    return agent, agent.env_kwargs


class SeededPerEpisode:
    """An agent with its own random generator, made afresh at every reset and seeded with
    the episode's layout seed: an episode's actions then do not depend on the episodes run
    before it, so an evaluation resumed part-way gives the rows of an uninterrupted one."""

    def __init__(self, factory: Any) -> None:
        self._factory = factory
        self._agent = factory(seed=0)
        self.name: str = self._agent.name

    def reset(self, env: Any, observation: dict, info: dict) -> None:
        self._agent = self._factory(seed=env.np_random_seed)
        self._agent.reset(env, observation, info)

    def act(self, observation: dict) -> np.ndarray:
        return self._agent.act(observation)


# The columns of episodes.csv and their types (those of run_episodes' values).
EPISODE_COLUMNS: dict[str, type] = {
    "agent": str,
    "map": str,
    "seed": int,
    "success": bool,
    "steps": int,
    "actions": int,
    "tips": int,
    "jar_displacement": float,
    "max_jar_displacement": float,
    "iou": float,
    "reward": float,
    "fingerprint": str,
}


def _parse(kind: type, text: str) -> Any:
    if kind is bool:
        return {"True": True, "False": False}[text]
    return kind(text)


def episode_row(agent: str, map_mode: str, result: dict[str, Any], fingerprint: str) -> dict:
    """One row of episodes.csv, each value of its column's type: what ``read_episodes_csv``
    gives back, so a row written, read back and written again is the same text."""
    row = {"agent": agent, "map": map_mode, **result, "fingerprint": fingerprint}
    if set(row) != set(EPISODE_COLUMNS):
        raise ValueError(
            f"an episode's summary must have the columns {list(EPISODE_COLUMNS)} of "
            f"episodes.csv, got {sorted(row)} (a new metric goes into EPISODE_COLUMNS too)"
        )
    return {key: kind(row[key]) for key, kind in EPISODE_COLUMNS.items()}


def read_episodes_csv(path: Path) -> tuple[list[dict[str, Any]], int]:
    """The complete, well-formed rows of an episodes.csv, typed as ``run_episodes`` returns
    them, and how many lines were not (a line cut short by a kill, a file of another layout)."""
    if not path.is_file():
        return [], 0
    with path.open(newline="") as f:
        lines = f.read().splitlines(keepends=True)
    if not lines or next(csv.reader([lines[0]]), []) != list(EPISODE_COLUMNS):
        return [], max(0, len(lines) - 1)
    rows, bad = [], 0
    for line in lines[1:]:
        values = next(csv.reader([line]), [])
        if not line.endswith("\n") or len(values) != len(EPISODE_COLUMNS):
            bad += 1
            continue
        try:
            rows.append(
                {
                    key: _parse(kind, text)
                    for (key, kind), text in zip(EPISODE_COLUMNS.items(), values, strict=True)
                }
            )
        except (ValueError, KeyError):
            bad += 1
    return rows, bad


def write_episodes_csv(path: Path, rows: Sequence[dict[str, Any]]) -> None:
    """Per-episode rows (agent, map, seed, metrics, fingerprint), written atomically."""
    with (path.with_name(path.name + ".tmp")).open("w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=list(EPISODE_COLUMNS))
        writer.writeheader()
        writer.writerows(rows)
    os.replace(path.with_name(path.name + ".tmp"), path)


def _digest(paths: Sequence[Path], root: Path) -> bytes:
    sha = hashlib.sha256()
    for path in sorted(paths):
        sha.update(str(path.relative_to(root)).encode() + b"\0" + path.read_bytes() + b"\0")
    return sha.digest()


def model_digest(path: Path) -> bytes:
    """A hash of what a ``model.zip`` holds, not of the archive's bytes, so that the same
    model trained twice (one run after another, or as a Ray trial) gets the same digest.

    It covers every member (the weights, optimizer state, versions) and the ``data`` member's
    plain settings; not what differs between identical trainings: the archive's write times,
    ``data``'s ``start_time`` and its pickled objects (classes and spaces, whose pickles are
    not byte-stable; the spaces are checked on load, the classes follow from the algorithm)."""
    sha = hashlib.sha256()
    try:
        with zipfile.ZipFile(path) as archive:
            for name in sorted(archive.namelist()):
                content = archive.read(name)
                if name == "data":
                    data = json.loads(content)
                    plain = {
                        key: value
                        for key, value in data.items()
                        if key != "start_time"
                        and not (isinstance(value, dict) and ":serialized:" in value)
                    }
                    content = json.dumps(plain, sort_keys=True).encode()
                sha.update(name.encode() + b"\0" + content + b"\0")
    except (zipfile.BadZipFile, OSError, EOFError, ValueError) as err:
        raise ValueError(
            f"{path} is not a readable model archive (truncated or corrupt?): {err}"
        ) from err
    return sha.digest()


def code_fingerprints(agent_specs: Sequence[str], actions: str = "recipe") -> dict[str, str]:
    """What produced an agent's rows, per spec: a hash of the installed tactile_search
    package (its Python files and compiled core), the agents' code (``agents/scripted/``,
    which holds the rollout, and ``agents/learned.py``) and, for a learned agent, its
    ``model.zip``'s contents (``model_digest``). Rows of another fingerprint are not
    reused."""
    package = Path(tactile_search.__file__).parent
    env_files = [
        p
        for p in package.rglob("*")
        if p.is_file() and p.suffix in (".py", ".so", ".pyd") and "__pycache__" not in p.parts
    ]
    agents_dir = Path(__file__).parent
    agent_files = [*(agents_dir / "scripted").glob("*.py"), agents_dir / "learned.py"]
    base = _digest(env_files, package) + _digest(agent_files, agents_dir)
    fingerprints = {}
    for spec in agent_specs:
        sha = hashlib.sha256(base)
        if spec not in SCRIPTED_AGENTS:
            sha.update(model_digest(Path(spec) / "model.zip"))
            config = read_run_config(Path(spec))
            env_kwargs = evaluation_env_kwargs(config)
            sha.update(json.dumps(env_kwargs, sort_keys=True, default=str).encode())
            # Whether its actions are the policy's mode or samples from it.
            deterministic = _deterministic(actions)
            if deterministic is None:
                deterministic = config["hyperparams"].get("deterministic_evaluation", True)
            sha.update(b"deterministic" if deterministic else b"sampled")
        fingerprints[spec] = sha.hexdigest()[:16]
    return fingerprints


def seeded_name(algo: str, map_mode: str, seed: int) -> str:
    """The evaluated name of one training seed's run when an agent has several
    (``agents.comparison.agent_and_seed`` reads it back)."""
    return f"{algo} ({map_mode} map, seed {seed})"


def unique_names(agents: Sequence[Any], specs: Sequence[str]) -> list[str]:
    """The agents' names, made unique: learned agents of the same algorithm and map (several
    training seeds) get their run's seed in the name."""
    given = [agent.name for agent in agents]
    names = list(given)
    for i, (agent, spec) in enumerate(zip(agents, specs, strict=True)):
        if given.count(agent.name) > 1 and spec not in SCRIPTED_AGENTS:
            config = agent.config
            names[i] = seeded_name(config["algo"], config["map"], config["seed"])
    repeated = sorted({name for name in names if names.count(name) > 1})
    if repeated:
        raise ValueError(f"each agent may be evaluated once, got {repeated} more than once")
    return names


def plot_success(path: Path, summaries: Sequence[Summary]) -> None:
    """Success rate per agent with its 95 % interval."""
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(1.2 + 1.3 * len(summaries), 3.6))
    x = np.arange(len(summaries))
    rates = [s.success_rate for s in summaries]
    errors = [
        [s.success_rate - s.success_low for s in summaries],
        [s.success_high - s.success_rate for s in summaries],
    ]
    ax.bar(x, rates, yerr=errors, capsize=5, color="tab:blue", alpha=0.8)
    ax.set_xticks(x, [s.agent for s in summaries], rotation=20, ha="right")
    ax.set_ylim(0, 1.05)
    ax.set_ylabel("success rate (95 % CI)")
    ax.set_title(f"{summaries[0].episodes} held-out episodes per agent")
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def plot_steps(path: Path, agents: Sequence[str], episodes: Sequence[Sequence[dict]]) -> None:
    """Steps to success per agent (successful episodes only)."""
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(1.2 + 1.3 * len(agents), 3.6))
    data = [[e["steps"] for e in runs if e["success"]] or [math.nan] for runs in episodes]
    ax.boxplot(data)
    ax.set_xticks(range(1, len(agents) + 1), agents, rotation=20, ha="right")
    ax.set_ylabel("steps to success")
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def read_progress(run_dir: Path) -> dict[str, np.ndarray]:
    """``timesteps`` and ``success_rate`` columns of a run's ``progress.csv``."""
    with (Path(run_dir) / "progress.csv").open() as f:
        rows = list(csv.DictReader(f))
    timesteps, success = [], []
    for row in rows:
        if row.get("rollout/success_rate") not in (None, ""):
            timesteps.append(float(row["time/total_timesteps"]))
            success.append(float(row["rollout/success_rate"]))
    return {"timesteps": np.array(timesteps), "success_rate": np.array(success)}


def plot_learning_curves(path: Path, runs: Sequence[tuple[str, Path]]) -> list[str]:
    """Training success rate (last 100 episodes) against timesteps, per learned run, given
    as (agent, run directory): an agent's training seeds share a colour (one legend entry per
    agent). Returns the legend's entries."""
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6, 3.6))
    colours: dict[str, str] = {}
    for agent, run_dir in runs:
        first = agent not in colours
        colours.setdefault(agent, f"C{len(colours) % 10}")
        curve = read_progress(run_dir)
        ax.plot(
            curve["timesteps"],
            curve["success_rate"],
            color=colours[agent],
            alpha=0.8,
            label=agent if first else None,
        )
    ax.set_xlabel("training timesteps")
    ax.set_ylabel("success rate (last 100 episodes)")
    ax.set_ylim(0, 1.05)
    if runs:
        ax.legend()
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return list(colours)


def record_gif(
    path: Path,
    agent: Any,
    env_kwargs: dict[str, Any],
    seed: int,
    max_steps: int = 200,
    stride: int = 2,
    drawn_by: str | None = None,
) -> None:
    """The first ``max_steps`` steps of ``agent`` on layout ``seed`` in the env of
    ``env_kwargs`` as a GIF, one frame every ``stride`` wrist motions plus the last (a frame
    takes ~0.2 s to draw); ``drawn_by`` (``gif_provenance``) is stored in the GIF's comment.

    In the ``probe`` action mode a step is many wrist motions: a ``wrist``-mode twin of the
    env, reset to the same layout, replays each step's motions (``last_motions``) so that
    the GIF shows the finger moving, not only where each probe ends."""
    from tactile_search.render import save_gif

    frames: list[np.ndarray] = []
    twin: CupboardSearchEnv | None = None
    motions_drawn = 0  # wrist motions so far

    def capture(env: CupboardSearchEnv, step: int, done: bool) -> None:
        nonlocal twin, motions_drawn
        if env.config.action_mode == "wrist":
            if step % stride == 0 or done:
                frames.append(env.render())
            return
        if step == 0:
            wrist = {**env_kwargs, "action_mode": "wrist"}
            twin = CupboardSearchEnv(render_mode="rgb_array", **wrist)
            twin.reset(seed=seed)
            frames.append(twin.render())
            return
        assert twin is not None
        motions = env.last_motions()
        for i, motion in enumerate(motions):
            twin.step(motion)
            motions_drawn += 1
            if motions_drawn % stride == 0 or (done and i == len(motions) - 1):
                frames.append(twin.render())
        if twin.render_state()["hand"] != env.render_state()["hand"]:
            raise RuntimeError(
                f"the wrist-mode replay of layout {seed} left the probe's path at step {step}"
            )

    run_episodes(
        agent, [seed], max_steps=max_steps, on_step=capture, render_mode="rgb_array", **env_kwargs
    )
    if twin is not None:
        twin.close()
    # Through a temporary file: a GIF that exists is a whole one.
    tmp = path.with_name(f"{path.stem}.tmp.gif")
    save_gif(frames, tmp, comment=drawn_by)
    os.replace(tmp, path)


def gif_provenance(fingerprint: str, seed: int, max_steps: int) -> str:
    """What an example GIF shows, as stored in its comment: the agent's fingerprint
    (``code_fingerprints``), the layout and the steps shown. A GIF is kept only if its
    comment says the same (``gif_drawn_by``), so a GIF left by other code is drawn again."""
    return f"tactile_search example: fingerprint {fingerprint}, layout {seed}, {max_steps} steps"


def gif_drawn_by(path: Path) -> str | None:
    """The provenance stored in the GIF at ``path`` (``record_gif``), or None if there is no
    such GIF or it stores none."""
    from PIL import Image

    try:
        with Image.open(path) as image:
            comment = image.info.get("comment")
    except (OSError, ValueError):  # missing, or not an image
        return None
    return comment.decode(errors="replace") if isinstance(comment, bytes) else None


def reusable_rows(
    csv_path: Path,
    names: Sequence[str],
    map_modes: Sequence[str],
    fingerprints: Sequence[str],
    seeds: Sequence[int],
) -> dict[tuple[str, int], dict[str, Any]]:
    """The rows of ``csv_path`` an evaluation of these agents (names, map modes and
    fingerprints, index by index) on ``seeds`` can reuse, by (agent name, seed); prints how
    many, and how many it drops (incomplete, or of other agents, seeds or code)."""
    wanted = {
        (name, map_mode, seed, fingerprint)
        for name, map_mode, fingerprint in zip(names, map_modes, fingerprints, strict=True)
        for seed in seeds
    }
    earlier, unreadable = read_episodes_csv(csv_path)
    done: dict[tuple[str, int], dict[str, Any]] = {}
    for row in earlier:
        if (row["agent"], row["map"], row["seed"], row["fingerprint"]) in wanted:
            done[row["agent"], row["seed"]] = row
    if earlier or unreadable:
        dropped = len(earlier) + unreadable - len(done)
        print(
            f"reusing {len(done)} episodes of {csv_path}"
            + (
                f" (dropped {dropped}: incomplete, or of other agents, seeds or code)"
                if dropped
                else ""
            ),
            flush=True,
        )
    return done


def prepare_evaluation(
    agent_specs: Sequence[str],
    out: Path,
    seeds: Sequence[int],
    resume: bool,
    actions: str = "recipe",
) -> tuple[list[tuple[Any, dict[str, Any]]], list[str], dict[str, str], dict]:
    """What an evaluation of ``agent_specs`` on ``seeds`` into ``out`` starts from: each
    agent with its env settings (``make_agent``), their unique names, their fingerprints by
    spec, and the rows of ``out/episodes.csv`` it reuses (none without ``resume``), by
    (name, seed); ``episodes.csv`` is rewritten to hold just those, agents as given, seeds
    ascending."""
    out.mkdir(parents=True, exist_ok=True)
    made = [make_agent(spec, actions) for spec in agent_specs]
    names = unique_names([agent for agent, _ in made], agent_specs)
    fingerprints = code_fingerprints(agent_specs, actions)
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
) -> list[Summary]:
    """Runs every agent on the same held-out layouts and writes the table, plots and GIFs.

    ``split``: ``validation`` or ``test`` (``agents.seed_ranges``; the test range only with
    ``final=True``, ``evaluation_seeds``); the first ``episodes`` seeds of it.

    ``agent_specs``: scripted agent names (``random``, ``gpis_planner``, ``oracle``) and run
    directories of ``agents.train``. ``gif_steps`` caps the steps an example GIF shows.
    ``torch_threads``: one thread predicts a single observation fastest (more threads only
    add synchronisation, and spin against anything else running). ``actions``: how learned
    agents act (``ACTIONS``: as each recipe says, the policy's mode, or sampled).

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
    if not isinstance(resume, bool):
        raise TypeError(f"resume must be a bool, got {type(resume).__name__}")
    if any(spec not in SCRIPTED_AGENTS for spec in agent_specs):
        import torch

        torch.set_num_threads(torch_threads)
    out = Path(out)
    seeds = evaluation_seeds(split, episodes, final)
    made, names, fingerprints, done = prepare_evaluation(agent_specs, out, seeds, resume, actions)
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
                run_episodes(agent, todo, on_episode=keep, **env_kwargs)
            results = ordered(name)
            summaries.append(summarize(name, map_mode, results))
            all_episodes.append(results)
            # agent.name: the agent without its training seed (unique_names adds it to name)
            if spec not in SCRIPTED_AGENTS:
                runs.append((agent.name, Path(spec)))
            if gifs and agent.name not in shown:
                shown.add(agent.name)
                file_name = agent.name.replace(" ", "_").replace("(", "").replace(")", "")
                file_name = file_name.replace(",", "")
                gif_path = out / "gifs" / f"{file_name}.gif"
                provenance = gif_provenance(fingerprints[spec], seeds[0], gif_steps)
                if not resume or gif_drawn_by(gif_path) != provenance:
                    gif_path.parent.mkdir(exist_ok=True)
                    record_gif(
                        gif_path,
                        agent,
                        env_kwargs,
                        seeds[0],
                        max_steps=gif_steps,
                        drawn_by=provenance,
                    )
            print(markdown_table(summaries[-1:]).splitlines()[-1], flush=True)
    write_episodes_csv(csv_path, [row for name in names for row in ordered(name)])
    table = markdown_table(summaries)
    write_atomically(
        out / "results.md",
        f"Held-out {split} layout seeds {seeds[0]}..{seeds[-1]} ({episodes} per agent).\n\n{table}",
    )
    plot_success(out / "success.png", summaries)
    plot_steps(out / "steps.png", names, all_episodes)
    plot_learning_curves(out / "learning_curves.png", runs)
    return summaries


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--runs", nargs="*", default=[], help="run directories of agents.train")
    parser.add_argument(
        "--scripted",
        nargs="*",
        default=list(SCRIPTED_AGENTS),
        choices=list(SCRIPTED_AGENTS),
        help="scripted baselines to include",
    )
    parser.add_argument("--episodes", type=int, default=200)
    parser.add_argument(
        "--split",
        choices=sorted(SPLITS),
        default="validation",
        help="the held-out layouts (agents/seed_ranges.py); test only with --final",
    )
    parser.add_argument(
        "--final",
        action="store_true",
        help="this is the final evaluation, which alone may read the test layouts",
    )
    parser.add_argument("--out", type=Path, default=Path("results"))
    parser.add_argument("--no-gifs", action="store_true")
    parser.add_argument("--gif-steps", type=int, default=200, help="steps shown per GIF")
    parser.add_argument(
        "--fresh",
        action="store_true",
        help="run every episode again instead of reusing the rows in --out/episodes.csv",
    )
    parser.add_argument(
        "--actions",
        choices=ACTIONS,
        default="recipe",
        help="learned agents' actions: as each recipe says (deterministic_evaluation), the "
        "policy's mode, or sampled (seeded per episode)",
    )
    args = parser.parse_args(argv)
    summaries = evaluate(
        [*args.runs, *args.scripted],
        out=args.out,
        episodes=args.episodes,
        split=args.split,
        final=args.final,
        gifs=not args.no_gifs,
        gif_steps=args.gif_steps,
        resume=not args.fresh,
        actions=args.actions,
    )
    print(markdown_table(summaries))


if __name__ == "__main__":
    main()
