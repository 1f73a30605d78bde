"""How a probe-mode agent spends its episodes: a diagnostic on the validation layouts.

For each run (a directory of ``agents.train`` trained in the ``probe`` action mode), every
episode's probes are traced (lane, depth and sweep indices, and the wrist motions each
made) and summarised: how many episodes succeed with the first probe, and in the episodes
that time out (neither success nor tip), how many probes they make, how many are waits (a
probe that made no motion: one motionless step), how many return to a lane the episode has
already probed, and what a probe costs in wrist motions when it keeps its lane and when it
changes lane (the time limit counts motions)::

    python -m agents.probe_trace docs/results/models/ppo_gpis_seed0 --episodes 200

Only the validation layouts: this is for understanding and choosing, which the test
layouts are not for (``tactile_search.seed_ranges``).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from agents.evaluation.agent_specs import make_agent
from agents.rollout import run_episodes
from tactile_search.envs import CupboardSearchConfig


@dataclass(frozen=True)
class Probe:
    """One agent step in the probe mode: its indices and the wrist motions it made."""

    lane: int
    depth: int
    sweep: int
    motions: int
    waited: bool  # made no motion (one motionless step)


@dataclass(frozen=True)
class TracedEpisode:
    seed: int
    success: bool
    tipped: bool
    probes: tuple[Probe, ...]

    @property
    def timed_out(self) -> bool:
        return not self.success and not self.tipped


class _Recording:
    """Wraps an agent and keeps the actions it takes (the rollout's ``on_step`` sees the
    env, not the action)."""

    def __init__(self, agent: Any) -> None:
        self.agent = agent
        self.name = agent.name
        self.actions: list[np.ndarray] = []

    def reset(self, env: Any, observation: Any, info: Any) -> None:
        self.actions.clear()
        self.agent.reset(env, observation, info)

    def act(self, observation: Any) -> np.ndarray:
        action = np.asarray(self.agent.act(observation))
        self.actions.append(action)
        return action


def trace(run_dir: Path, seeds: Sequence[int]) -> list[TracedEpisode]:
    """Every episode of the run's agent on ``seeds``, probe by probe."""
    agent, env_kwargs = make_agent(str(run_dir))
    # The mode the core resolves from the recipe's settings (its default where they say none).
    action_mode = CupboardSearchConfig(**env_kwargs).action_mode
    if action_mode != "probe":
        raise ValueError(
            f"{run_dir} was trained in the {action_mode!r} action mode; a probe trace needs "
            "the 'probe' mode"
        )
    recording = _Recording(agent)
    probes: list[Probe] = []
    episodes: list[TracedEpisode] = []

    def on_step(env: Any, step: int, done: bool) -> None:
        if step == 0:
            probes.clear()
            return
        motions = env.last_motions()
        lane, depth, sweep = (int(i) for i in recording.actions[step - 1])
        waited = len(motions) == 1 and not motions.any()
        probes.append(Probe(lane, depth, sweep, len(motions), bool(waited)))

    def on_episode(result: dict[str, Any]) -> None:
        episodes.append(
            TracedEpisode(result["seed"], result["success"], result["tips"] > 0, tuple(probes))
        )

    run_episodes(recording, list(seeds), on_step=on_step, on_episode=on_episode, **env_kwargs)
    return episodes


def summary(episodes: Sequence[TracedEpisode]) -> dict[str, float]:
    """The figures of ``probe_trace``'s table (see the module's docstring)."""
    timed_out = [e for e in episodes if e.timed_out]
    probes = [p for e in timed_out for p in e.probes]
    kept, changed, revisits = [], [], 0
    for episode in timed_out:
        seen: set[int] = set()
        for before, probe in zip((None, *episode.probes), episode.probes, strict=False):
            if before is not None and not probe.waited:
                (kept if probe.lane == before.lane else changed).append(probe.motions)
            revisits += probe.lane in seen
            seen.add(probe.lane)

    def mean(values: Sequence[float]) -> float:
        return float(np.mean(values)) if values else float("nan")

    return {
        "episodes": len(episodes),
        "success": mean([e.success for e in episodes]),
        "first-probe success": mean([e.success and len(e.probes) == 1 for e in episodes]),
        "timed out": mean([e.timed_out for e in episodes]),
        "probes per timed-out episode": mean([len(e.probes) for e in timed_out]),
        "waits (share of their probes)": mean([p.waited for p in probes]),
        "probes in a lane already probed (share)": revisits / len(probes) if probes else np.nan,
        "motions per probe, same lane": mean(kept),
        "motions per probe, lane changed": mean(changed),
    }


def summary_markdown(summaries: dict[str, dict[str, float]]) -> str:
    """One column per run; a figure with nothing to count (NaN in ``summary``) is "-"."""
    names = list(summaries)
    keys = list(next(iter(summaries.values())))
    lines = ["| | " + " | ".join(names) + " |", "|---" * (len(names) + 1) + "|"]
    for key in keys:
        cells = []
        for name in names:
            value = summaries[name][key]
            share = key in ("success", "first-probe success", "timed out") or "share" in key
            if np.isnan(value):  # nothing to count: no such probe, or no timed-out episode
                cells.append("-")
            else:
                cells.append(f"{value:.1%}" if share else f"{value:,.1f}".removesuffix(".0"))
        lines.append(f"| {key} | " + " | ".join(cells) + " |")
    return "\n".join(lines)
