"""The time-to-agent profile (``benchmarks.time_to_agent``) runs a recipe's whole path, the
clone stage and PPO, on a registered id's recipe, and writes each stage's seconds."""

from __future__ import annotations

import json
from pathlib import Path

import yaml

from benchmarks.time_to_agent import main


def test_the_profile_runs_the_identify_recipe_stage_by_stage(tmp_path: Path, capsys) -> None:
    main(
        [
            *("--env-id", "tactile_search/IdentifyByTouch-v0", "--scale", "0.001"),
            *("--torch-threads", "1", "--env-threads", "1", "--out", str(tmp_path)),
            *("--imitation", "dagger_rounds=1", "dagger_epochs=1", "cloning={epochs: 1}"),
        ]
    )
    run = tmp_path / "ppo_gpis_seed0"
    stages = json.loads((run / "time_to_agent.json").read_text())["stages"]
    assert any("teacher" in name for name in stages) and any("PPO" in n for n in stages)
    assert all(seconds >= 0 for seconds in stages.values())
    config = yaml.safe_load((run / "config.yml").read_text())
    assert config["env_id"] == "tactile_search/IdentifyByTouch-v0"
    assert config["hyperparams"]["env_kwargs"]["task"] == "identify"
    assert config["timesteps_done"] >= 512
    assert "IdentifyByTouch-v0" in capsys.readouterr().out
