"""RLlib's PPO (new API stack) trains on the environment; runners draw disjoint layouts."""

from __future__ import annotations

import math
from collections.abc import Iterator
from typing import Any

import gymnasium as gym
import numpy as np
import pytest

pytest.importorskip("ray.rllib")
pytest.importorskip("torch")

import torch
from ray.rllib.core.columns import Columns
from ray.rllib.env.env_context import EnvContext
from ray.rllib.env.single_agent_env_runner import SingleAgentEnvRunner

from agents.rllib.env import make_env, register, spread_seeds
from agents.rllib.module import CupboardSearchRLModule
from agents.rllib.training import build_config, train_rllib
from agents.sb3.training_env import TRAIN_LAYOUT_SEEDS
from tactile_search.envs.vector import CupboardSearchVectorEnv

# Every env runner registers its env with gymnasium under one name (RLlib's doing).
pytestmark = pytest.mark.filterwarnings("ignore:.*Overriding environment rllib-single-agent")

# The smallest grid the core takes (W / H = 2, H >= 36) keeps the CNN cheap.
TINY = {"grid_shape": (36, 72), "max_steps": 8}


@pytest.fixture
def local_runners() -> Iterator[list[SingleAgentEnvRunner]]:
    """Two env runners built in this process as RLlib builds its remote ones (worker
    indices 1 and 2, the config's seed), whose envs record every layout seed they draw."""
    register()
    config = build_config(
        map_mode="none", env_runners=2, envs_per_runner=3, fragment=16, seed=5, settings=TINY
    )
    runners = [SingleAgentEnvRunner(config=config, worker_index=w, num_workers=2) for w in (1, 2)]
    for runner in runners:
        env = runner.env.unwrapped
        env.drawn = []
        layout = env._layout

        def recording(index: int, seed: Any, env: Any = env, layout: Any = layout) -> int:
            env.drawn.append(layout(index, seed))
            return env.drawn[-1]

        env._layout = recording
    yield runners
    for runner in runners:
        runner.stop()


def test_runners_draw_disjoint_training_layouts(local_runners: list[SingleAgentEnvRunner]) -> None:
    drawn = []
    for index, runner in enumerate(local_runners, start=1):
        env = runner.env.unwrapped
        assert isinstance(env, CupboardSearchVectorEnv)
        assert env.num_envs == 3
        # 16 steps of each of 3 envs with 8-step episodes: the first reset's 3 layouts and
        # at least 3 more at the autoresets.
        runner.sample(num_timesteps=48, random_actions=True)
        # the runner's reset seed, config.seed + w, spread over its sub-envs
        assert env.np_random_seed == tuple(spread_seeds(5 + index, 3))
        assert len(env.drawn) >= 6
        assert all(TRAIN_LAYOUT_SEEDS[0] <= s < TRAIN_LAYOUT_SEEDS[1] for s in env.drawn)
        assert len(set(env.drawn)) == len(env.drawn)  # no slot replays another's layout
        drawn.append(set(env.drawn))
    assert not drawn[0] & drawn[1]


def test_make_env_takes_settings_and_refuses_the_single_env_path() -> None:
    env = make_env(EnvContext({"map": "none", **TINY}, worker_index=1) | {"num_envs": 2})
    assert isinstance(env.unwrapped, CupboardSearchVectorEnv)
    assert env.num_envs == 2
    assert env.unwrapped.layout_seeds == TRAIN_LAYOUT_SEEDS
    assert env.unwrapped.config.max_steps == 8
    # SYNC/ASYNC: RLlib calls the creator with the bare context (no num_envs).
    with pytest.raises(ValueError, match="VECTOR_ENTRY_POINT"):
        make_env(EnvContext({"map": "none"}, worker_index=1))
    with pytest.raises(ValueError, match="threads"):
        make_env({"num_envs": 1, "threads": 2})
    with pytest.raises(TypeError, match="mapping"):
        make_env([("num_envs", 1)])  # type: ignore[arg-type]


@pytest.mark.parametrize(
    ("setting", "error"), [({"no_such_setting": 1}, TypeError), ({"max_steps": 0}, ValueError)]
)
def test_a_bad_setting_raises_the_envs_own_error(setting: dict, error: type) -> None:
    with pytest.raises(error) as expected:
        CupboardSearchVectorEnv(num_envs=1, **setting)
    with pytest.raises(error) as direct:
        make_env({"num_envs": 1, **setting})
    assert str(direct.value) == str(expected.value)
    # ... and through RLlib: building an env runner builds the env.
    register()
    config = build_config(map_mode="none", env_runners=1, envs_per_runner=1, settings=setting)
    with pytest.raises(error) as via_rllib:
        SingleAgentEnvRunner(config=config, worker_index=1, num_workers=1)
    assert str(via_rllib.value) == str(expected.value)


@pytest.mark.parametrize(("map_mode", "action_mode"), [("gpis", "probe"), ("none", "wrist")])
def test_module_reads_the_observation_as_the_connectors_deliver_it(
    map_mode: str, action_mode: str
) -> None:
    register()
    config = build_config(
        map_mode=map_mode, env_runners=1, envs_per_runner=2, fragment=4,
        settings={**TINY, "action_mode": action_mode},
    )  # fmt: skip
    runner = SingleAgentEnvRunner(config=config, worker_index=1, num_workers=1)
    try:
        assert isinstance(runner.module, CupboardSearchRLModule)
        runner.sample(num_timesteps=8)  # the module acts
        batch = runner._cached_to_module  # the env-to-module output for the next step
        obs = batch[Columns.OBS]
        if map_mode == "none":
            assert set(obs) == {"proprio"}
        else:  # a dict of tensors; the map stays uint8
            assert set(obs) == {"map", "proprio"}
            assert obs["map"].dtype == torch.uint8
            assert tuple(obs["map"].shape) == (2, 2, *TINY["grid_shape"])
        assert obs["proprio"].dtype == torch.float32
        # The learner's (full) module, with the runner's weights.
        spec = config.get_rl_module_spec(spaces=runner.get_spaces(), inference_only=False)
        module = spec.build()
        module.set_state(runner.module.get_state())
        with torch.no_grad():
            out = module.forward_train(batch)
            inputs = out[Columns.ACTION_DIST_INPUTS]
            if action_mode == "wrist":
                assert tuple(inputs.shape) == (2, 6)  # mean and log-std of 3 actions
                assert torch.all(inputs[:, 3:] == -1.0)  # the recipe's initial log-std
            else:  # one categorical per probe index: lanes + depths + sweeps logits
                counts = runner.env.unwrapped.single_action_space.nvec
                assert tuple(inputs.shape) == (2, int(counts.sum()))
                dist = module.get_train_action_dist_cls().from_logits(inputs)
                probes = dist.sample()
                assert tuple(probes.shape) == (2, 3) and (probes < torch.as_tensor(counts)).all()
            acting = runner.module.forward_exploration(batch)[Columns.ACTION_DIST_INPUTS]
            assert torch.equal(inputs, acting)
            values = module.compute_values(batch)
            assert tuple(values.shape) == (2,)
            shared = module.compute_values(batch, embeddings=out[Columns.EMBEDDINGS])
            assert torch.equal(values, shared)
    finally:
        runner.stop()


def test_module_refuses_other_spaces() -> None:
    proprio_only = gym.spaces.Dict({"proprio": gym.spaces.Box(-1, 1, (11,), np.float32)})
    with pytest.raises(TypeError, match="1-D MultiDiscrete"):
        CupboardSearchRLModule(observation_space=proprio_only, action_space=gym.spaces.Discrete(4))
    action = gym.spaces.Box(-1, 1, (3,), np.float32)
    with pytest.raises(TypeError, match="Dict with 'proprio'"):
        CupboardSearchRLModule(
            observation_space=gym.spaces.Box(0, 1, (11,), np.float32), action_space=action
        )
    proprio = gym.spaces.Box(-1, 1, (11,), np.float32)
    with pytest.raises(ValueError, match="at most two 2s"):
        CupboardSearchRLModule(
            observation_space=gym.spaces.Dict({"proprio": proprio}),
            action_space=action,
            model_config={"conv_channels": (8, 8, 8), "conv_strides": (2, 2, 2)},
        )


def test_ppo_trains_with_two_env_runners() -> None:
    runners, envs, fragment = 2, 2, 32
    configured = runners * envs * fragment
    rows = train_rllib(
        iterations=3,
        address="local",  # a fresh local instance, never a cluster that happens to run
        num_cpus=2,
        report=None,
        map_mode="gpis",  # the map goes through the CNN
        env_runners=runners,
        envs_per_runner=envs,
        fragment=fragment,
        seed=0,
        settings={"grid_shape": (36, 72), "max_steps": 24},
        training={"minibatch_size": 64, "num_epochs": 1},
    )
    assert [row["iteration"] for row in rows] == [1, 2, 3]
    lifetime = 0
    for row in rows:
        # A runner stops at the first vector step that fills its quota, and autoreset steps
        # do not count: at most envs - 1 steps over per runner.
        assert configured <= row["env_steps"] <= configured + runners * (envs - 1)
        lifetime += row["env_steps"]
        assert row["env_steps_lifetime"] == lifetime
    assert rows[-1]["episodes_lifetime"] > 0
    assert math.isfinite(rows[-1]["episode_return_mean"])
