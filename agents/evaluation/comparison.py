"""Results pooled over training seeds, and differences between agents with intervals.

An evaluation's ``episodes.csv`` holds one row per agent and held-out layout; a learned agent
trained with several seeds appears once per seed (``ppo (gpis map, seed 1)``). Here:

- ``pool``: per agent, the success pooled over its training seeds and layouts, a 95 %
  bootstrap interval of it, each seed's success and the spread across seeds (max - min);
  tips, time-outs and jar displacement per episode (an episode ends when the target is
  touched or claimed, when a jar tips, at a wrong claim, or at the time limit: a failure
  with neither a tip nor a wrong claim is a time-out),
  and the wrist motions an action costs (the time limit counts motions; a probe is many);
- ``difference``: agent A's pooled success minus agent B's, with a 95 % bootstrap interval
  over layouts and training seeds: each resample draws the layouts with replacement (the
  same layouts for both agents: every agent meets the same ones, so the comparison is
  paired) and, independently for each agent, its training seeds with replacement;
- ``comparison_markdown``: both as markdown tables, and whether A beats B with
  non-overlapping (Wilson) intervals in every training seed, seed i against seed i; with a
  ``task``, also the task's own measures (``TASK_MEASURES``: the identify task's wrong
  claims, the map task's scores), pooled and differenced the same way;
- ``interval_sources_markdown``: each difference's interval beside the one over the layouts
  alone, these training seeds held: how much of its width more test layouts would remove;
- ``overlap``: where A and B succeed and fail, layout by layout: over every (training seed
  of A, training seed of B, layout), how often both succeed, A alone, B alone, neither; and
  the layouts that defeat every training seed of A (``overlap_markdown``).

``python -m agents.comparison docs/results/episodes.csv`` prints the tables.
"""

from __future__ import annotations

import dataclasses
import re
from collections.abc import Sequence
from typing import Any

import numpy as np

from agents.evaluation.episodes_csv import ADDED_COLUMNS
from agents.sb3.learned import learned_agent_name
from tactile_search.benchmark.map_curve import parse_map_curve
from tactile_search.benchmark.statistics import mean_interval, wilson_interval
from tactile_search.envs.config import markdown_table

# The form of agents.evaluation.agent_specs.seeded_name, with the suffixes of a blanked map
# (agents.evaluation.map_ablation) and of changed env settings (agents.evaluation.evaluation)
# if any:
# "ppo (gpis map, seed 1)" -> "ppo (gpis map)", seed 1;
# "ppo (gpis map, seed 1) [std=0]" -> "ppo (gpis map) [std=0]", seed 1.
_WITH_SEED = re.compile(
    r"^(?P<algo>.+) \((?P<map>[^,()]+) map, seed (?P<seed>\d+)\)(?P<suffix>( \[[^\]]+\])*)$"
)


BOOTSTRAP_SAMPLES = 10_000


@dataclasses.dataclass(frozen=True)
class Measure:
    """A per-episode figure that decides a task: ``field``, the ``AgentResults`` matrix it
    is read from; ``percent``: a rate (shown in % and points) rather than millimetres;
    ``better``: ``"higher"`` or ``"lower"``."""

    field: str
    label: str
    percent: bool
    better: str


MEASURES = {
    "success": Measure("success", "success", percent=True, better="higher"),
    "wrong_claims": Measure("wrong_claims", "wrong claims", percent=True, better="lower"),
    "map_score_area": Measure(
        "map_score_area", "map distance over the motions (mm)", percent=False, better="lower"
    ),
    "map_score_mm": Measure(
        "map_score_mm", "map distance at the end (mm)", percent=False, better="lower"
    ),
}


# What decides each task (the ``task`` setting; docs/DESIGN.md §4.4): the search task's
# success; the identify task's success and wrong claims (an episode ended by a claim naming
# another jar or none); the map task's score (no episode of it succeeds).
TASK_MEASURES: dict[str, tuple[str, ...]] = {
    "search": ("success",),
    "identify": ("success", "wrong_claims"),
    "map": ("map_score_area", "map_score_mm"),
}


# The bootstrap's own generator, fixed so that a table is the same every time it is made.
BOOTSTRAP_SEED = 0


def agent_and_seed(name: str) -> tuple[str, int | None]:
    """An evaluated agent's name split into the agent and its training seed (None for a
    scripted agent or a single run)."""
    match = _WITH_SEED.match(name)
    if match is None:
        return name, None
    agent = learned_agent_name(match["algo"], match["map"]) + match["suffix"]
    return agent, int(match["seed"])


@dataclasses.dataclass(frozen=True)
class AgentResults:
    """One agent's successes as a (training seeds x layouts) matrix, and its other figures."""

    agent: str
    training_seeds: tuple[int | None, ...]
    layouts: tuple[int, ...]
    success: np.ndarray  # (seeds, layouts) of 0/1
    tips: np.ndarray  # (seeds, layouts) of 0/1 (an episode with a tip)
    timeouts: np.ndarray  # (seeds, layouts) of 0/1 (neither success nor tip: the time limit)
    displacement_mm: np.ndarray  # (seeds, layouts)
    motions: np.ndarray  # (seeds, layouts): wrist motions (the env's steps)
    actions: np.ndarray  # (seeds, layouts): the agent's actions (a probe, or a motion)
    wrong_claims: np.ndarray  # (seeds, layouts) of 0/1: a claim naming another jar or none
    map_score_area: np.ndarray  # (seeds, layouts): the map task's mean outline distance, mm
    map_score_mm: np.ndarray  # (seeds, layouts): ... at the episode's end, mm
    # (seeds, layouts, MAP_CURVE_POINTS): the distance against the motions (the map task's
    # rows' map_score_curve), None when the rows hold none.
    map_curves: np.ndarray | None = None

    def restricted(self, layouts: Sequence[int]) -> AgentResults:
        index = [self.layouts.index(seed) for seed in layouts]
        matrices = {
            field.name: getattr(self, field.name)[:, index]
            for field in dataclasses.fields(self)
            if isinstance(getattr(self, field.name), np.ndarray)
        }
        return dataclasses.replace(self, layouts=tuple(layouts), **matrices)

    def measure(self, name: str) -> np.ndarray:
        """The (seeds x layouts) matrix of ``MEASURES[name]``."""
        if name not in MEASURES:
            raise ValueError(f"measure must be one of {sorted(MEASURES)}, got {name!r}")
        return np.asarray(getattr(self, MEASURES[name].field))


def added(row: dict[str, Any], column: str) -> Any:
    """``row``'s ``column``, one of the columns added with the tasks, or the value an older
    row has (``ADDED_COLUMNS``)."""
    return row.get(column, ADDED_COLUMNS[column])


def map_curves(
    by_seed: dict[int | None, dict[int, dict[str, Any]]],
    seeds: Sequence[int | None],
    layouts: Sequence[int],
) -> np.ndarray | None:
    """The (seeds, layouts, points) array of the rows' map score curves, or None unless every
    row holds one (the map task's)."""
    texts = [[added(by_seed[s][layout], "map_score_curve") for layout in layouts] for s in seeds]
    if not all(text for row in texts for text in row):
        return None
    return np.array([[parse_map_curve(text) for text in row] for row in texts])


def agent_results(rows: Sequence[dict[str, Any]]) -> dict[str, AgentResults]:
    """Every agent's results, on the layouts all of its training seeds met; agents in the
    order they first appear."""
    by_agent: dict[str, dict[int | None, dict[int, dict[str, Any]]]] = {}
    for row in rows:
        agent, seed = agent_and_seed(row["agent"])
        by_agent.setdefault(agent, {}).setdefault(seed, {})[int(row["seed"])] = row
    results = {}
    for agent, by_seed in by_agent.items():
        seeds = tuple(sorted(by_seed, key=lambda s: -1 if s is None else s))
        layouts = tuple(sorted(set.intersection(*(set(by_seed[s]) for s in seeds))))
        if not layouts:
            raise ValueError(f"{agent}: its training seeds share no evaluated layout")

        def matrix(
            get: Any, by_seed: dict = by_seed, seeds: tuple = seeds, layouts: tuple = layouts
        ) -> np.ndarray:
            return np.array([[get(by_seed[s][layout]) for layout in layouts] for s in seeds])

        results[agent] = AgentResults(
            agent=agent,
            training_seeds=seeds,
            layouts=layouts,
            success=matrix(lambda r: float(r["success"])),
            tips=matrix(lambda r: float(int(r["tips"]) > 0)),
            # A failure neither by a tip nor by a wrong claim (identify) ran out of time.
            timeouts=matrix(
                lambda r: float(
                    not r["success"] and int(r["tips"]) == 0 and not added(r, "wrong_claim")
                )
            ),
            displacement_mm=matrix(lambda r: 1000.0 * float(r["jar_displacement"])),
            motions=matrix(lambda r: float(r["steps"])),
            actions=matrix(lambda r: float(r["actions"])),
            # A search evaluation's rows may lack the tasks' columns (then ADDED_COLUMNS').
            wrong_claims=matrix(lambda r: float(bool(added(r, "wrong_claim")))),
            map_score_area=matrix(lambda r: float(added(r, "map_score_area"))),
            map_score_mm=matrix(lambda r: float(added(r, "map_score_mm"))),
            map_curves=map_curves(by_seed, seeds, layouts),
        )
    return results


def bootstrap_means(
    matrices: Sequence[np.ndarray],
    rng: np.random.Generator,
    samples: int,
    resample_seeds: bool = True,
) -> list[np.ndarray]:
    """For each (seeds x layouts) matrix, ``samples`` bootstrap means: the layouts drawn with
    replacement once per sample for all matrices (paired), each matrix's seeds drawn with
    replacement on their own (or, without ``resample_seeds``, every seed once: the
    interval of these trained seeds, the layouts' share of the uncertainty alone)."""
    layout_weights = resample_weights(rng, matrices[0].shape[1], samples)
    means = []
    for matrix in matrices:
        seeds = matrix.shape[0]
        seed_weights = (
            resample_weights(rng, seeds, samples)
            if resample_seeds
            else np.full((samples, seeds), 1 / seeds)
        )
        means.append(np.einsum("bs,sl,bl->b", seed_weights, matrix, layout_weights))
    return means


def resample_weights(rng: np.random.Generator, count: int, samples: int) -> np.ndarray:
    """``samples`` draws of ``count`` items with replacement, as each item's share of the
    draw: the (samples x count) weights a bootstrap mean takes."""
    return rng.multinomial(count, np.full(count, 1 / count), samples) / count


def pooled_interval(
    matrix: np.ndarray, samples: int = BOOTSTRAP_SAMPLES
) -> tuple[float, float, float]:
    """A (seeds x layouts) matrix's mean and its 95 % bootstrap interval (layouts and seeds
    resampled, ``bootstrap_means``; the same draws for every matrix of a shape)."""
    (means,) = bootstrap_means([matrix], np.random.default_rng(BOOTSTRAP_SEED), samples)
    return float(matrix.mean()), float(np.quantile(means, 0.025)), float(np.quantile(means, 0.975))


@dataclasses.dataclass(frozen=True)
class Pooled:
    """One agent's pooled figures."""

    agent: str
    training_seeds: tuple[int | None, ...]
    episodes: int
    success: float
    success_low: float
    success_high: float
    per_seed: tuple[tuple[int | None, float, float, float], ...]  # seed, rate, Wilson low, high
    spread: float  # max - min of the per-seed success rates
    tip_rate: float
    timeout_rate: float
    displacement_mm: float
    motions_per_action: float


def pool(results: AgentResults, samples: int = BOOTSTRAP_SAMPLES) -> Pooled:
    """``results`` pooled over training seeds and layouts (see the module docstring)."""
    success, success_low, success_high = pooled_interval(results.success, samples)
    n_layouts = len(results.layouts)
    per_seed = []
    for seed, row in zip(results.training_seeds, results.success, strict=True):
        successes = int(row.sum())
        per_seed.append((seed, successes / n_layouts, *wilson_interval(successes, n_layouts)))
    rates = [rate for _, rate, _, _ in per_seed]
    return Pooled(
        agent=results.agent,
        training_seeds=results.training_seeds,
        episodes=int(results.success.size),
        success=success,
        success_low=success_low,
        success_high=success_high,
        per_seed=tuple(per_seed),
        spread=max(rates) - min(rates),
        tip_rate=float(results.tips.mean()),
        timeout_rate=float(results.timeouts.mean()),
        displacement_mm=float(results.displacement_mm.mean()),
        motions_per_action=float(results.motions.sum() / max(results.actions.sum(), 1.0)),
    )


def difference(
    a: AgentResults,
    b: AgentResults,
    samples: int = BOOTSTRAP_SAMPLES,
    measure: str = "success",
    resample_seeds: bool = True,
) -> tuple[float, float, float]:
    """A's pooled ``measure`` (``MEASURES``) minus B's on the layouts both met, and its 95 %
    bootstrap interval (paired over layouts, over each agent's training seeds unless
    ``resample_seeds`` is False: then over the layouts alone, ``bootstrap_means``)."""
    layouts = sorted(set(a.layouts) & set(b.layouts))
    if not layouts:
        raise ValueError(f"{a.agent} and {b.agent} share no evaluated layout")
    a, b = a.restricted(layouts), b.restricted(layouts)
    rng = np.random.default_rng(BOOTSTRAP_SEED)
    mean_a, mean_b = bootstrap_means(
        [a.measure(measure), b.measure(measure)], rng, samples, resample_seeds
    )
    diffs = mean_a - mean_b
    return (
        float(a.measure(measure).mean() - b.measure(measure).mean()),
        float(np.quantile(diffs, 0.025)),
        float(np.quantile(diffs, 0.975)),
    )


def gap_change(
    a_dense: AgentResults,
    b_dense: AgentResults,
    a_default: AgentResults,
    b_default: AgentResults,
    samples: int = BOOTSTRAP_SAMPLES,
) -> tuple[float, float, float]:
    """How much A's success gap over B grows from the default tier to the dense one: (A - B on
    the dense tier) - (A - B on the default tier), with its 95 % bootstrap interval. Each
    tier's layouts are resampled on their own, the same draw for A and B (paired); each
    agent's training seeds once for both tiers (the same models play both)."""
    for agent, dense, default in ((a_dense, a_dense, a_default), (b_dense, b_dense, b_default)):
        if dense.training_seeds != default.training_seeds:
            raise ValueError(
                f"{agent.agent} played the tiers with other training seeds: "
                f"{dense.training_seeds} and {default.training_seeds}"
            )
    tiers = []
    for a, b in ((a_dense, b_dense), (a_default, b_default)):
        layouts = sorted(set(a.layouts) & set(b.layouts))
        if not layouts:
            raise ValueError(f"{a.agent} and {b.agent} share no evaluated layout")
        tiers.append((a.restricted(layouts).success, b.restricted(layouts).success))
    rng = np.random.default_rng(BOOTSTRAP_SEED)
    seed_a = resample_weights(rng, len(a_dense.training_seeds), samples)
    seed_b = resample_weights(rng, len(b_dense.training_seeds), samples)
    gaps, observed = [], []
    for a, b in tiers:
        layout = resample_weights(rng, a.shape[1], samples)
        mean_a = np.einsum("bs,sl,bl->b", seed_a, a, layout)
        mean_b = np.einsum("bs,sl,bl->b", seed_b, b, layout)
        gaps.append(mean_a - mean_b)
        observed.append(a.mean() - b.mean())
    change = gaps[0] - gaps[1]
    return (
        float(observed[0] - observed[1]),
        float(np.quantile(change, 0.025)),
        float(np.quantile(change, 0.975)),
    )


def pooled_measure(
    results: AgentResults, measure: str, samples: int = BOOTSTRAP_SAMPLES
) -> tuple[float, float, float]:
    """``results``' ``measure`` pooled over training seeds and layouts, with its 95 %
    bootstrap interval (as ``pool``'s success)."""
    return pooled_interval(results.measure(measure), samples)


def beats_in_every_seed(a: Pooled, b: Pooled) -> bool | None:
    """Whether A's Wilson interval lies above B's in every training seed (seed i against
    seed i); None when they were not trained with the same seeds."""
    seeds_a = {seed: (low, high) for seed, _, low, high in a.per_seed}
    seeds_b = {seed: (low, high) for seed, _, low, high in b.per_seed}
    if set(seeds_a) != set(seeds_b) or None in seeds_a:
        return None
    return all(seeds_a[s][0] > seeds_b[s][1] for s in seeds_a)


def _percent(value: float) -> str:
    return f"{100 * value:.1f}%"


def _seed_text(seed: int | None) -> str:
    return "-" if seed is None else str(seed)


def _measure_text(measure: Measure, value: float, difference: bool = False) -> str:
    if measure.percent:
        return f"{100 * value:+.1f} pts" if difference else _percent(value)
    return f"{value:+.1f}" if difference else f"{value:.1f}"


def _interval_text(measure: Measure, low: float, high: float, difference: bool = False) -> str:
    if measure.percent and difference:
        return f"[{100 * low:+.1f}, {100 * high:+.1f}]"
    if measure.percent:
        return f"[{_percent(low)}, {_percent(high)}]"
    return f"[{low:+.1f}, {high:+.1f}]" if difference else f"[{low:.1f}, {high:.1f}]"


def measure_markdown(
    results: dict[str, AgentResults], reference: str, name: str, samples: int = BOOTSTRAP_SAMPLES
) -> str:
    """The measure ``name`` (``MEASURES``) pooled per agent with its interval, and the
    differences of ``reference`` against every other agent, as markdown."""
    measure = MEASURES[name]
    lines = [
        f"| agent | {measure.label}, pooled ({measure.better} is better) | 95 % CI (bootstrap) |",
        "|---|---|---|",
    ]
    for agent, r in results.items():
        value, low, high = pooled_measure(r, name, samples)
        lines.append(
            f"| {agent} | {_measure_text(measure, value)} | {_interval_text(measure, low, high)} |"
        )
    lines += [
        "",
        f"| {reference} minus | {measure.label}, difference | 95 % CI (bootstrap over layouts "
        "and training seeds) |",
        "|---|---|---|",
    ]
    for agent, other in results.items():
        if agent != reference:
            diff, low, high = difference(results[reference], other, samples, name)
            lines.append(
                f"| {agent} | {_measure_text(measure, diff, True)} "
                f"| {_interval_text(measure, low, high, True)} |"
            )
    return "\n".join(lines) + "\n"


def comparison_markdown(
    rows: Sequence[dict[str, Any]],
    reference: str | None = None,
    samples: int = BOOTSTRAP_SAMPLES,
    task: str = "search",
) -> str:
    """The pooled table, the per-seed table of ``task``'s measures (``TASK_MEASURES``) and,
    where the task has a success, the differences of ``reference`` (default: the first agent)
    against every other agent, as markdown; then each of the task's measures other than
    success pooled and differenced (``measure_markdown``). The map task, which has no
    success, shows none."""
    results, reference = _checked_results(rows, reference, task)
    measures = TASK_MEASURES[task]
    has_success = "success" in measures
    pooled = {agent: pool(r, samples) for agent, r in results.items()}
    parts = [_pooled_markdown(pooled, has_success), _per_seed_markdown(results, measures)]
    if has_success:
        parts.append(_success_difference_markdown(results, pooled, reference, samples))
    parts += [
        measure_markdown(results, reference, name, samples)
        for name in measures
        if name != "success"
    ]
    return "\n".join(parts)


def _checked_results(
    rows: Sequence[dict[str, Any]], reference: str | None, task: str
) -> tuple[dict[str, AgentResults], str]:
    """``rows``' results by agent and the reference agent (default: the first), or
    ``ValueError`` naming an unknown ``task`` or ``reference``."""
    if task not in TASK_MEASURES:
        raise ValueError(f"task must be one of {sorted(TASK_MEASURES)}, got {task!r}")
    results = agent_results(rows)
    reference = reference or next(iter(results))
    if reference not in results:
        raise ValueError(f"reference must be one of {sorted(results)}, got {reference!r}")
    return results, reference


def _pooled_markdown(pooled: dict[str, Pooled], has_success: bool) -> str:
    """Each agent pooled over its training seeds: success (where the task has one), how its
    episodes end otherwise, the jars it displaces and the wrist motions it spends."""
    success_columns = (
        ["success, pooled", "95 % CI (bootstrap)", "spread across seeds"] if has_success else []
    )
    ending_columns = ["episodes with a tip"] + (["episodes timed out"] if has_success else [])
    columns = [
        "agent",
        "training seeds",
        "episodes",
        *success_columns,
        *ending_columns,
        "jar displacement (mm per episode)",
        "wrist motions per action",
    ]
    rows = []
    for p in pooled.values():
        seeds = ", ".join(_seed_text(s) for s in p.training_seeds)
        success_cells = (
            [
                _percent(p.success),
                f"[{_percent(p.success_low)}, {_percent(p.success_high)}]",
                _percent(p.spread),
            ]
            if has_success
            else []
        )
        ending_cells = [_percent(p.tip_rate)] + ([_percent(p.timeout_rate)] if has_success else [])
        rows.append(
            [
                p.agent,
                seeds,
                str(p.episodes),
                *success_cells,
                *ending_cells,
                f"{p.displacement_mm:.1f}",
                f"{p.motions_per_action:.1f}",
            ]
        )
    return markdown_table(columns, rows) + "\n"


def _per_seed_markdown(results: dict[str, AgentResults], measures: Sequence[str]) -> str:
    """Each training seed's figure of every measure in ``measures``, with its 95 % interval
    over the layouts: Wilson's for a rate, the normal approximation's for millimetres."""
    header = ["agent", "training seed"]
    for name in measures:
        label = MEASURES[name].label
        kind = "Wilson" if MEASURES[name].percent else "over layouts"
        header += [label, f"95 % CI ({kind})"]
    rows = []
    for agent, r in results.items():
        for index, seed in enumerate(r.training_seeds):
            cells = [agent, _seed_text(seed)]
            for name in measures:
                values = r.measure(name)[index]
                measure = MEASURES[name]
                if measure.percent:
                    count = int(values.sum())
                    low, high = wilson_interval(count, len(values))
                    cells += [_percent(count / len(values)), _interval_text(measure, low, high)]
                else:
                    low, high = mean_interval(values.tolist())
                    cells += [f"{values.mean():.1f}", _interval_text(measure, low, high)]
            rows.append(cells)
    return markdown_table(header, rows) + "\n"


def _success_difference_markdown(
    results: dict[str, AgentResults],
    pooled: dict[str, Pooled],
    reference: str,
    samples: int,
) -> str:
    lines = [
        f"| {reference} minus | success difference | 95 % CI (bootstrap over layouts and "
        "training seeds) | above it in every training seed (Wilson intervals apart) |",
        "|---|---|---|---|",
    ]
    for agent, other in results.items():
        if agent == reference:
            continue
        diff, low, high = difference(results[reference], other, samples)
        every = beats_in_every_seed(pooled[reference], pooled[agent])
        every_text = "-" if every is None else ("yes" if every else "no")
        lines.append(
            f"| {agent} | {100 * diff:+.1f} pts | [{100 * low:+.1f}, {100 * high:+.1f}] "
            f"| {every_text} |"
        )
    return "\n".join(lines) + "\n"


def interval_sources_markdown(
    rows: Sequence[dict[str, Any]],
    reference: str,
    task: str = "search",
    samples: int = BOOTSTRAP_SAMPLES,
) -> str:
    """Where a difference's interval comes from: for ``reference`` against every other
    learned agent (one trained with several seeds), each of ``task``'s measures differenced
    with its 95 % interval over layouts and training seeds (``difference``), beside the
    interval over the layouts alone with these training seeds held (what more test layouts
    would narrow; the rest is the seeds', which only more training seeds narrow)."""
    results, reference = _checked_results(rows, reference, task)
    lines = [
        f"| {reference} minus | measure | difference | 95 % CI, layouts and training seeds "
        "| 95 % CI, layouts alone (these training seeds) |",
        "|---|---|---|---|---|",
    ]
    for agent, other in results.items():
        if agent == reference or len(other.training_seeds) < 2:
            continue
        for name in TASK_MEASURES[task]:
            measure = MEASURES[name]
            diff, low, high = difference(results[reference], other, samples, name)
            _, fixed_low, fixed_high = difference(
                results[reference], other, samples, name, resample_seeds=False
            )
            lines.append(
                f"| {agent} | {measure.label} | {_measure_text(measure, diff, True)} "
                f"| {_interval_text(measure, low, high, True)} "
                f"| {_interval_text(measure, fixed_low, fixed_high, True)} |"
            )
    return "\n".join(lines) + "\n"


@dataclasses.dataclass(frozen=True)
class Overlap:
    """Agent A's and agent B's outcomes on the same layouts (``overlap``)."""

    a: str
    b: str
    pairs: int  # (seed of A, seed of B, layout) triples counted
    both: int
    a_alone: int
    b_alone: int
    neither: int
    layouts: int  # layouts both met
    a_always_fails: int  # layouts that defeat every training seed of A
    of_those_b_fails: int  # ... and every training seed of B too


def overlap(results: dict[str, AgentResults], a: str, b: str) -> Overlap:
    """Where ``a`` and ``b`` succeed and fail on the layouts both met."""
    for name in (a, b):
        if name not in results:
            raise ValueError(f"agents are {sorted(results)}, got {name!r}")
    layouts = sorted(set(results[a].layouts) & set(results[b].layouts))
    if not layouts:
        raise ValueError(f"{a!r} and {b!r} met no layout in common")
    sa = results[a].restricted(layouts).success.astype(bool)  # (seeds of a, layouts)
    sb = results[b].restricted(layouts).success.astype(bool)
    x, y = sa[:, None, :], sb[None, :, :]  # every seed of a against every seed of b
    a_fails_always = ~sa.any(axis=0)
    return Overlap(
        a=a,
        b=b,
        pairs=int(x.shape[0] * y.shape[1] * len(layouts)),
        both=int((x & y).sum()),
        a_alone=int((x & ~y).sum()),
        b_alone=int((~x & y).sum()),
        neither=int((~x & ~y).sum()),
        layouts=len(layouts),
        a_always_fails=int(a_fails_always.sum()),
        of_those_b_fails=int((a_fails_always & ~sb.any(axis=0)).sum()),
    )


def overlap_markdown(rows: Sequence[dict[str, Any]], a: str, b: str) -> str:
    """``overlap`` of ``a`` and ``b`` as a markdown table and a sentence."""
    o = overlap(agent_results(rows), a, b)
    return (
        f"| (seed, seed, layout) triples | both succeed | {o.a} alone | {o.b} alone | neither |\n"
        "|---|---|---|---|---|\n"
        f"| {o.pairs} | {o.both} | {o.a_alone} | {o.b_alone} | {o.neither} |\n\n"
        f"{o.a_always_fails} of the {o.layouts} layouts defeat every training seed of {o.a}; "
        f"{o.of_those_b_fails} of them defeat {o.b} too.\n"
    )
