"""A recipe's learning rate or clip range as rl-zoo3's ``lin_<value>``: a linear schedule
from the value to 0 over the run, for SB3 and left as the string for rl-zoo3."""

from __future__ import annotations

import pytest

from agents.sb3.recipes import algorithm_kwargs, schedule


def test_a_number_stays_a_number() -> None:
    assert schedule("learning_rate", 1e-4) == 1e-4


def test_lin_falls_from_its_value_at_the_start_to_zero_at_the_end() -> None:
    rate = schedule("learning_rate", "lin_2.0e-4")
    assert rate(1.0) == pytest.approx(2e-4)
    assert rate(0.5) == pytest.approx(1e-4)
    assert rate(0.0) == 0.0


@pytest.mark.parametrize("bad", ["lin_", "lin_x", "lin_-1e-4", "lin_0", "exp_1e-4", "1e-4"])
def test_other_strings_are_refused_naming_the_forms(bad: str) -> None:
    with pytest.raises(ValueError, match="lin_<value>"):
        schedule("clip_range", bad)


def test_sb3_gets_the_schedule_and_rl_zoo3_the_string() -> None:
    recipe = {"learning_rate": "lin_1.5e-4", "clip_range": 0.2, "n_timesteps": 10}
    made = algorithm_kwargs(recipe)
    assert callable(made["learning_rate"]) and made["clip_range"] == 0.2
    assert "n_timesteps" not in made
    assert algorithm_kwargs(recipe, make_schedules=False)["learning_rate"] == "lin_1.5e-4"
    with pytest.raises(ValueError, match="learning_rate"):
        algorithm_kwargs({"learning_rate": "lin_x"}, make_schedules=False)


def test_a_ppo_model_trains_with_the_scheduled_rate() -> None:
    from stable_baselines3 import PPO

    model = PPO(
        "MlpPolicy",
        "CartPole-v1",
        n_steps=32,
        batch_size=32,
        n_epochs=1,
        device="cpu",
        **algorithm_kwargs({"learning_rate": "lin_1.0e-3"}),
    )
    model.learn(64)
    # The optimiser's rate follows the schedule: 0 at the run's last update (a constant
    # rate would still be 1e-3), half the start half way.
    assert model.policy.optimizer.param_groups[0]["lr"] == 0.0
    assert model.lr_schedule(0.5) == pytest.approx(5e-4)
