"""The benchmark's command line evaluates a published model as it was trained (its run's
config.yml: algorithm, env settings, the policy's mode or sampled), says what it ran, and
reports every bad input as one line, never a traceback."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

pytest.importorskip("stable_baselines3")
pytest.importorskip("sb3_contrib")

from tactile_search.benchmark.__main__ import main

ROOT = Path(__file__).resolve().parents[1]
MODELS = ROOT / "docs" / "results" / "models"
#: The published agents' success on the test layouts (docs/RESULTS.md).
PUBLISHED_GPIS_SUCCESS = 0.965


def run_cli(tmp_path: Path, *args: str) -> subprocess.CompletedProcess:
    """The command as a user runs it from another folder (the repository on the path for
    the published models' policy classes, which live in its ``agents`` package; its
    ``python`` folder first, so the package is this checkout's wherever it is installed)."""
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(ROOT / "python"), str(ROOT)])}
    return subprocess.run(
        [sys.executable, "-m", "tactile_search.benchmark", "--no-progress", *args],
        cwd=tmp_path,
        env=env,
        capture_output=True,
        text=True,
        timeout=600,
    )


def test_a_published_model_runs_in_the_mode_and_map_it_was_trained_in(capsys) -> None:
    result = main(["--policy", str(MODELS / "ppo_gpis_seed0" / "model.zip"), "--episodes", "4",
                   "--no-progress"])  # fmt: skip
    assert result.env_kwargs["action_mode"] == "probe"
    assert result.env_kwargs["map"] == "gpis"
    assert not any(key.startswith("reward_") for key in result.env_kwargs)
    summary = result.summary
    assert summary.success_low <= PUBLISHED_GPIS_SUCCESS <= summary.success_high
    described = capsys.readouterr().out.splitlines()[0]
    assert described.startswith("tactile_search/CupboardSearch-v0, map gpis, action_mode probe")
    assert "actions: the policy's mode" in described


def test_a_recurrent_model_loads_as_recurrent_from_its_config(capsys) -> None:
    result = main(["--policy", str(MODELS / "recurrent_ppo_none_seed0" / "model.zip"),
                   "--episodes", "2", "--no-progress"])  # fmt: skip
    assert result.env_kwargs["map"] == "none"
    assert result.summary.agent.startswith("recurrent_ppo")


def test_an_overridden_setting_is_named_in_what_ran(capsys) -> None:
    main(["--policy", str(MODELS / "ppo_gpis_seed0" / "model.zip"), "--episodes", "1",
          "--env", "max_steps=60", "--no-progress"])  # fmt: skip
    assert "overridden: max_steps=60" in capsys.readouterr().out


@pytest.mark.parametrize(
    ("args", "words"),
    [
        (["--algo", "recurrent_ppo"], "was trained with ppo (its config.yml), got --algo"),
        (["--env", "map=none"], "the model cannot run under map='none'"),
        (["--env", "action_mode=wrist"], "it was trained on actions MultiDiscrete"),
    ],
)
def test_a_setting_or_algorithm_the_model_cannot_run_under_is_one_line(
    tmp_path: Path, args: list[str], words: str
) -> None:
    done = run_cli(tmp_path, "--policy", str(MODELS / "ppo_gpis_seed0" / "model.zip"), *args)
    assert done.returncode == 2
    assert "Traceback" not in done.stderr
    assert len(done.stderr.strip().splitlines()) == 1, done.stderr
    assert words in done.stderr


def test_a_file_that_is_no_model_is_one_line(tmp_path: Path) -> None:
    bad = tmp_path / "model.zip"
    bad.write_text("not a zip")
    done = run_cli(tmp_path, "--policy", str(bad))
    assert done.returncode == 2
    assert "Traceback" not in done.stderr
    assert f"{bad} does not load as a ppo model" in done.stderr
