"""The map encoders of ``tactile_search.networks.encoders``: the spatial grid they keep, their
features, the no-map mode, PPO training, saving and loading with them, and their argument checks."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from collections.abc import Iterator
from pathlib import Path

import numpy as np
import pytest

import tactile_search

torch = pytest.importorskip("torch")
sb3 = pytest.importorskip("stable_baselines3")

from gymnasium import spaces  # noqa: E402
from stable_baselines3.common.preprocessing import preprocess_obs  # noqa: E402

from tactile_search.networks.encoders import (  # noqa: E402
    ImpalaMapExtractor,
    MapExtractor,
    SpatialSoftmaxMapExtractor,
    map_feature_shape,
)

REPO = Path(__file__).resolve().parents[1]
ENCODERS = (ImpalaMapExtractor, SpatialSoftmaxMapExtractor)


@pytest.fixture(autouse=True)
def one_torch_thread() -> Iterator[None]:
    threads = torch.get_num_threads()
    torch.set_num_threads(1)
    yield
    torch.set_num_threads(threads)


def observation_space(**kwargs: object) -> spaces.Dict:
    return tactile_search.CupboardSearchEnv(**kwargs).observation_space


def real_observations(steps: int = 6, **kwargs: object) -> dict[str, np.ndarray]:
    """A batch of the env's observations along a short random episode (a map with content),
    stacked as SB3 stacks a VecEnv's."""
    env = tactile_search.CupboardSearchEnv(**kwargs)
    obs, _ = env.reset(seed=3)
    env.action_space.seed(3)
    batch = [obs]
    for _ in range(steps - 1):
        obs, *_ = env.step(env.action_space.sample())
        batch.append(obs)
    return {key: np.stack([o[key] for o in batch]) for key in batch[0]}


def features(extractor: MapExtractor, obs: dict[str, np.ndarray]) -> torch.Tensor:
    """``extractor`` on ``obs`` as an SB3 policy feeds it (uint8 maps scaled to [0, 1])."""
    tensors = {key: torch.as_tensor(value) for key, value in obs.items()}
    with torch.no_grad():
        return extractor(preprocess_obs(tensors, extractor._observation_space))


@pytest.mark.parametrize(
    ("cls", "grid_shape", "expected", "extractor_kwargs"),
    [
        (ImpalaMapExtractor, None, (32, 5, 10), {}),  # default grid 40x80
        # space-to-depth 2 then two stages: 40x80 -> 20x40 -> 10x20 -> 5x10, the same grid
        (ImpalaMapExtractor, None, (16, 5, 10), {"space_to_depth": 2, "channels": (16, 16)}),
        # padded to 38x74 -> 19x37 -> 10x19 -> 5x10
        (ImpalaMapExtractor, (37, 74), (16, 5, 10), {"space_to_depth": 2, "channels": (16, 16)}),
        (ImpalaMapExtractor, (36, 72), (32, 5, 9), {}),  # 36 -> 18 -> 9 -> 5, 72 -> 36 -> 18 -> 9
        (SpatialSoftmaxMapExtractor, None, (32, 20, 40), {}),
        (SpatialSoftmaxMapExtractor, (36, 72), (32, 18, 36), {}),
    ],
)
def test_encoder_keeps_the_maps_spatial_grid(
    cls: type[MapExtractor],
    grid_shape: tuple[int, int] | None,
    expected: tuple[int, int, int],
    extractor_kwargs: dict,
) -> None:
    kwargs = {"map": "gpis"} if grid_shape is None else {"map": "gpis", "grid_shape": grid_shape}
    space = observation_space(**kwargs)
    if grid_shape is not None:
        assert space["map"].shape == (2, *grid_shape)
    extractor = cls(space, **extractor_kwargs)
    assert map_feature_shape(extractor) == expected
    out = features(extractor, real_observations(**kwargs))
    assert out.shape == (6, extractor.features_dim)
    assert torch.isfinite(out).all()


def test_features_dim_is_map_features_plus_proprio() -> None:
    space = observation_space(map="gpis")
    proprio = space["proprio"].shape[0]
    assert ImpalaMapExtractor(space).features_dim == 256 + proprio
    assert ImpalaMapExtractor(space, map_features=64, proprio_features=32).features_dim == 96
    assert SpatialSoftmaxMapExtractor(space).features_dim == 3 * 32 + proprio
    smaller = SpatialSoftmaxMapExtractor(space, channels=(8, 8), strides=(2, 2))
    assert smaller.features_dim == 3 * 8 + proprio
    assert map_feature_shape(smaller) == (8, 10, 20)


@pytest.mark.parametrize("cls", ENCODERS)
def test_without_a_map_the_features_are_the_proprio(cls: type[MapExtractor]) -> None:
    space = observation_space(map="none")
    assert "map" not in space.spaces
    extractor = cls(space)
    assert map_feature_shape(extractor) is None
    assert extractor.features_dim == space["proprio"].shape[0]
    obs = real_observations(map="none")
    np.testing.assert_array_equal(features(extractor, obs).numpy(), obs["proprio"])
    through_linear = cls(space, proprio_features=16)
    assert through_linear.features_dim == 16
    assert features(through_linear, obs).shape == (6, 16)


@pytest.mark.parametrize("cls", ENCODERS)
def test_a_moved_map_pixel_changes_the_map_features_only(cls: type[MapExtractor]) -> None:
    torch.manual_seed(0)
    space = observation_space(map="gpis")
    extractor = cls(space)
    obs = {key: np.zeros((1, *s.shape), s.dtype) for key, s in space.spaces.items()}
    moved = {key: value.copy() for key, value in obs.items()}
    obs["map"][0, 0, 8, 12] = 255
    moved["map"][0, 0, 30, 60] = 255
    before, after = features(extractor, obs)[0], features(extractor, moved)[0]
    map_dim = extractor.features_dim - space["proprio"].shape[0]
    assert not torch.allclose(before[:map_dim], after[:map_dim])
    torch.testing.assert_close(before[map_dim:], after[map_dim:])


def test_space_to_depth_rearranges_every_cell_and_loses_none() -> None:
    from tactile_search.networks.encoders import SpaceToDepth

    x = torch.arange(2 * 5 * 7, dtype=torch.float32).reshape(1, 2, 5, 7) + 1.0
    out = SpaceToDepth(2, 2)(x)
    torch.testing.assert_close(
        out, torch.nn.PixelUnshuffle(2)(torch.nn.functional.pad(x, (0, 1, 0, 1))), rtol=0, atol=0
    )
    channels_last = SpaceToDepth(2, 2)(x.contiguous(memory_format=torch.channels_last))
    assert torch.equal(channels_last, out)
    assert out.shape == (1, 8, 3, 4)
    # every cell once, the padding zeros added: a permutation of the padded map
    padded = torch.nn.functional.pad(x, (0, 1, 0, 1))
    assert torch.equal(torch.sort(out.flatten()).values, torch.sort(padded.flatten()).values)
    # channel c * 4 + 2 * dy + dx of cell (i, j) is the map's cell (2 i + dy, 2 j + dx)
    assert out[0, 1 * 4 + 2 * 1 + 0, 2, 3] == padded[0, 1, 5, 6]
    assert out[0, 0 * 4 + 2 * 0 + 1, 1, 2] == x[0, 0, 2, 5]
    assert torch.equal(torch.nn.PixelShuffle(2)(out), padded)


def test_space_to_depth_sees_a_single_moved_cell() -> None:
    torch.manual_seed(0)
    space = observation_space(map="gpis")
    extractor = ImpalaMapExtractor(space, space_to_depth=2, channels=(16, 16), res_blocks=1)
    obs = {key: np.zeros((1, *s.shape), s.dtype) for key, s in space.spaces.items()}
    moved = {key: value.copy() for key, value in obs.items()}
    obs["map"][0, 1, 10, 20] = 255
    moved["map"][0, 1, 10, 21] = 255  # the same 2x2 block, another cell of it
    map_dim = extractor.features_dim - space["proprio"].shape[0]
    before, after = features(extractor, obs)[0], features(extractor, moved)[0]
    assert not torch.allclose(before[:map_dim], after[:map_dim])


@pytest.mark.parametrize("cls", ENCODERS)
def test_channels_last_computes_the_same_features(cls: type[MapExtractor]) -> None:
    space = observation_space(map="gpis")
    fast, plain = cls(space), cls(space, channels_last=False)
    plain.load_state_dict(fast.state_dict())
    obs = real_observations()
    torch.testing.assert_close(features(fast, obs), features(plain, obs), rtol=1e-4, atol=1e-5)


def test_ppo_trains_saves_and_loads_with_the_impala_encoder(tmp_path: Path) -> None:
    from stable_baselines3 import PPO

    from tactile_search.envs.sb3_vec_env import CupboardSearchSb3VecEnv

    env = CupboardSearchSb3VecEnv(num_envs=2, map="gpis", threads=1, seed=0)
    model = PPO(
        "MultiInputPolicy",
        env,
        n_steps=64,
        batch_size=64,
        n_epochs=2,
        seed=0,
        device="cpu",
        policy_kwargs={
            "features_extractor_class": ImpalaMapExtractor,
            "features_extractor_kwargs": {"channels": (8, 16, 16), "map_features": 64},
            "log_std_init": -1.0,
        },
    )
    extractor = model.policy.features_extractor
    assert isinstance(extractor, ImpalaMapExtractor)
    assert map_feature_shape(extractor) == (16, 5, 10)
    first_conv = extractor.map_net[0][0].weight.detach().clone()
    model.learn(total_timesteps=256)
    assert model.num_timesteps == 256
    assert not torch.equal(first_conv, extractor.map_net[0][0].weight)  # the encoder learned

    path = tmp_path / "model.zip"
    model.save(path)
    obs = real_observations(steps=4)
    action, _ = model.predict(obs, deterministic=True)
    loaded = PPO.load(path, device="cpu")
    assert isinstance(loaded.policy.features_extractor, ImpalaMapExtractor)
    np.testing.assert_allclose(loaded.predict(obs, deterministic=True)[0], action, atol=1e-6)

    # A fresh interpreter with only the repository on the path: the pickled class reference
    # `tactile_search.networks.encoders.ImpalaMapExtractor` resolves there too.
    np.savez(tmp_path / "obs.npz", **obs)
    script = (
        "import json, sys, numpy as np\n"
        "from stable_baselines3 import PPO\n"
        "obs = dict(np.load(sys.argv[2]))\n"
        "model = PPO.load(sys.argv[1], device='cpu')\n"
        "print(json.dumps(model.predict(obs, deterministic=True)[0].tolist()))\n"
    )
    done = subprocess.run(
        [sys.executable, "-c", script, str(path), str(tmp_path / "obs.npz")],
        capture_output=True,
        text=True,
        cwd=tmp_path,
        env={**os.environ, "PYTHONPATH": str(REPO), "OMP_NUM_THREADS": "1"},
        timeout=120,
        check=False,
    )
    assert done.returncode == 0, done.stderr
    fresh = np.array(json.loads(done.stdout.strip().splitlines()[-1]), dtype=np.float32)
    np.testing.assert_allclose(fresh, action, atol=1e-5)


def test_every_map_mode_builds_the_same_policy_class() -> None:
    from stable_baselines3.common.policies import MultiInputActorCriticPolicy

    for map_mode in ("gpis", "occupancy", "none"):
        space = observation_space(map=map_mode)
        policy = MultiInputActorCriticPolicy(
            space,
            spaces.Box(-1.0, 1.0, (3,), np.float32),
            lambda _: 3e-4,
            features_extractor_class=SpatialSoftmaxMapExtractor,
        )
        assert isinstance(policy.features_extractor, SpatialSoftmaxMapExtractor)
        obs = real_observations(steps=2, map=map_mode)
        assert policy.predict(obs, deterministic=True)[0].shape == (2, 3)


def test_the_encoders_are_importable_from_the_installed_package() -> None:
    import tactile_search.networks.encoders as encoders

    assert ImpalaMapExtractor.__module__ == "tactile_search.networks.encoders"
    assert encoders.SpatialSoftmaxMapExtractor is SpatialSoftmaxMapExtractor


@pytest.mark.parametrize("old_module", ["agents.encoders", "agents.sb3.encoders"])
def test_a_recipe_naming_the_encoders_old_module_resolves_to_its_new_place(
    old_module: str,
) -> None:
    from agents.sb3.recipes import algorithm_kwargs
    from tactile_search.networks.recipe_classes import load_objects

    recipe = {"policy_kwargs": {"features_extractor_class": f"{old_module}.ImpalaMapExtractor"}}
    assert algorithm_kwargs(recipe)["policy_kwargs"]["features_extractor_class"] is (
        ImpalaMapExtractor
    )
    assert load_objects(recipe)["policy_kwargs"]["features_extractor_class"] is (ImpalaMapExtractor)
    assert load_objects({"n_epochs": 10}) == {}


@pytest.mark.parametrize(
    ("cls", "kwargs", "error", "match"),
    [
        (ImpalaMapExtractor, {"channels": ()}, ValueError, "channels"),
        (ImpalaMapExtractor, {"channels": (16, 0)}, ValueError, r"channels\[1\]"),
        (ImpalaMapExtractor, {"channels": (16.0, 32)}, TypeError, r"channels\[0\]"),
        (ImpalaMapExtractor, {"channels": 16}, TypeError, "channels"),
        (ImpalaMapExtractor, {"map_features": 0}, ValueError, "map_features"),
        (ImpalaMapExtractor, {"res_blocks": -1}, ValueError, "res_blocks"),
        (ImpalaMapExtractor, {"proprio_features": -2}, ValueError, "proprio_features"),
        (ImpalaMapExtractor, {"channels_last": "yes"}, TypeError, "channels_last"),
        (ImpalaMapExtractor, {"space_to_depth": 0}, ValueError, "space_to_depth"),
        (ImpalaMapExtractor, {"space_to_depth": 2.0}, TypeError, "space_to_depth"),
        (SpatialSoftmaxMapExtractor, {"strides": (1, 2)}, ValueError, "strides"),
        (SpatialSoftmaxMapExtractor, {"strides": (1, 0, 1)}, ValueError, r"strides\[1\]"),
        (SpatialSoftmaxMapExtractor, {"learn_temperature": 1}, TypeError, "learn_temperature"),
    ],
)
def test_bad_arguments_are_rejected(
    cls: type[MapExtractor], kwargs: dict, error: type[Exception], match: str
) -> None:
    with pytest.raises(error, match=match):
        cls(observation_space(map="gpis"), **kwargs)


def test_bad_observation_spaces_are_rejected() -> None:
    proprio = spaces.Box(-1.0, 1.0, (11,), np.float32)
    with pytest.raises(TypeError, match="Dict observation space"):
        ImpalaMapExtractor(proprio)
    flat_map = spaces.Dict({"map": spaces.Box(0, 255, (40, 80), np.uint8), "proprio": proprio})
    with pytest.raises(ValueError, match=r"Box of shape \(C, H, W\)"):
        ImpalaMapExtractor(flat_map)
    with pytest.raises(ValueError, match="no keys"):
        SpatialSoftmaxMapExtractor(spaces.Dict({}))
    with pytest.raises(TypeError, match="MapExtractor"):
        map_feature_shape(torch.nn.Linear(2, 2))


def test_a_recipe_names_its_encoder_by_dotted_path(tmp_path: Path) -> None:
    from agents.sb3.learned import LearnedAgent
    from agents.sb3.recipes import algorithm_kwargs
    from tests.recipes import train_with_recipe

    policy_kwargs = {
        "log_std_init": -1.0,
        "features_extractor_class": "tactile_search.networks.encoders.ImpalaMapExtractor",
        "features_extractor_kwargs": {"channels": [8, 16, 16], "map_features": 64},
    }
    run_dir = train_with_recipe(
        tmp_path, "gpis", policy="MultiInputPolicy", policy_kwargs=policy_kwargs
    )
    agent = LearnedAgent(run_dir)
    assert isinstance(agent.model.policy.features_extractor, ImpalaMapExtractor)
    with pytest.raises(ValueError, match="features_extractor_class"):
        algorithm_kwargs({"policy_kwargs": {"features_extractor_class": "agents.nope.Nope"}})
