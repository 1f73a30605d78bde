"""Behaviour cloning from a Minari dataset alone (``python -m
agents.behaviour_cloning_from_dataset``): the clone fits the dataset's actions, and the
command, run tiny, trains and evaluates on validation layouts."""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path

import numpy as np
import pytest
from gymnasium import spaces

pytest.importorskip("minari")
pytest.importorskip("h5py")
pytest.importorskip("torch")
pytest.importorskip("stable_baselines3")

import minari
import torch

from agents.behaviour_cloning_from_dataset import main
from agents.offline.behaviour_cloning import (
    BehaviourCloningSettings,
    action_sizes,
    step_transitions,
    train_behaviour_cloning,
)
from agents.offline.catalogue import DatasetSource, dataset_id
from agents.offline.recording import training_seeds
from agents.offline.references import ReferenceScores
from agents.offline.writing import datasets_root, write_agent_dataset

IDENTIFY_ID = "tactile_search/IdentifyByTouch-v0"
REFERENCES = ReferenceScores("random_identify", -2.0, "oracle", 0.5, episodes=1)


@pytest.fixture(autouse=True)
def one_torch_thread() -> Iterator[None]:
    """One thread, as the command uses by default: the network is small, and on a busy
    machine a second thread slows each step down."""
    before = torch.get_num_threads()
    torch.set_num_threads(1)
    yield
    torch.set_num_threads(before)


@pytest.fixture(scope="module")
def identify_dataset(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, str]:
    """The identify planner's episodes on four training layouts (probes with a claim entry:
    a four-entry MultiDiscrete), in a root of their own."""
    root = tmp_path_factory.mktemp("datasets")
    source = DatasetSource(
        IDENTIFY_ID, "identify_planner", dataset_id(IDENTIFY_ID, "identify_planner")
    )
    with datasets_root(root):
        write_agent_dataset(source, training_seeds(4), REFERENCES)
    return root, source.dataset_id


def test_the_clone_fits_the_datasets_actions(identify_dataset: tuple[Path, str]) -> None:
    root, name = identify_dataset
    with datasets_root(root):
        dataset = minari.load_dataset(name)
    # Full batches of its 20 or so steps: the network can learn them all by heart.
    settings = BehaviourCloningSettings(epochs=150, batch_size=32, learning_rate=1e-2)
    policy, losses = train_behaviour_cloning(dataset, settings)
    assert losses[-1] < 0.1 * losses[0], losses
    observations, actions = step_transitions(dataset)
    assert actions.shape == (dataset.total_steps, 4)
    chosen = np.stack(
        [policy.act({k: v[i] for k, v in observations.items()}) for i in range(len(actions))]
    )
    # Every entry of the dataset's action (lane, depth, sweep, claim) at nearly every step.
    assert np.mean(np.all(chosen == actions, axis=1)) >= 0.9


def test_training_is_repeatable_from_its_seed(identify_dataset: tuple[Path, str]) -> None:
    root, name = identify_dataset
    with datasets_root(root):
        dataset = minari.load_dataset(name)
    settings = BehaviourCloningSettings(epochs=2, seed=3)
    first, first_losses = train_behaviour_cloning(dataset, settings)
    second, second_losses = train_behaviour_cloning(dataset, settings)
    assert first_losses == second_losses
    for a, b in zip(first.state_dict().values(), second.state_dict().values(), strict=True):
        assert torch.equal(a, b)


def test_only_discrete_actions_are_cloned() -> None:
    assert action_sizes(spaces.MultiDiscrete([29, 10, 9])) == [29, 10, 9]
    assert action_sizes(spaces.Discrete(5)) == [5]
    with pytest.raises(TypeError, match="Discrete"):
        action_sizes(spaces.Box(-1.0, 1.0, (3,)))
    with pytest.raises(ValueError, match="learning_rate"):
        BehaviourCloningSettings(learning_rate=0.0)
    with pytest.raises(TypeError, match="epochs"):
        BehaviourCloningSettings(epochs=1.5)  # type: ignore[arg-type]


def test_the_command_trains_and_evaluates_on_validation_layouts(
    identify_dataset: tuple[Path, str], capsys: pytest.CaptureFixture[str]
) -> None:
    root, name = identify_dataset
    main(["--dataset", name, "--datasets-root", str(root), "--epochs", "2", "--episodes", "2"])
    out = capsys.readouterr().out
    assert "epoch 2: loss" in out
    assert f"{name}: 4 episodes" in out
    assert "clone on 2 validation layouts: success" in out
    assert "normalised score" in out


def test_the_command_names_a_dataset_that_is_not_there(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    with pytest.raises(SystemExit):
        main(["--dataset", "tactile_search/search/nothing-v0", "--datasets-root", str(tmp_path)])
    assert "tactile_search/search/nothing-v0" in capsys.readouterr().err
