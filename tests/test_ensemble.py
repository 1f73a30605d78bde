"""Training seeds acting as one (agents.evaluation.ensemble): the spec, what may be averaged,
and an ensemble of one model's copies acting as that model."""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest

from agents.evaluation.ensemble import EnsembleAgent, ensemble_members
from agents.rollout import run_episodes

SEEDS = [1_000_000, 1_000_001]


def test_the_spec_names_two_runs_or_more():
    assert ensemble_members("runs/ppo_gpis_seed0") is None
    assert ensemble_members("ensemble:a,b") == [Path("a"), Path("b")]
    with pytest.raises(ValueError, match="two runs or more"):
        ensemble_members("ensemble:a")


@pytest.fixture(scope="module")
def gpis_run(tmp_path_factory: pytest.TempPathFactory) -> Path:
    from tests.recipes import train_with_recipe

    return train_with_recipe(tmp_path_factory.mktemp("ensemble"), "gpis")


def test_copies_of_one_model_act_as_that_model(gpis_run: Path, tmp_path: Path):
    from agents.evaluation.agent_specs import make_agent
    from agents.sb3.learned import LearnedAgent

    copy = tmp_path / "copy"
    shutil.copytree(gpis_run, copy)
    ensemble, env_kwargs = make_agent(f"ensemble:{gpis_run},{copy}")
    assert isinstance(ensemble, EnsembleAgent)
    assert ensemble.name == "ppo (gpis map, ensemble of 2)"
    alone = LearnedAgent(gpis_run, deterministic=True)
    assert run_episodes(ensemble, SEEDS, **env_kwargs) == run_episodes(alone, SEEDS, **env_kwargs)


def test_an_ensemble_refuses_other_agents_or_a_factorised_head(gpis_run: Path, tmp_path: Path):
    from agents.evaluation.agent_specs import make_agent
    from tests.recipes import train_with_recipe

    none_run = train_with_recipe(tmp_path, "none")  # SB3's MultiInputPolicy: one head per index
    with pytest.raises(ValueError, match="must be one agent"):
        make_agent(f"ensemble:{gpis_run},{none_run}")
    with pytest.raises(ValueError, match="one categorical over every probe"):
        make_agent(f"ensemble:{none_run},{none_run}")
    with pytest.raises(ValueError, match="acts by the mode"):
        make_agent(f"ensemble:{gpis_run},{gpis_run}", actions="sample")
