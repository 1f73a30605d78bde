"""Learning from the GPIS probe planner (``agents.imitation``): the demonstrations are the
planner's probes on states it reads only through observations, DAgger's labels are what the
planner chooses when it follows the student's probes, a student with another map sees its
own observation, behaviour cloning learns the teacher's probes on held-out layouts, and the
command writes a run that evaluates and warm-starts PPO."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np
import pytest

from agents.imitation.cloning import CloningSettings, agreement, clone
from agents.imitation.demonstrations import Demonstrations, record
from agents.imitation.training import ImitationSettings, _training_layouts
from agents.scripted import GpisProbePlanner
from tactile_search import CupboardSearchEnv, seed_ranges

PROBE_GPIS = {"map": "gpis", "action_mode": "probe"}
GAMMA = 0.9


@pytest.fixture
def no_ground_truth(monkeypatch: pytest.MonkeyPatch) -> None:
    """Every env of the test refuses its ground truth and its oracle."""

    def refuse(self: Any) -> Any:
        raise AssertionError("the teacher read the ground truth")

    monkeypatch.setattr(CupboardSearchEnv, "render_state", refuse)
    monkeypatch.setattr(CupboardSearchEnv, "oracle_action", refuse)


def replay(layout_seed: int, env_kwargs: dict, students_probes: list | None = None) -> dict:
    """One episode as ``record`` should see it, driven by hand: the planner labels each
    state (following ``students_probes`` where given) in the env of ``env_kwargs``."""
    env = CupboardSearchEnv(**env_kwargs)
    planner = GpisProbePlanner()
    observation, info = env.reset(seed=layout_seed)
    planner.reset(env, observation, info)
    seen, labels, rewards = [], [], []
    done, step = False, 0
    while not done:
        label = planner.act(observation)
        action = label
        if students_probes is not None:
            action = students_probes[step]
            planner.follow(action)
        seen.append(observation)
        labels.append(label)
        observation, reward, terminated, truncated, info = env.step(action)
        rewards.append(reward)
        done, step = terminated or truncated, step + 1
    return {"observations": seen, "labels": np.array(labels), "rewards": rewards}


def test_the_teachers_demonstrations_are_its_probes_and_the_discounted_returns(
    no_ground_truth: None,
) -> None:
    demonstrations = record([1, 2], PROBE_GPIS, GAMMA)
    first = replay(1, PROBE_GPIS)
    n = len(first["labels"])
    assert len(demonstrations) == n + len(replay(2, PROBE_GPIS)["labels"])
    np.testing.assert_array_equal(demonstrations.actions[:n], first["labels"])
    np.testing.assert_array_equal(demonstrations.layout_seeds[:n], 1)
    space = CupboardSearchEnv(**PROBE_GPIS).action_space
    assert all(space.contains(action) for action in demonstrations.actions)
    expected = np.cumsum([r * GAMMA**i for i, r in enumerate(first["rewards"])][::-1])[::-1]
    np.testing.assert_allclose(
        demonstrations.returns[:n], expected / GAMMA ** np.arange(n), rtol=1e-5
    )
    np.testing.assert_array_equal(
        demonstrations.observations["map"][0], first["observations"][0]["map"]
    )


def map_rule_demonstrations(layouts: int) -> Demonstrations:
    """A small fixed demo set whose probe depends on the map alone: at each layout's reset, a
    lane on the side of the cupboard where the GPIS std's mass lies (left of the layouts'
    median centroid: lane 3, else lane 25), straight in at the first depth. The layouts whose
    centroid lies nearest the median (a fifth of those drawn) are left out: there a held-out
    layout's side turns on details of the network's numerics, which differ between CPUs
    (oneDNN's kernels), and the test measures learning, not that."""
    env = CupboardSearchEnv(**PROBE_GPIS)
    drawn = [env.reset(seed=seed)[0] for seed in range(layouts * 5 // 4)]
    std = np.stack([o["map"][1] for o in drawn]).astype(float).sum(axis=1)
    centroid = (std * np.arange(std.shape[1])).sum(axis=1) / std.sum(axis=1)
    clear = np.sort(np.argsort(np.abs(centroid - np.median(centroid)))[-layouts:])
    observations = [drawn[i] for i in clear]
    lanes = np.where(centroid[clear] < np.median(centroid), 3, 25)
    middle = env.action_space.nvec[2] // 2
    return Demonstrations(
        {key: np.stack([o[key] for o in observations]) for key in observations[0]},
        np.stack([lanes, np.zeros(layouts, int), np.full(layouts, middle)], axis=1),
        np.zeros(layouts, np.float32),
        np.arange(layouts, dtype=np.uint64),
        np.zeros(layouts, bool),
        np.zeros(layouts, np.int64),
        np.zeros(layouts, np.int64),  # one probe per episode
    )


def test_behaviour_cloning_learns_a_map_dependent_probe_for_held_out_layouts() -> None:
    """Cloning into the GPIS recipe's network (its MLP with ReLU: see
    docs/results/ablations_imitation) on 240 layouts agrees with the demonstrations on 85 %
    of 60 held-out ones, where always choosing one side gets half."""
    import torch

    from agents.sb3.recipes import algorithm_class, load_hyperparams, new_model
    from agents.sb3.training_env import make_training_env

    demonstrations = map_rule_demonstrations(300)
    train, held_out = demonstrations.rows(np.arange(240)), demonstrations.rows(np.arange(240, 300))
    torch.set_num_threads(1)
    recipe = load_hyperparams("ppo", "gpis")
    recipe["policy_kwargs"]["activation_fn"] = "torch.nn.ReLU"
    model = new_model(
        algorithm_class("ppo"), recipe, make_training_env(recipe["env_kwargs"], 16, 0), seed=0
    )
    before = agreement(model.policy, held_out)["lane"]
    history = clone(
        model.policy, train, CloningSettings(epochs=30, batch_size=32, learning_rate=1e-3)
    )
    assert history[-1]["nll"] < history[0]["nll"]
    after = agreement(model.policy, held_out)
    assert after["lane"] >= 0.85 > before, (before, after)
    assert after["depth"] == after["sweep"] == 1.0


def random_student(seed: int, space: Any) -> Any:
    """A student probing at random (its own stream per episode)."""

    def start(layout_seed: int) -> Any:
        rng = np.random.default_rng([seed, layout_seed])

        def act(_observation: dict) -> np.ndarray:
            return np.array([rng.integers(n) for n in space.nvec])

        return act

    return start


def test_dagger_labels_are_the_observation_only_planners_following_the_student(
    no_ground_truth: None,
) -> None:
    space = CupboardSearchEnv(**PROBE_GPIS).action_space
    labelled = record([3], PROBE_GPIS, GAMMA, student=random_student(0, space))
    rng = np.random.default_rng([0, 3])
    probes = [np.array([rng.integers(n) for n in space.nvec]) for _ in range(len(labelled))]
    hand = replay(3, PROBE_GPIS, probes)
    np.testing.assert_array_equal(labelled.actions, hand["labels"])
    for i, observation in enumerate(hand["observations"]):
        np.testing.assert_array_equal(labelled.observations["proprio"][i], observation["proprio"])
    # The student went its own way: its probes are not the labels.
    assert not np.array_equal(np.array(probes), labelled.actions)


def test_a_student_with_another_map_sees_its_own_map_and_is_labelled_from_the_gpis_map(
    no_ground_truth: None,
) -> None:
    occupancy = {"map": "occupancy", "action_mode": "probe"}
    labelled = record([1], occupancy, GAMMA)
    teacher = replay(1, PROBE_GPIS)
    np.testing.assert_array_equal(labelled.actions, teacher["labels"])
    env = CupboardSearchEnv(**occupancy)
    observation, _ = env.reset(seed=1)
    np.testing.assert_array_equal(labelled.observations["map"][0], observation["map"])
    assert not np.array_equal(observation["map"], teacher["observations"][0]["map"])


def test_demonstrations_need_the_probe_mode_and_consistent_rows(tmp_path: Path) -> None:
    with pytest.raises(ValueError, match="action_mode='probe'"):
        record([1], {"map": "gpis"}, GAMMA)
    demonstrations = record([1, 2, 4, 5], PROBE_GPIS, GAMMA)
    path = tmp_path / "demos.npz"
    demonstrations.save(path)
    loaded = Demonstrations.load(path)
    np.testing.assert_array_equal(loaded.observations["map"], demonstrations.observations["map"])
    np.testing.assert_array_equal(loaded.actions, demonstrations.actions)
    kept, held_out = demonstrations.split_by_layout(0.5, seed=0)
    assert kept.episodes == held_out.episodes == 2
    assert not set(kept.layout_seeds) & set(held_out.layout_seeds)
    with pytest.raises(ValueError, match="one row per probe"):
        Demonstrations(
            demonstrations.observations,
            demonstrations.actions[:1],
            *(np.zeros(1) for _ in range(5)),
        )
    with pytest.raises(ValueError, match="not a file of demonstrations"):
        np.savez(tmp_path / "other.npz", actions=demonstrations.actions)
        Demonstrations.load(tmp_path / "other.npz")


def test_the_planner_refuses_to_follow_a_probe_off_its_grid() -> None:
    env = CupboardSearchEnv(**PROBE_GPIS)
    observation, info = env.reset(seed=1)
    planner = GpisProbePlanner()
    planner.reset(env, observation, info)
    planner.act(observation)
    for bad in ([29, 0, 0], [0, -1, 0], [0.5, 0, 0], [1, 2]):
        with pytest.raises(ValueError, match="probe"):
            planner.follow(np.array(bad))


def test_settings_refuse_what_cannot_train() -> None:
    with pytest.raises(ValueError, match="demo_episodes"):
        ImitationSettings(demo_episodes=1)
    with pytest.raises(TypeError, match="dagger_rounds"):
        ImitationSettings(dagger_rounds=1.5)
    with pytest.raises(TypeError, match="mirror"):
        ImitationSettings(mirror="yes")
    with pytest.raises(ValueError, match="learning_rate"):
        CloningSettings(learning_rate=0.0)
    with pytest.raises(ValueError, match="entropy_weight"):
        CloningSettings(entropy_weight=float("nan"))


def test_training_layouts_are_distinct_and_in_the_training_range() -> None:
    layouts = _training_layouts(3, 500)
    low, high = seed_ranges.TRAINING
    assert len(set(layouts)) == 500 and all(low <= seed < high for seed in layouts)
    assert layouts == _training_layouts(3, 500) and layouts != _training_layouts(4, 500)


def test_the_command_writes_a_run_that_evaluates_and_warm_starts_ppo(tmp_path: Path) -> None:
    """``python -m agents.imitate`` for a few hundred probes: the run's model plays an
    episode as an evaluated agent and starts a PPO run (``--init-from``)."""
    import yaml

    from agents.imitate import main
    from agents.sb3.learned import LearnedAgent
    from tests.recipes import train_with_recipe

    args = ["--map", "gpis", "--seed", "5", "--out", str(tmp_path), "--quiet"]
    few = ["--demo-episodes", "100", "--dagger-rounds", "1", "--dagger-episodes", "60"]
    main([*args, *few, "--epochs", "5", "--dagger-epochs", "2"])
    run_dir = tmp_path / "ppo_gpis_seed5"
    config = yaml.safe_load((run_dir / "config.yml").read_text())
    rounds = config["imitation"]["rounds"]
    assert [r["round"] for r in rounds] == [0, 1]
    assert rounds[0]["layouts"] == 100 and rounds[1]["layouts"] == 60
    assert config["timesteps_done"] == sum(r["states"] for r in rounds) >= 200
    agent = LearnedAgent(run_dir)
    assert config["label"] == "imitation" and agent.name == "imitation (gpis map)"
    cloned = LearnedAgent(run_dir / "rounds" / "round0")
    assert cloned.name == "imitation_round0 (gpis map)"
    assert cloned.config["timesteps_done"] == rounds[0]["states"]
    env = CupboardSearchEnv(**agent.env_kwargs)
    observation, info = env.reset(seed=seed_ranges.VALIDATION[0])
    agent.reset(env, observation, info)
    assert env.action_space.contains(agent.act(observation).astype(np.int64))
    # Everything cloned: the teacher's probes but its held-out layouts', and the student's.
    kept = len(Demonstrations.load(run_dir / "demonstrations.npz"))
    assert rounds[1]["states"] < kept < config["timesteps_done"]
    anchored = {"anchor_weight": 1.0, "anchor_decay_timesteps": 128}
    warm = train_with_recipe(
        tmp_path / "ppo", "gpis", train_kwargs={"init_from": run_dir}, **anchored
    )
    assert yaml.safe_load((warm / "config.yml").read_text())["init_from"]["path"].startswith(
        str(run_dir)
    )
    progress = (warm / "progress.csv").read_text().splitlines()
    assert "anchor/nll" in progress[0] and "anchor/weight" in progress[0]
    # An anchor needs the demonstrations of the model it starts from.
    with pytest.raises(ValueError, match=r"demonstrations\.npz is missing"):
        train_with_recipe(tmp_path / "again", "gpis", train_kwargs={"init_from": warm}, **anchored)


def test_the_anchor_pulls_the_policy_towards_the_demonstrations() -> None:
    """Before each rollout the anchor trains a few minibatches of the demonstrations with a
    weight that decays to nothing: the demonstrations' NLL falls while it acts, and nothing
    changes once it has decayed."""
    import torch
    from stable_baselines3.common.logger import Logger

    from agents.sb3.anchor import behaviour_cloning_anchor
    from agents.sb3.recipes import algorithm_class, load_hyperparams, new_model
    from agents.sb3.training_env import make_training_env

    demonstrations = map_rule_demonstrations(64)
    recipe = load_hyperparams("ppo", "gpis")
    model = new_model(
        algorithm_class("ppo"), recipe, make_training_env(recipe["env_kwargs"], 16, 0), seed=0
    )
    model.set_logger(Logger(folder=None, output_formats=[]))
    anchor = behaviour_cloning_anchor(demonstrations, weight=1.0, decay_timesteps=100)
    anchor.init_callback(model)

    def nll() -> float:
        with torch.no_grad():
            observations, _ = model.policy.obs_to_tensor(demonstrations.observations)
            actions = torch.as_tensor(demonstrations.actions)
            return -model.policy.evaluate_actions(observations, actions)[1].mean().item()

    before = nll()
    for _ in range(5):
        anchor.on_rollout_start()
    assert nll() < before - 0.1
    model.num_timesteps = 100
    weights = [p.detach().clone() for p in model.policy.parameters()]
    anchor.on_rollout_start()
    assert all(torch.equal(a, b) for a, b in zip(weights, model.policy.parameters(), strict=True))
    with pytest.raises(ValueError, match="weight"):
        behaviour_cloning_anchor(demonstrations, weight=-1.0, decay_timesteps=100)


def test_the_mirror_image_of_a_state_gets_the_mirror_image_of_the_teachers_probe_mostly() -> None:
    """The planner, shown the mirror image of a reset's observation, chooses the mirror
    image of the probe it chooses on the observation itself in most layouts, and a probe in
    a neighbouring lane in nearly all (it is not exactly symmetric: its grid lookups round
    down, and near-ties go one way): mirrored demonstrations are the teacher's choices."""
    from agents.imitation.mirror import mirrored
    from agents.scripted.geometry import Geometry

    env = CupboardSearchEnv(**PROBE_GPIS)
    geometry = Geometry.from_env(env)
    same = near = 0
    layouts = range(30)
    for seed in layouts:
        observation, info = env.reset(seed=seed)
        planner = GpisProbePlanner()
        planner.reset(env, observation, info)
        probe = planner.act(observation)
        demonstration = Demonstrations(
            {key: value[None] for key, value in observation.items()},
            probe[None],
            *(np.zeros(1) for _ in range(5)),
        )
        image = mirrored(demonstration, geometry)
        seen = {key: value[0] for key, value in image.observations.items()}
        planner = GpisProbePlanner()
        planner.reset(env, seen, info)
        chosen = planner.act(seen)
        same += np.array_equal(chosen, image.actions[0])
        near += abs(int(chosen[0]) - int(image.actions[0][0])) <= 1
    assert same >= 0.5 * len(layouts) and near >= 0.8 * len(layouts), (same, near)


def test_mirroring_twice_gives_the_demonstrations_back_and_needs_a_symmetric_scene() -> None:
    from agents.imitation.mirror import mirrored
    from agents.scripted.geometry import Geometry

    demonstrations = record([1, 2], PROBE_GPIS, GAMMA)
    env = CupboardSearchEnv(**PROBE_GPIS)
    geometry = Geometry.from_env(env)
    twice = mirrored(mirrored(demonstrations, geometry), geometry)
    for key, value in demonstrations.observations.items():
        np.testing.assert_array_equal(twice.observations[key], value)
    np.testing.assert_array_equal(twice.actions, demonstrations.actions)
    once = mirrored(demonstrations, geometry)
    assert not np.array_equal(once.observations["map"], demonstrations.observations["map"])
    lopsided = CupboardSearchEnv(**PROBE_GPIS, camera_position=[0.05, -0.25, 0.075])
    with pytest.raises(ValueError, match="the camera's x"):
        mirrored(demonstrations, Geometry.from_env(lopsided))


# A clone stage of a few seconds: a dozen teacher episodes, one small DAgger round.
SMALL_IMITATION = {
    "demo_episodes": 12,
    "dagger_rounds": 1,
    "dagger_episodes": 4,
    "dagger_epochs": 1,
    "mirror": True,
    "cloning": {"epochs": 2},
}


def test_a_recipe_with_an_imitation_section_fine_tunes_the_clone_it_keeps(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """``train`` with a recipe's ``imitation`` section clones the planner into
    ``<run>/imitation/`` and warm-starts PPO from that clone; the recorded section is the
    one run (overrides applied); a run started again reuses the clone; another section
    clones afresh."""
    import yaml

    from agents.run_dir import model_digest
    from tests.recipes import train_with_recipe

    section = {**SMALL_IMITATION, "demo_episodes": 40}
    small = {"demo_episodes": 12}
    run_dir = train_with_recipe(tmp_path, "none", imitation_overrides=small, imitation=section)
    clone_dir = run_dir / "imitation"
    config = yaml.safe_load((run_dir / "config.yml").read_text())
    assert config["hyperparams"]["imitation"] == {**section, **small}
    assert config["init_from"]["model_digest"] == model_digest(clone_dir / "model.zip").hex()
    clone = yaml.safe_load((clone_dir / "config.yml").read_text())
    assert clone["imitation"]["demo_episodes"] == 12 and clone["imitation"]["mirror"] is True
    assert [r["round"] for r in clone["imitation"]["rounds"]] == [0, 1]
    assert (clone_dir / "teacher_demonstrations.npz").is_file()
    digest = model_digest(clone_dir / "model.zip")
    capsys.readouterr()

    again = train_with_recipe(tmp_path, "none", imitation_overrides=small, imitation=section)
    assert "reusing the clone" in capsys.readouterr().out
    assert model_digest(again / "imitation" / "model.zip") == digest

    train_with_recipe(tmp_path, "none", imitation={**section, "demo_episodes": 10})
    assert "imitating the teacher" in capsys.readouterr().out
    clone = yaml.safe_load((clone_dir / "config.yml").read_text())
    assert clone["imitation"]["demo_episodes"] == 10

    # A stage killed while it wrote the teacher's demonstrations records them again.
    (clone_dir / "model.zip").unlink()
    teacher = clone_dir / "teacher_demonstrations.npz"
    teacher.write_bytes(teacher.read_bytes()[:100])
    train_with_recipe(tmp_path, "none", imitation={**section, "demo_episodes": 10})
    assert Demonstrations.load(teacher).episodes == 10


def test_a_warm_start_skips_the_imitation_section_and_bad_sections_are_refused(
    tmp_path: Path,
) -> None:
    import yaml

    from agents.imitation.clone_stage import with_overrides
    from agents.sb3.training import TrainSettings, train
    from tests.recipes import train_with_recipe

    plain = train_with_recipe(tmp_path / "plain", "none")
    warm = train_with_recipe(
        tmp_path / "warm", "none", train_kwargs={"init_from": plain}, imitation=SMALL_IMITATION
    )
    assert "imitation" not in yaml.safe_load((warm / "config.yml").read_text())["hyperparams"]
    assert not (warm / "imitation").exists()
    with pytest.raises(ValueError, match=r"no setting \['demos'\]"):
        train_with_recipe(tmp_path / "bad", "none", imitation={"demos": 10})
    with pytest.raises(ValueError, match=r"imitation.cloning has no setting \['seed'\]"):
        train_with_recipe(tmp_path / "bad", "none", imitation={"cloning": {"seed": 1}})
    with pytest.raises(TypeError, match="mapping"):
        train_with_recipe(tmp_path / "bad", "none", imitation=[1, 2])
    with pytest.raises(ValueError, match="demo_episodes"):
        train_with_recipe(tmp_path / "bad", "none", imitation={"demo_episodes": 1})
    with pytest.raises(ValueError, match="no imitation section"):
        train(
            TrainSettings(
                "ppo",
                "none",
                out=tmp_path,
                hyperparams=tmp_path / "plain" / "ppo.yml",
                imitation={"mirror": True},
            )
        )
    # PPO alone on a recipe with a clone stage: only from a model, or from scratch by choice.
    with pytest.raises(ValueError, match="fine-tunes a clone of the planner"):
        train(TrainSettings("ppo", "none", out=tmp_path / "alone"))
    scratch = train(
        TrainSettings(
            "ppo",
            "none",
            out=tmp_path / "alone",
            timesteps=64,
            n_envs=2,
            from_scratch=True,
            progress_bar=False,
            torch_threads=1,
        )
    )
    assert "imitation" not in yaml.safe_load((scratch / "config.yml").read_text())["hyperparams"]
    with pytest.raises(TypeError, match="from_scratch"):
        train(TrainSettings("ppo", "none", out=tmp_path / "alone", from_scratch="yes"))
    assert with_overrides({"cloning": {"epochs": 3}}, {"cloning": {"batch_size": 8}}) == {
        "cloning": {"epochs": 3, "batch_size": 8}
    }


def test_a_recurrent_student_is_cloned_on_whole_episodes_and_learns_what_needs_memory() -> None:
    """Two-probe episodes whose second probe depends only on the first observation (the
    second observations are all alike): no policy without memory can agree on more than
    half of the second probes; the recurrent recipe's network, cloned on whole episodes
    (its memory emptied at each episode's start), agrees on held-out episodes."""
    import gymnasium as gym

    from agents.sb3.recipes import algorithm_class, load_hyperparams, new_model
    from agents.sb3.training_env import make_training_env

    recipe = load_hyperparams("recurrent_ppo", "none")
    env = make_training_env(recipe["env_kwargs"], 1, 0, threads=1)
    try:
        model = new_model(algorithm_class("recurrent_ppo"), recipe, env, seed=0)
    finally:
        env.close()
    proprio_space = model.observation_space["proprio"]
    assert isinstance(proprio_space, gym.spaces.Box)
    episodes = 160
    rng = np.random.default_rng(0)
    side = rng.integers(0, 2, size=episodes)
    proprio = np.zeros((episodes, 2, proprio_space.shape[0]), np.float32)
    proprio[:, 0, 0] = np.where(side == 1, 0.8, -0.8)  # the cue, seen at the first probe only
    actions = np.zeros((episodes, 2, 3), np.int64)
    actions[:, 0] = [14, 0, 4]  # the same first probe everywhere
    actions[:, 1, 0] = np.where(side == 1, 25, 3)  # then the cue's side
    demonstrations = Demonstrations(
        {"proprio": proprio.reshape(-1, proprio_space.shape[0])},
        actions.reshape(-1, 3),
        np.zeros(2 * episodes, np.float32),
        np.repeat(np.arange(episodes, dtype=np.uint64), 2),
        np.zeros(2 * episodes, bool),
        np.zeros(2 * episodes, np.int64),
        np.tile(np.arange(2, dtype=np.int64), episodes),
    )
    assert [s.stop - s.start for s in demonstrations.episode_slices()] == [2] * episodes
    train, held_out = demonstrations.split_by_layout(0.25, seed=0)
    clone(model.policy, train, CloningSettings(epochs=30, batch_size=64, learning_rate=1e-3))
    second = held_out.rows(held_out.episode_steps == 1)
    assert agreement(model.policy, held_out)["lane"] >= 0.95
    # The second probes alone, each as a one-probe episode: no cue, a coin toss at best.
    cut = Demonstrations(
        second.observations,
        second.actions,
        second.returns,
        second.layout_seeds,
        second.episode_success,
        second.episode_tips,
        np.zeros(len(second), np.int64),
    )
    assert agreement(model.policy, cut)["lane"] <= 0.75


def test_every_learned_agent_gets_the_same_clone_stage_and_fine_tuning_budget() -> None:
    """Fair controls: every recipe clones the same teacher with the same settings
    and fine-tunes for the same number of probes with the same reward."""
    from agents.sb3.recipes import load_hyperparams

    recipes = [load_hyperparams("ppo", map_mode) for map_mode in ("gpis", "occupancy", "none")] + [
        load_hyperparams("recurrent_ppo", "none")
    ]
    for key in ("imitation", "n_timesteps", "learning_rate", "ent_coef", "n_envs", "n_steps"):
        assert len({repr(recipe[key]) for recipe in recipes}) == 1, key
    rewards = [{k: v for k, v in recipe["env_kwargs"].items() if k != "map"} for recipe in recipes]
    assert all(reward == rewards[0] for reward in rewards)
