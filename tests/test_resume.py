"""Long runs survive faults: a training run killed with SIGKILL or stopped with Ctrl-C
resumes to the same total with its logs intact, an interrupted evaluation resumes without
redoing episodes, and a broken model directory gets an error naming the file.

The training runs are tiny (PPO without a map, 2 envs x the recipe's n_steps per rollout, a
checkpoint at every rollout) and run as real CLI subprocesses; waits poll with generous limits, so a
loaded machine makes the tests slower, not flaky."""

from __future__ import annotations

import csv
import os
import shlex
import shutil
import signal
import subprocess
import sys
import time
import zipfile
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
import pytest
import yaml
from PIL import Image

pytest.importorskip("stable_baselines3")

from agents.evaluation import evaluation as evaluate_module
from agents.evaluation.episodes_csv import EPISODE_COLUMNS, read_episodes_csv
from agents.evaluation.evaluation import evaluate
from agents.evaluation.gifs import gif_drawn_by, gif_provenance
from agents.run_dir import checkpoints
from agents.sb3.learned import LearnedAgent
from agents.sb3.recipes import load_hyperparams
from agents.sb3.training import TrainSettings, train
from agents.train import main
from tactile_search.seed_ranges import VALIDATION

REPO = Path(__file__).resolve().parents[1]
ROLLOUT = 2 * load_hyperparams("ppo", "none")["n_steps"]  # --n-envs 2 x the recipe's n_steps
TOTAL = 16 * ROLLOUT
SEED = 5
LIMIT = 600.0  # seconds any wait may take before the test fails


def train_command(out: Path, *extra: str) -> list[str]:
    return [
        sys.executable,
        "-m",
        "agents.train",
        "--algo",
        "ppo",
        "--map",
        "none",
        "--seed",
        str(SEED),
        "--timesteps",
        str(TOTAL),
        "--n-envs",
        "2",
        "--checkpoint-every",
        str(ROLLOUT),
        "--out",
        str(out),
        "--no-progress",
        # PPO alone (the recipe's clone stage is not what resuming is about).
        "--from-scratch",
        # One torch thread: with torch loaded before agents.train set OMP_WAIT_POLICY (the
        # in-process resume below, under pytest), two threads spin against each other.
        "--torch-threads",
        "1",
        *extra,
    ]


def _default_sigint() -> None:
    # A child of a shell's background job inherits SIGINT ignored; Python then never raises
    # KeyboardInterrupt. Ctrl-C's default, so Python installs its handler.
    signal.signal(signal.SIGINT, signal.SIG_DFL)


class Child:
    """A CLI subprocess with its output in files (a pipe nobody reads could block it)."""

    def __init__(self, args: list[str], log: Path) -> None:
        self.stdout_path, self.stderr_path = log.with_suffix(".out"), log.with_suffix(".err")
        with self.stdout_path.open("w") as out, self.stderr_path.open("w") as err:
            self.process = subprocess.Popen(
                args, cwd=REPO, stdout=out, stderr=err, text=True, preexec_fn=_default_sigint
            )

    def output(self) -> str:
        return self.stdout_path.read_text() + self.stderr_path.read_text()

    def wait_until(self, condition: Callable[[], bool], what: str) -> None:
        deadline = time.monotonic() + LIMIT
        while not condition():
            code = self.process.poll()
            assert code is None, f"exited ({code}) before {what}:\n{self.output()[-3000:]}"
            assert time.monotonic() < deadline, f"no {what} after {LIMIT} s"
            time.sleep(0.02)

    def wait(self) -> int:
        return self.process.wait(timeout=LIMIT)


def progress_rows(run_dir: Path) -> list[dict[str, str]]:
    """The rows of a run's progress.csv, without a last line a kill cut short."""
    lines = (run_dir / "progress.csv").read_text().splitlines(keepends=True)
    return list(csv.DictReader(line for line in lines if line.endswith("\n")))


def total(row: dict[str, str]) -> int:
    return int(float(row["time/total_timesteps"]))


@pytest.fixture(scope="module")
def interrupted_run(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Any]:
    """A run SIGKILLed after its first checkpoint, resumed with --resume, stopped there
    with SIGINT, and resumed in-process with the command the interruption printed."""
    out = tmp_path_factory.mktemp("runs")
    run_dir = out / f"ppo_none_seed{SEED}"
    record: dict[str, Any] = {"run_dir": run_dir}

    first = Child(train_command(out), out / "first")
    first.wait_until(lambda: bool(checkpoints(run_dir)), "a checkpoint")
    first.process.kill()
    first.wait()
    killed_at = checkpoints(run_dir)[-1][0]
    record["killed_at"] = killed_at
    record["finished_before_the_kill"] = (run_dir / "model.zip").exists()
    record["rows_before_the_kill"] = [r for r in progress_rows(run_dir) if total(r) <= killed_at]

    second = Child(train_command(out, "--resume"), out / "second")
    second.wait_until(lambda: checkpoints(run_dir)[-1][0] > killed_at, "a new checkpoint")
    second.process.send_signal(signal.SIGINT)
    record["sigint_status"] = second.wait()
    record["sigint_output"] = second.output()
    record["finished_before_the_sigint"] = (run_dir / "model.zip").exists()
    record["checkpoints_after_the_sigint"] = [steps for steps, _ in checkpoints(run_dir)]
    lines = record["sigint_output"].splitlines()
    saved = next(line for line in lines if line.startswith("interrupted: saved "))
    record["sigint_checkpoint"] = Path(saved.split()[2])
    record["sigint_checkpoint_existed"] = record["sigint_checkpoint"].is_file()
    command = shlex.split(lines[lines.index(saved) + 1])
    record["resume_command"] = command
    assert command[:3] == [sys.executable, "-m", "agents.train"], command
    started = time.monotonic()
    main(command[3:])
    record["seconds_to_finish_in_process"] = time.monotonic() - started
    return record


def test_a_killed_run_resumes_to_the_same_total_with_its_logs_intact(interrupted_run):
    run_dir = interrupted_run["run_dir"]
    assert not interrupted_run["finished_before_the_kill"]
    config = yaml.safe_load((run_dir / "config.yml").read_text())
    assert config["timesteps_done"] == TOTAL
    resumes = config["resumes"]
    assert len(resumes) == 2 and resumes[0]["from_timesteps"] == interrupted_run["killed_at"]
    assert resumes[0]["env_seed"] != resumes[1]["env_seed"] != SEED
    rows = progress_rows(run_dir)
    # One row per rollout, each once, in order: the rows redone after a resume replaced.
    assert [total(r) for r in rows] == list(range(ROLLOUT, TOTAL + 1, ROLLOUT))
    before = interrupted_run["rows_before_the_kill"]
    assert before, "the first run logged rows before its checkpoint"
    for old, new in zip(before, rows, strict=False):
        assert {key: new[key] for key in old} == old
    assert len(list(run_dir.glob("events.out.tfevents.*"))) == 3
    agent = LearnedAgent(run_dir)
    assert agent.model.num_timesteps == TOTAL
    from tactile_search import CupboardSearchEnv

    env = CupboardSearchEnv(map="none")
    observation, info = env.reset(seed=1)
    agent.reset(env, observation, info)
    assert agent.act(observation).shape == (3,)
    env.close()


def test_ctrl_c_saves_a_checkpoint_and_prints_the_command_that_resumes(interrupted_run):
    assert not interrupted_run["finished_before_the_sigint"]
    assert interrupted_run["sigint_status"] == 130, interrupted_run["sigint_output"][-3000:]
    assert interrupted_run["sigint_checkpoint_existed"]
    steps = int(interrupted_run["sigint_checkpoint"].name.split("_")[2])
    assert steps % ROLLOUT == 0 and steps == max(interrupted_run["checkpoints_after_the_sigint"])
    command = interrupted_run["resume_command"]
    assert "--resume" in command and command[command.index("--seed") + 1] == str(SEED)
    assert command[command.index("--torch-threads") + 1] == "1"
    config = yaml.safe_load((interrupted_run["run_dir"] / "config.yml").read_text())
    assert config["resumes"][1]["from_timesteps"] == steps


def test_resuming_a_finished_run_does_nothing(interrupted_run, capsys):
    run_dir = interrupted_run["run_dir"]
    before = {p.name: p.stat().st_mtime_ns for p in run_dir.iterdir()}
    out = run_dir.parent
    assert train(TrainSettings("ppo", "none", out=out, seed=SEED, resume=True)) == run_dir
    assert "already finished" in capsys.readouterr().out
    assert {p.name: p.stat().st_mtime_ns for p in run_dir.iterdir()} == before


def test_resuming_needs_a_checkpoint_and_a_fresh_start_keeps_one(interrupted_run, tmp_path):
    with pytest.raises(ValueError, match="not a training run: no such directory"):
        train(TrainSettings("ppo", "none", out=tmp_path, seed=SEED, resume=True))
    run_dir = tmp_path / interrupted_run["run_dir"].name
    run_dir.mkdir()
    shutil.copy(interrupted_run["run_dir"] / "config.yml", run_dir)
    config = yaml.safe_load((run_dir / "config.yml").read_text())
    del config["timesteps_done"]
    (run_dir / "config.yml").write_text(yaml.safe_dump(config))
    with pytest.raises(ValueError, match="no checkpoint to resume from"):
        train(TrainSettings("ppo", "none", out=tmp_path, seed=SEED, resume=True))
    with pytest.raises(ValueError, match="a resumed run keeps the recipe"):
        train(
            TrainSettings("ppo", "none", out=tmp_path, seed=SEED, timesteps=TOTAL + 1, resume=True)
        )
    shutil.copytree(interrupted_run["run_dir"] / "checkpoints", run_dir / "checkpoints")
    with pytest.raises(ValueError, match="unfinished run with a checkpoint"):
        train(TrainSettings("ppo", "none", out=tmp_path, seed=SEED, from_scratch=True))
    with pytest.raises(ValueError, match="checkpoint_every must be at least 1"):
        train(TrainSettings("ppo", "none", out=tmp_path, seed=SEED, checkpoint_every=0))


# Evaluation


def _evaluate(out: Path, agents: list[str], episodes: int = 3) -> list:
    return evaluate(agents, out=out, episodes=episodes, gif_steps=4)


def test_an_interrupted_evaluation_resumes_without_redoing_episodes(tmp_path, monkeypatch):
    agents = ["random", "oracle"]
    whole = tmp_path / "whole"
    summaries = _evaluate(whole, agents)
    rows, bad = read_episodes_csv(whole / "episodes.csv")
    assert bad == 0 and len(rows) == 6
    assert all(type(row[key]) is kind for row in rows for key, kind in EPISODE_COLUMNS.items())

    # The evaluation killed after four episodes, the fifth row cut short.
    resumed = tmp_path / "resumed"
    shutil.copytree(whole, resumed)
    lines = (resumed / "episodes.csv").read_bytes().splitlines(keepends=True)
    (resumed / "episodes.csv").write_bytes(b"".join(lines[:5]) + lines[5][:25])
    (resumed / "results.md").unlink()
    (resumed / "gifs" / "oracle.gif").unlink()
    random_gif = (resumed / "gifs" / "random.gif").stat().st_mtime_ns
    ran: list[tuple[str, int]] = []
    original = evaluate_module.evaluate_agent

    def counting(agent: Any, seeds: list[int], **kwargs: Any) -> list:
        if "on_episode" in kwargs:
            ran.extend((agent.name, seed) for seed in seeds)
        return original(agent, seeds, **kwargs)

    monkeypatch.setattr(evaluate_module, "evaluate_agent", counting)
    again = _evaluate(resumed, agents)
    first = VALIDATION[0]
    assert ran == [("oracle", first + 1), ("oracle", first + 2)]
    assert (resumed / "episodes.csv").read_bytes() == (whole / "episodes.csv").read_bytes()
    assert (resumed / "results.md").read_text() == (whole / "results.md").read_text()
    assert repr(again) == repr(summaries)  # NaN-safe, every digit
    assert (resumed / "gifs" / "random.gif").stat().st_mtime_ns == random_gif
    assert (resumed / "gifs" / "oracle.gif").is_file()

    # Run once more: nothing left to do; then a row from other code is run again.
    ran.clear()
    _evaluate(resumed, agents)
    assert ran == []
    text = (resumed / "episodes.csv").read_text()
    fingerprint = rows[0]["fingerprint"]
    (resumed / "episodes.csv").write_text(text.replace(fingerprint, "0" * 16, 1))
    _evaluate(resumed, agents)
    assert ran == [("random", first)]
    assert (resumed / "episodes.csv").read_bytes() == (whole / "episodes.csv").read_bytes()


def test_an_example_gif_left_by_other_code_is_drawn_again(tmp_path):
    from tactile_search.render import save_gif

    out = tmp_path / "eval"
    _evaluate(out, ["random"], episodes=1)
    gif = out / "gifs" / "random.gif"
    ((row,), _) = read_episodes_csv(out / "episodes.csv")
    expected = gif_provenance(row["fingerprint"], VALIDATION[0], 4)
    assert gif_drawn_by(gif) == expected

    # Another evaluation's GIF in its place, beside rows that are all reused: drawn again.
    save_gif([np.zeros((4, 4, 3), np.uint8)], gif, comment="drawn by other code")
    _evaluate(out, ["random"], episodes=1)
    assert gif_drawn_by(gif) == expected
    with Image.open(gif) as image:
        assert image.size != (4, 4)

    # Its own GIF is kept.
    drawn_at = gif.stat().st_mtime_ns
    _evaluate(out, ["random"], episodes=1)
    assert gif.stat().st_mtime_ns == drawn_at
    assert gif_drawn_by(tmp_path / "missing.gif") is None


# Model directories


@pytest.fixture(scope="module")
def small_run(tmp_path_factory: pytest.TempPathFactory) -> Path:
    out = tmp_path_factory.mktemp("small")
    return train(
        TrainSettings(
            "ppo",
            "none",
            out=out,
            timesteps=256,
            n_envs=2,
            torch_threads=1,
            progress_bar=False,
            from_scratch=True,
        )
    )


def _edit_config(run_dir: Path, edit: Callable[[dict], Any]) -> None:
    config = yaml.safe_load((run_dir / "config.yml").read_text())
    (run_dir / "config.yml").write_text(yaml.safe_dump(edit(config)))


def _flip_a_byte(path: Path) -> None:
    data = bytearray(path.read_bytes())
    data[len(data) // 2] ^= 0xFF
    path.write_bytes(bytes(data))


BROKEN = {
    "no model": ("model.zip is missing", lambda d: (d / "model.zip").unlink()),
    "no config": ("config.yml is missing", lambda d: (d / "config.yml").unlink()),
    "config a list": (
        "config.yml must hold a mapping",
        lambda d: (d / "config.yml").write_text("- ppo\n- none\n"),
    ),
    "config not YAML": (
        "config.yml is not a readable YAML",
        lambda d: (d / "config.yml").write_text("algo: [ppo\n"),
    ),
    "config without algo": (
        r"config.yml lacks the keys \['algo'\]",
        lambda d: _edit_config(d, lambda c: {k: v for k, v in c.items() if k != "algo"}),
    ),
    "another version": (
        "config.yml was written by tactile_search 0.0.1",
        lambda d: _edit_config(
            d, lambda c: {**c, "versions": {**c["versions"], "tactile_search": "0.0.1"}}
        ),
    ),
    "corrupt zip": ("model.zip is corrupt", lambda d: _flip_a_byte(d / "model.zip")),
    "truncated zip": (
        "model.zip is not",
        lambda d: (d / "model.zip").write_bytes((d / "model.zip").read_bytes()[:3000]),
    ),
    "not a zip": ("model.zip is not a readable zip", lambda d: (d / "model.zip").write_text("x")),
    "another algorithm": (
        "model.zip does not load as a recurrent_ppo model",
        lambda d: _edit_config(d, lambda c: {**c, "algo": "recurrent_ppo"}),
    ),
    "another map": (
        "model.zip expects the observation space",
        lambda d: _edit_config(d, lambda c: {**c, "map": "gpis"}),
    ),
    "a label that is no name": (
        "label must be a non-empty name",
        lambda d: _edit_config(d, lambda c: {**c, "label": "ppo (none map)"}),
    ),
}


@pytest.mark.parametrize("case", list(BROKEN))
def test_a_broken_model_directory_raises_a_value_error_naming_the_file(
    small_run: Path, tmp_path: Path, case: str
):
    message, breakage = BROKEN[case]
    run_dir = tmp_path / "run"
    shutil.copytree(small_run, run_dir)
    breakage(run_dir)
    with pytest.raises(ValueError, match=message) as raised:
        LearnedAgent(run_dir)
    assert str(run_dir) in str(raised.value)


def test_the_intact_model_directory_loads(small_run: Path, tmp_path: Path):
    assert LearnedAgent(small_run).name == "ppo (none map)"
    labelled = tmp_path / "labelled"
    shutil.copytree(small_run, labelled)
    _edit_config(labelled, lambda c: {**c, "label": "ppo_finetuned"})
    assert LearnedAgent(labelled).name == "ppo_finetuned (none map)"
    with zipfile.ZipFile(small_run / "model.zip") as archive:
        assert "data" in archive.namelist()
    assert os.path.getsize(small_run / "model.zip") > 3000
