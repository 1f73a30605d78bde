"""Who labels the cloned states (agents.imitation.teachers): the planner by default, or an
ensemble of trained runs whose labels are the ensemble's own probes (distillation)."""

from __future__ import annotations

import shutil
from pathlib import Path

import numpy as np
import pytest

from agents.imitation.clone_stage import TEACHER_DEMONSTRATIONS_FILE, teacher_demonstrations_file
from agents.imitation.demonstrations import record
from agents.imitation.teachers import PLANNER, check_teacher, make_teacher
from agents.imitation.training import ImitationSettings
from agents.scripted import GpisProbePlanner
from tactile_search import CupboardSearchEnv

PROBE_GPIS = {"map": "gpis", "action_mode": "probe"}


def test_a_teacher_is_the_planner_or_an_ensemble_of_runs():
    assert ImitationSettings().teacher == PLANNER
    assert isinstance(make_teacher(PLANNER), GpisProbePlanner)
    assert check_teacher("ensemble:a,b") == "ensemble:a,b"
    with pytest.raises(ValueError, match=r"teacher must be one of the core's planners \["):
        ImitationSettings(teacher="oracle")
    with pytest.raises(ValueError, match="two runs or more"):
        ImitationSettings(teacher="ensemble:runs/one")
    with pytest.raises(TypeError, match="teacher must be a string"):
        ImitationSettings(teacher=3)  # type: ignore[arg-type]


def test_every_core_planner_is_a_teacher() -> None:
    from agents.scripted import CORE_PLANNERS

    for name, (face, _reference) in CORE_PLANNERS.items():
        assert ImitationSettings(teacher=name).teacher == name
        assert type(make_teacher(name)) is face


def test_each_teacher_keeps_its_demonstrations_in_a_file_of_its_own():
    assert teacher_demonstrations_file(PLANNER) == TEACHER_DEMONSTRATIONS_FILE
    ours = teacher_demonstrations_file("ensemble:a,b")
    assert ours != TEACHER_DEMONSTRATIONS_FILE and ours.endswith(".npz")
    assert ours != teacher_demonstrations_file("ensemble:a,c")


def test_an_ensemble_teacher_labels_every_state_with_its_own_probe(tmp_path: Path):
    from agents.evaluation.agent_specs import make_agent
    from tests.recipes import train_with_recipe

    run = train_with_recipe(tmp_path / "trained", "gpis")
    copy = tmp_path / "copy"
    shutil.copytree(run, copy)
    spec = f"ensemble:{run},{copy}"
    demonstrations = record([1_000_007], PROBE_GPIS, 0.9, teacher=spec)
    ensemble, _ = make_agent(spec)
    space = CupboardSearchEnv(**PROBE_GPIS).action_space
    for row in range(len(demonstrations)):
        observation = {key: value[row] for key, value in demonstrations.observations.items()}
        label = demonstrations.actions[row]
        assert space.contains(label)
        np.testing.assert_array_equal(label, ensemble.act(observation).astype(np.int64))
