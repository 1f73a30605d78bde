"""When an identify agent claims: its decisions on each jar, by how often it has felt it.

In the identify task (docs/DESIGN.md §4.4) every action carries a claim, which names the jar
the finger touches. After every step the finger either touches a jar or none; the agent's
next action then claims, or goes on probing. This traces those decisions on the validation
layouts and counts them by what the finger touches (the target; the hidden decoy, the jar
hidden from the camera as the target is; another jar; in the registered identify ids every
jar but the target has the other shape; or none) and by how many of
the episode's steps so far ended touching that jar (its first touch, its second, three or
more). A claim's share on the target against its share on the hidden decoy, at the first
touch and after more, says whether an agent tells the target by its shape (from one touch
or from several); against its share on the other jars, whether it tells it by where the
camera could not see.

The jar touched is the core's ground truth (``render_state()["touched_jar"]``, the jar a
claim would name: ``Episode::touched_jar``), read by this trace after each step, never by
the agent. Only the validation layouts: this is for understanding and choosing, which the
test layouts are not for (``tactile_search.seed_ranges``)."""

from __future__ import annotations

from collections import Counter
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

from agents.evaluation.agent_specs import make_agent
from agents.evaluation.evaluation import env_id_settings, task_of
from agents.rollout import run_episodes
from tactile_search.benchmark.statistics import wilson_interval

#: What the finger touches at a decision: the target, the layout's hidden decoy (a jar of
#: the other shape hidden from the camera as the target is), another jar, or none.
TOUCHED = ("target", "hidden decoy", "other jar", "no jar")
#: A decision's touch count, capped: the jar's first touch, its second, three or more.
TOUCH_COUNTS = (1, 2, 3)


@dataclass(frozen=True)
class Decision:
    """One decision: what the finger touched after a step, the touch's count on that jar
    (0 when it touches none), and whether the next action claimed."""

    touched: str
    touch: int
    claimed: bool


def trace_decisions(
    spec: str,
    seeds: Sequence[int],
    env_id: str,
    actions: str = "mode",
    blanked: Sequence[str] = (),
) -> tuple[str, list[Decision]]:
    """The agent ``spec`` (a run directory or a scripted name, ``make_agent``) on ``seeds``
    of the registered ``env_id``, a claiming task's: its name without its training seed, and
    every decision it made."""
    if task_of(env_id) != "identify":
        raise ValueError(f"claim decisions need an identify id, got {env_id!r}")
    agent, env_kwargs = make_agent(spec, actions, blanked)
    env_kwargs = {**env_kwargs, **env_id_settings(env_id)}
    decisions: list[Decision] = []
    touches: Counter[int] = Counter()
    pending: tuple[str, int] | None = None  # the decision the next step answers

    def on_step(env: Any, step: int, done: bool) -> None:
        nonlocal pending
        state = env.render_state()
        if step == 0:
            touches.clear()
        elif pending is not None:
            decisions.append(Decision(*pending, claimed=state["claim"] is not None))
        pending = None
        if done:
            return
        jar = state["touched_jar"]
        if jar is None:
            pending = ("no jar", 0)
        else:
            touches[jar] += 1
            pending = (jar_kind(state["jars"][jar]), min(touches[jar], TOUCH_COUNTS[-1]))

    run_episodes(agent, list(seeds), on_step=on_step, **env_kwargs)
    return agent.name, decisions


def jar_kind(jar: Mapping[str, Any]) -> str:
    """A jar of ``render_state()["jars"]`` as ``TOUCHED`` names it."""
    if jar["is_target"]:
        return "target"
    return "hidden decoy" if jar["is_decoy"] else "other jar"


def decision_table(decisions: Sequence[Decision]) -> dict[tuple[str, int], tuple[int, int]]:
    """(touched, touch) -> (claims, decisions), every row of ``TOUCHED`` by ``TOUCH_COUNTS``
    (``no jar`` at touch 0) present."""
    keys = [(t, n) for t in TOUCHED[:-1] for n in TOUCH_COUNTS] + [("no jar", 0)]
    table = {key: (0, 0) for key in keys}
    for d in decisions:
        claims, total = table[d.touched, d.touch]
        table[d.touched, d.touch] = (claims + d.claimed, total + 1)
    return table


def row_label(touched: str, touch: int) -> str:
    if touched == "no jar":
        return "touching no jar"
    ordinal = {1: "1st touch", 2: "2nd touch", 3: "3rd touch or later"}[touch]
    return f"{touched}, {ordinal}"


def claim_cell(claims: int, total: int) -> str:
    """``claims/total rate [95 % Wilson]``; ``-`` with no decision to count."""
    if total == 0:
        return "-"
    low, high = wilson_interval(claims, total)
    return f"{claims}/{total}: {claims / total:.0%} [{low:.0%}, {high:.0%}]"


def decisions_markdown(by_agent: Mapping[str, Sequence[Decision]]) -> str:
    """One column per agent: each row's claims out of its decisions, the claim rate with its
    95 % Wilson interval; then the share of each agent's claims that named the target, for
    claims on a jar's first touch and on a later one."""
    names = list(by_agent)
    tables = {name: decision_table(by_agent[name]) for name in names}
    lines = [
        "| the finger touches | " + " | ".join(names) + " |",
        "|---" * (len(names) + 1) + "|",
    ]
    for key in next(iter(tables.values())):
        cells = [claim_cell(*tables[name][key]) for name in names]
        lines.append(f"| {row_label(*key)} | " + " | ".join(cells) + " |")
    for label, touches in (("a first touch", (1,)), ("a later touch", (2, 3))):
        cells = []
        for name in names:
            claims = [sum(tables[name][t, n][0] for n in touches) for t in TOUCHED[:-1]]
            cells.append(claim_cell(claims[0], sum(claims)))
        lines.append(f"| claims naming the target, on {label} | " + " | ".join(cells) + " |")
    return "\n".join(lines)
