"""The claim-decision trace (``agents.evaluation.claim_decisions``): it counts every claim an
agent makes, on the jar the core says the finger touched, and its table adds up."""

from __future__ import annotations

import gymnasium as gym
import pytest

from agents.claim_decisions import main
from agents.evaluation.agent_specs import make_agent
from agents.evaluation.claim_decisions import (
    Decision,
    decision_table,
    decisions_markdown,
    trace_decisions,
)
from agents.rollout import run_episodes
from tactile_search import CupboardSearchEnv
from tactile_search.seed_ranges import held_out_seeds

IDENTIFY = "tactile_search/IdentifyByTouch-v0"
SEEDS = list(held_out_seeds("validation", 6))


def test_render_state_names_the_jar_a_claim_would_name() -> None:
    oracle, env_kwargs = make_agent("oracle")
    env = CupboardSearchEnv(**{**env_kwargs, **gym.spec(IDENTIFY).kwargs})
    observation, info = env.reset(seed=SEEDS[0])
    assert env.render_state()["touched_jar"] is None  # the hand starts clear of every jar
    oracle.reset(env, observation, info)
    touched_before_claim = None
    for _ in range(env.config.max_steps):
        touched_before_claim = env.render_state()["touched_jar"]
        observation, _, terminated, truncated, info = env.step(oracle.act(observation))
        if terminated or truncated:
            break
    assert info["success"]
    assert touched_before_claim == info["claimed_jar"]
    assert env.render_state()["jars"][info["claimed_jar"]]["is_target"]


def test_the_oracle_claims_only_on_the_target() -> None:
    name, decisions = trace_decisions("oracle", SEEDS, IDENTIFY)
    claims = [d for d in decisions if d.claimed]
    assert name == "oracle"
    assert len(claims) == len(SEEDS)  # one claim per episode, each ending it
    assert all(d.touched == "target" and d.touch >= 1 for d in claims)


def test_every_claim_of_an_episode_is_one_claimed_decision() -> None:
    _, decisions = trace_decisions("random_identify", SEEDS, IDENTIFY)
    agent, env_kwargs = make_agent("random_identify")
    rows = run_episodes(agent, SEEDS, **{**env_kwargs, **gym.spec(IDENTIFY).kwargs})
    claimed_episodes = sum(row["success"] or row["wrong_claim"] for row in rows)
    assert sum(d.claimed for d in decisions) == claimed_episodes
    # A claim touching no jar is a wrong one: the trace counts it under "no jar".
    wrong_on_nothing = sum(d.claimed and d.touched == "no jar" for d in decisions)
    assert wrong_on_nothing <= sum(row["wrong_claim"] for row in rows)


def test_the_table_counts_claims_and_decisions_per_jar_and_touch() -> None:
    decisions = [
        Decision("target", 1, False),
        Decision("target", 2, True),
        Decision("other jar", 1, True),
        Decision("other jar", 3, False),
        Decision("hidden decoy", 1, True),
        Decision("no jar", 0, False),
    ]
    table = decision_table(decisions)
    assert table["target", 1] == (0, 1) and table["target", 2] == (1, 1)
    assert table["other jar", 1] == (1, 1) and table["other jar", 3] == (0, 1)
    assert table["no jar", 0] == (0, 1) and table["target", 3] == (0, 0)
    assert table["hidden decoy", 1] == (1, 1) and table["hidden decoy", 2] == (0, 0)
    assert sum(total for _, total in table.values()) == len(decisions)
    text = decisions_markdown({"a": decisions})
    assert "| target, 2nd touch | 1/1: 100% [" in text
    assert "| claims naming the target, on a first touch | 0/2: 0% [" in text
    assert "| claims naming the target, on a later touch | 1/1: 100% [" in text
    assert "| target, 3rd touch or later | - |" in text


def test_a_task_without_claims_is_refused() -> None:
    with pytest.raises(ValueError, match="identify id, got 'tactile_search/MapByTouch-v0'"):
        trace_decisions("oracle", SEEDS, "tactile_search/MapByTouch-v0")


def test_the_command_writes_the_table_and_each_decision(tmp_path, capsys) -> None:
    main(["oracle", "--episodes", "2", "--out", str(tmp_path)])
    printed = capsys.readouterr().out
    table = (tmp_path / "claim_decisions.md").read_text()
    assert table.strip() in printed
    lines = (tmp_path / "claim_decisions.csv").read_text().splitlines()
    assert lines[0] == "agent,spec,touched,touch,claimed"
    assert sum(line.endswith(",True") for line in lines[1:]) == 2
