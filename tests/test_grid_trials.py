"""A grid trial reuses a finished run only if it was trained with the recipe the trial has
now: a recipe edited since (`make results` after a change of `agents/hyperparams/`) trains
the run again instead of publishing the old model under the new recipe."""

from __future__ import annotations

from pathlib import Path

import pytest
import yaml

pytest.importorskip("stable_baselines3")

import tactile_search
from agents.grid import trials as trials_module
from agents.grid.trials import TrainingTrial, changed_recipe_keys, train_trial
from agents.run_dir import CHECKPOINT_DIR, CHECKPOINT_PREFIX
from agents.sb3.recipes import load_hyperparams

TIMESTEPS = 1024


def finished_run(runs: Path, **recipe_changes) -> TrainingTrial:
    """A trial of PPO with no map, and a finished run of it in ``runs`` (a config as
    ``train`` records it, with ``recipe_changes`` applied, and a model file)."""
    trial = TrainingTrial("ppo", "none", 0, str(runs.resolve()), TIMESTEPS, 1, from_scratch=True)
    recipe = load_hyperparams("ppo", "none")
    recipe["n_timesteps"] = TIMESTEPS
    del recipe["imitation"]  # PPO from scratch records no imitation section
    recipe.update(recipe_changes)
    config = {
        "algo": "ppo",
        "map": "none",
        "seed": 0,
        "hyperparams": recipe,
        "versions": {"tactile_search": tactile_search.__version__},
    }
    trial.run_dir.mkdir(parents=True)
    (trial.run_dir / "config.yml").write_text(yaml.safe_dump(config))
    (trial.run_dir / "model.zip").write_bytes(b"the old model")
    return trial


def stopped_half_way(trial: TrainingTrial) -> Path:
    """Turns ``trial``'s finished run into one stopped at a checkpoint; the checkpoint."""
    (trial.run_dir / "model.zip").unlink()
    checkpoint = trial.run_dir / CHECKPOINT_DIR / f"{CHECKPOINT_PREFIX}_512_steps.zip"
    checkpoint.parent.mkdir()
    checkpoint.write_bytes(b"half of the run")
    return checkpoint


@pytest.fixture
def trainings(monkeypatch) -> list[dict]:
    """The calls ``train_trial`` makes to train, recorded instead of run."""
    calls: list[dict] = []

    def record(settings, imitation_overrides=None):
        calls.append({**vars(settings), "imitation_overrides": imitation_overrides})
        return settings.run_dir

    monkeypatch.setattr(trials_module, "train_with_clone_stage", record)
    return calls


def test_a_finished_run_of_the_same_recipe_is_reused(tmp_path, trainings, capsys) -> None:
    trial = finished_run(tmp_path)
    assert changed_recipe_keys(trial) == []
    assert train_trial(trial) == trial.run_dir
    assert trainings == []
    assert (trial.run_dir / "model.zip").read_bytes() == b"the old model"
    assert "reusing" in capsys.readouterr().out


def test_a_finished_run_of_an_edited_recipe_is_trained_again(tmp_path, trainings, capsys) -> None:
    recipe = load_hyperparams("ppo", "none")
    trial = finished_run(tmp_path, n_epochs=recipe["n_epochs"] + 6, old_key=1)
    assert changed_recipe_keys(trial) == ["n_epochs", "old_key"]
    train_trial(trial)
    assert len(trainings) == 1 and trainings[0]["resume"] is False
    assert not (trial.run_dir / "model.zip").exists()  # the old model is not left beside
    assert "its recipe differs from the trial's in n_epochs, old_key" in capsys.readouterr().out


def test_an_unfinished_run_of_an_edited_recipe_starts_afresh(tmp_path, trainings) -> None:
    recipe = load_hyperparams("ppo", "none")
    trial = finished_run(tmp_path, learning_rate=recipe["learning_rate"] * 2)
    checkpoint = stopped_half_way(trial)
    train_trial(trial)
    assert trainings[0]["resume"] is False
    assert not checkpoint.exists()


def test_an_unfinished_run_of_the_same_recipe_resumes(tmp_path, trainings) -> None:
    trial = finished_run(tmp_path)
    checkpoint = stopped_half_way(trial)
    train_trial(trial)
    assert trainings[0]["resume"] is True
    assert checkpoint.exists()


def test_a_run_whose_config_cannot_be_read_is_trained_again(tmp_path, trainings) -> None:
    trial = finished_run(tmp_path)
    (trial.run_dir / "config.yml").write_text("- not a mapping\n")
    assert changed_recipe_keys(trial) == ["config.yml"]
    train_trial(trial)
    assert len(trainings) == 1
