"""A published run's model card is generated from the run and its evaluation rows (nothing
typed), beside a record of its model's digest; the benchmark checks a model against that
record before unpickling it, refuses a changed model and warns about one without a record."""

from __future__ import annotations

import dataclasses
import shutil
import zipfile
from pathlib import Path

import pytest
import yaml

pytest.importorskip("stable_baselines3")

from agents import run_dir
from agents.evaluation.episodes_csv import EPISODES_FILE, read_episodes_csv, write_episodes_csv
from agents.grid.model_card import published_runs, write_model_card
from tactile_search.benchmark import load_policy
from tactile_search.benchmark.__main__ import main
from tactile_search.benchmark.model_digest import (
    UnverifiedModelWarning,
    digest_path,
    model_digest,
    recorded_digest,
    verified_digest,
    write_digest,
)
from tactile_search.benchmark.statistics import summarize
from tactile_search.benchmark.summary_table import markdown_row, summary_cells

ROOT = Path(__file__).resolve().parents[1]
MODELS = ROOT / "docs" / "results" / "models"
#: A small published run (no map: its model is the smallest) and its agent's evaluated name.
RUN = "ppo_none_seed0"
AGENT = "ppo (none map, seed 0)"
#: Rows of the published evaluation a test card summarises.
ROWS = 40


def copy_run(into: Path, name: str = RUN) -> Path:
    """A copy of a published run's model, config and clone-stage config in ``into``."""
    source, copy = MODELS / name, into / name
    run_dir.clone_dir(copy).mkdir(parents=True)
    for path in (run_dir.model_path, run_dir.config_path):
        shutil.copyfile(path(source), path(copy))
    shutil.copyfile(
        run_dir.config_path(run_dir.clone_dir(source)), run_dir.config_path(run_dir.clone_dir(copy))
    )
    return copy


def published_rows(agents: set[str]) -> list[dict]:
    """The first ``ROWS`` published evaluation rows of each of ``agents``."""
    rows, _ = read_episodes_csv(ROOT / "docs" / "results" / EPISODES_FILE)
    kept = []
    for agent in sorted(agents):
        kept += [row for row in rows if row["agent"] == agent][:ROWS]
    return kept


def tamper(model: Path) -> None:
    """Changes one byte of the model's weights, keeping it a readable archive."""
    original = model.with_name("original.zip")
    model.rename(original)
    with zipfile.ZipFile(original) as source, zipfile.ZipFile(model, "w") as changed:
        for name in source.namelist():
            content = source.read(name)
            if name == "policy.pth":
                content = content[:-1] + bytes([content[-1] ^ 1])
            changed.writestr(name, content)
    original.unlink()


def test_a_card_holds_the_runs_facts_and_its_evaluation(tmp_path: Path) -> None:
    run = copy_run(tmp_path / "models")
    results = tmp_path / "results"
    results.mkdir()
    rows = published_rows({AGENT, "oracle"})
    write_episodes_csv(results / EPISODES_FILE, rows)
    card = write_model_card(run, results)
    assert card == run_dir.model_card_path(run)
    text = card.read_text()
    config = yaml.safe_load(run_dir.config_path(run).read_text())
    clone = yaml.safe_load(run_dir.config_path(run_dir.clone_dir(run)).read_text())
    digest = model_digest(run_dir.model_path(run)).hex()
    assert recorded_digest(run_dir.model_path(run)) == digest
    assert f"`{digest}`" in text
    assert f"search (`{config['env_id']}`)" in text
    assert f"| map | `{config['map']}` |" in text
    assert f"| algorithm | `{config['algo']}` |" in text
    assert f"`agents/hyperparams/ppo.yml`, key `{config['env_id']}` -> `none`" in text
    assert (
        f"python -m agents.train --env-id {config['env_id']} --algo ppo --map none --seed "
        f"{config['seed']}"
    ) in text
    assert f"| training seed | {config['seed']} |" in text
    clone_min, ppo_min = clone["wall_clock_seconds"] / 60, config["wall_clock_seconds"] / 60
    assert f"{clone_min:.1f} + {ppo_min:.1f} = {clone_min + ppo_min:.1f}" in text
    for package, version in config["versions"].items():
        assert f"| {package} | `{version}` |" in text
    mine = [row for row in rows if row["agent"] == AGENT]
    summary = dataclasses.asdict(summarize(AGENT, "none", mine))
    assert markdown_row([f"{ROWS} test", *summary_cells("search", summary)]) in text
    assert f"The rows of `{AGENT}`" in text
    # Generated: the same run and rows give the same bytes.
    assert write_model_card(run, results).read_text() == text


def test_a_run_not_yet_evaluated_gets_a_card_that_says_so(tmp_path: Path) -> None:
    run = copy_run(tmp_path / "models")
    text = write_model_card(run, tmp_path / "no_results").read_text()
    assert "Not evaluated yet" in text


def test_only_finished_runs_are_published_runs(tmp_path: Path) -> None:
    models = tmp_path / "models"
    finished = copy_run(models)
    unfinished = copy_run(models, "ppo_gpis_seed0")
    run_dir.model_path(unfinished).unlink()
    assert published_runs(models) == [finished]
    with pytest.raises(ValueError, match="not a finished run"):
        write_model_card(unfinished, tmp_path)


def test_the_agents_digest_is_the_packages() -> None:
    assert run_dir.model_digest is model_digest
    assert run_dir.model_digest_path(MODELS / RUN) == digest_path(run_dir.model_path(MODELS / RUN))


def test_a_tampered_model_is_refused_before_it_is_unpickled(tmp_path, monkeypatch, capsys) -> None:
    import stable_baselines3

    model = run_dir.model_path(copy_run(tmp_path))
    recorded = write_digest(model)
    tamper(model)
    assert model_digest(model).hex() != recorded

    def unpickled(*args, **kwargs):
        raise AssertionError("the model was loaded before its digest was checked")

    monkeypatch.setattr(stable_baselines3.PPO, "load", unpickled)
    with pytest.raises(ValueError, match="does not match the digest recorded beside it"):
        load_policy(model)
    with pytest.raises(SystemExit) as exit_:
        main(["--policy", str(model), "--episodes", "1", "--no-progress"])
    assert exit_.value.code == 2
    error = capsys.readouterr().err
    assert len(error.strip().splitlines()) == 1 and "does not match the digest" in error


def test_a_model_without_a_digest_loads_with_one_warning_line(tmp_path, capsys) -> None:
    model = run_dir.model_path(copy_run(tmp_path))
    with pytest.warns(UnverifiedModelWarning, match="no recorded digest"):
        policy = load_policy(model)
    assert not policy.verified and policy.digest == model_digest(model).hex()
    main(["--policy", str(model), "--episodes", "1", "--num-envs", "1", "--no-progress"])
    error = capsys.readouterr().err.strip().splitlines()
    assert len(error) == 1 and "warning:" in error[0] and "no recorded digest" in error[0]
    write_digest(model)
    policy = load_policy(model)
    assert policy.verified and policy.digest == model_digest(model).hex()


def test_a_digest_record_that_holds_no_digest_is_refused(tmp_path: Path) -> None:
    model = run_dir.model_path(copy_run(tmp_path))
    digest_path(model).write_text("not a digest\n")
    with pytest.raises(ValueError, match="64 lowercase hex digits"):
        verified_digest(model)


@pytest.mark.parametrize(
    "model",
    sorted(path for path in MODELS.rglob("*.zip") if digest_path(path).is_file()),
    ids=lambda path: str(path.relative_to(MODELS)),
)
def test_a_published_model_matches_its_recorded_digest(model: Path) -> None:
    assert verified_digest(model) == model_digest(model).hex()


def test_the_projects_evaluation_refuses_a_tampered_model_too(tmp_path, monkeypatch) -> None:
    import stable_baselines3

    from agents.sb3.learned import LearnedAgent

    run = copy_run(tmp_path)
    write_digest(run_dir.model_path(run))
    tamper(run_dir.model_path(run))

    def unpickled(*args, **kwargs):
        raise AssertionError("the model was loaded before its digest was checked")

    monkeypatch.setattr(stable_baselines3.PPO, "load", unpickled)
    with pytest.raises(ValueError, match="does not match the digest recorded beside it"):
        LearnedAgent(run)


def test_a_card_reads_no_rows_of_another_tasks_run_of_the_same_name(tmp_path: Path) -> None:
    # The map task's run ppo_none_seed0 and the search task's share the agent name
    # "ppo (none map, seed 0)"; the search evaluation's rows are the search run's, not its.
    run = copy_run(tmp_path / "models", f"MapByTouch-v0/{RUN}")
    results = tmp_path / "results"
    results.mkdir()
    write_episodes_csv(results / EPISODES_FILE, published_rows({AGENT}))
    text = write_model_card(run, results).read_text()
    assert "Not evaluated yet" in text and "CupboardSearch-v0" not in text
