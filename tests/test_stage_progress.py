"""What a user training a variant sees of the clone stage: the stages listed with their
sizes, and each stage's bar advancing once per episode recorded or epoch cloned."""

from __future__ import annotations

from agents.imitation.batched import record_batched
from agents.imitation.cloning import CloningSettings, clone
from agents.imitation.stage_progress import stage_bar, stage_plan
from agents.imitation.training import ImitationSettings, _training_layouts

PROBE_GPIS = {"map": "gpis", "action_mode": "probe"}


def test_the_plan_names_every_stage_with_its_size() -> None:
    settings = ImitationSettings(demo_episodes=2000, dagger_rounds=3, dagger_episodes=1000)
    plan = stage_plan(settings, 150_000)
    assert plan == (
        "stages: the teacher's demonstrations (2,000 episodes), behaviour cloning (40 epochs), "
        "3 DAgger rounds (1,000 episodes, 15 epochs each), PPO fine-tuning (150,000 probes)"
    )
    one = ImitationSettings(demo_episodes=10, dagger_rounds=1, dagger_episodes=5)
    assert "1 DAgger round (5 episodes" in stage_plan(one)
    assert "DAgger" not in stage_plan(ImitationSettings(demo_episodes=10, dagger_rounds=0))


def test_the_bars_advance_per_episode_recorded_and_per_epoch_cloned() -> None:
    from agents.sb3.recipes import algorithm_class, load_hyperparams, new_model
    from agents.sb3.training_env import make_training_env

    counted = []
    demonstrations = record_batched(
        _training_layouts(1, 7), PROBE_GPIS, 0.9, num_envs=3, progress=counted.append
    )
    assert counted == [1] * 7
    recipe = load_hyperparams("ppo", "gpis")
    env = make_training_env(recipe["env_kwargs"], 2, 0)
    policy = new_model(algorithm_class("ppo"), recipe, env, seed=0).policy
    env.close()
    epochs = []
    clone(policy, demonstrations, CloningSettings(epochs=3), progress=epochs.append)
    assert epochs == [1, 1, 1]
    with stage_bar("quiet", 3, "epoch", enabled=False) as update:
        assert update is None
