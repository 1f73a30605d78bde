"""The evaluation protocol's seed ranges: training, validation and test are disjoint, the
training env draws its layouts (sampled, not read from a constant) from the training range
only, and the test range is read only by the final evaluation."""

from __future__ import annotations

import itertools

import numpy as np
import pytest

pytest.importorskip("stable_baselines3")

from agents.evaluate import main as evaluate_main
from agents.evaluation.evaluation import evaluation_seeds
from agents.sb3.training_env import make_training_env
from tactile_search.seed_ranges import SPLITS, TEST, TRAINING, VALIDATION, held_out_seeds


def in_range(seed: int, bounds: tuple[int, int]) -> bool:
    return bounds[0] <= seed < bounds[1]


def test_the_three_ranges_are_disjoint() -> None:
    ranges = sorted([TRAINING, VALIDATION, TEST])
    for (_, high), (low, _) in itertools.pairwise(ranges):
        assert high <= low


def test_the_training_env_draws_only_training_layouts() -> None:
    venv = make_training_env({"map": "none", "max_steps": 2}, n_envs=4, seed=0, threads=1)
    batch_env = venv.venv  # the VecMonitor's CupboardSearchSb3VecEnv
    drawn: list[int] = []
    draw = batch_env._new_seeds

    def recording(count: int) -> list[int]:
        seeds = draw(count)
        drawn.extend(seeds)
        return seeds

    batch_env._new_seeds = recording
    venv.reset()
    for _ in range(300):  # an episode ends every 3rd step in each env: ~400 new layouts
        venv.step(np.zeros((4, 3), dtype=np.float32))
    venv.close()
    assert len(drawn) > 300
    assert all(in_range(seed, TRAINING) for seed in drawn)
    assert not any(in_range(seed, bounds) for seed in drawn for bounds in SPLITS.values())


@pytest.mark.parametrize("split", sorted(SPLITS))
def test_held_out_seeds_lie_in_their_range(split: str) -> None:
    seeds = held_out_seeds(split, 1000)
    assert seeds[0] == SPLITS[split][0] and all(in_range(s, SPLITS[split]) for s in seeds)
    with pytest.raises(ValueError, match="holds"):
        held_out_seeds(split, SPLITS[split][1] - SPLITS[split][0] + 1)


def test_only_the_final_evaluation_reads_the_test_layouts(tmp_path) -> None:
    with pytest.raises(ValueError, match="test layouts are read only by the final results"):
        evaluation_seeds("test", 5)
    assert evaluation_seeds("test", 5, final=True) == held_out_seeds("test", 5)
    with pytest.raises(ValueError, match="final"):
        evaluate_main(
            ["--scripted", "oracle", "--episodes", "1", "--split", "test", "--out", str(tmp_path)]
        )
    final = ["--scripted", "oracle", "--episodes", "1", "--split", "test", "--final"]
    evaluate_main([*final, "--no-gifs", "--out", str(tmp_path)])
    assert f"test layout seeds {TEST[0]}..{TEST[0]}" in (tmp_path / "results.md").read_text()
    with pytest.raises(ValueError, match="split"):
        held_out_seeds("training", 5)
