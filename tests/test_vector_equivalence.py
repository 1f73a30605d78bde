"""The vector env is gymnasium's ``SyncVectorEnv`` of the single env, bit for bit.

The idea of gymnasium's own vector tests, applied to ours: the same seeds and actions
through ``gym.make_vec(..., vectorization_mode="vector_entry_point")`` and through a
``SyncVectorEnv`` of ``gym.make`` envs give equal observations, rewards, flags and infos
(with their ``_key`` masks), over resets, steps and autoresets, in every autoreset mode, map
mode and action mode; ``reset_mask``, render, pickling and the errors gymnasium expects.
"""

from __future__ import annotations

import pickle
from typing import Any

import gymnasium as gym
import numpy as np
import pytest
from gymnasium.error import ResetNeeded
from gymnasium.vector import AutoresetMode, SyncVectorEnv

import tactile_search  # registers the environments
from tactile_search import CupboardSearchVectorEnv
from tactile_search.envs.config import MAP_MODES

ENV_ID = "tactile_search/CupboardSearch-v0"
NUM_ENVS = 3
#: Short episodes, so that every run crosses several autoresets.
SHORT = {"max_steps": 6}


def pair(
    autoreset_mode: AutoresetMode = AutoresetMode.NEXT_STEP, env_id: str = ENV_ID, **settings: Any
) -> tuple[gym.vector.VectorEnv, gym.vector.VectorEnv]:
    """Ours (through ``make_vec``) and the ``SyncVectorEnv`` of the single env."""
    settings = {**SHORT, **settings}
    ours = gym.make_vec(
        env_id, num_envs=NUM_ENVS, vectorization_mode="vector_entry_point",
        autoreset_mode=autoreset_mode, **settings,
    )  # fmt: skip
    sync = SyncVectorEnv(
        [lambda: gym.make(env_id, **settings) for _ in range(NUM_ENVS)],
        autoreset_mode=autoreset_mode,
    )
    return ours, sync


def assert_identical(ours: Any, theirs: Any, where: str) -> None:
    """Equal structure, values and dtypes (NaN-free: our arrays never hold NaN)."""
    if isinstance(theirs, dict):
        assert sorted(ours) == sorted(theirs), f"{where}: keys"
        for key in theirs:
            assert_identical(ours[key], theirs[key], f"{where}[{key!r}]")
    elif isinstance(theirs, tuple | list):
        assert len(ours) == len(theirs), f"{where}: length"
        for index, (a, b) in enumerate(zip(ours, theirs, strict=True)):
            assert_identical(a, b, f"{where}[{index}]")
    elif isinstance(theirs, np.ndarray) and theirs.dtype == object:
        assert ours.shape == theirs.shape, f"{where}: shape"
        for index, (a, b) in enumerate(zip(ours, theirs, strict=True)):
            assert_identical(a, b, f"{where}[{index}]")
    else:
        a, b = np.asarray(ours), np.asarray(theirs)
        assert a.dtype == b.dtype, f"{where}: dtype {a.dtype} != {b.dtype}"
        np.testing.assert_array_equal(a, b, err_msg=where)


def run_both(ours: gym.vector.VectorEnv, sync: gym.vector.VectorEnv, steps: int, seed: int) -> int:
    """Steps both with the same random actions; returns how many episodes ended."""
    actions = sync.action_space
    actions.seed(seed)
    ended = 0
    for step in range(steps):
        action = actions.sample()
        out_ours, out_sync = ours.step(action), sync.step(action)
        assert_identical(out_ours, out_sync, f"step {step}")
        ended += int(np.sum(out_sync[2] | out_sync[3]))
    return ended


@pytest.mark.parametrize("mode", list(MAP_MODES))
@pytest.mark.parametrize("action_mode", ["wrist", "probe"])
def test_next_step_autoreset_equals_sync_vector_env(mode: str, action_mode: str) -> None:
    ours, sync = pair(map=mode, action_mode=action_mode)
    assert_identical(ours.reset(seed=7), sync.reset(seed=7), "reset")
    assert run_both(ours, sync, steps=20, seed=1) >= NUM_ENVS  # autoresets were crossed
    ours.close()
    sync.close()


@pytest.mark.parametrize("env_id", [i for i in tactile_search.ENV_IDS if i != ENV_ID])
@pytest.mark.parametrize("action_mode", ["wrist", "probe"])
def test_every_registered_id_equals_sync_vector_env_and_pickles(
    env_id: str, action_mode: str
) -> None:
    ours, sync = pair(env_id=env_id, action_mode=action_mode)
    assert ours.unwrapped.config == sync.envs[0].unwrapped.config
    assert_identical(ours.reset(seed=5), sync.reset(seed=5), "reset")
    assert run_both(ours, sync, steps=12, seed=3) >= NUM_ENVS
    copy = pickle.loads(pickle.dumps(ours.unwrapped))
    run_both(copy, sync, steps=8, seed=4)
    ours.close()
    sync.close()


@pytest.mark.parametrize("action_mode", ["wrist", "probe"])
def test_same_step_autoreset_equals_sync_vector_env(action_mode: str) -> None:
    ours, sync = pair(AutoresetMode.SAME_STEP, action_mode=action_mode)
    assert_identical(ours.reset(seed=11), sync.reset(seed=11), "reset")
    assert run_both(ours, sync, steps=20, seed=2) >= NUM_ENVS
    ours.close()
    sync.close()


def test_disabled_autoreset_with_reset_mask_equals_sync_vector_env() -> None:
    ours, sync = pair(AutoresetMode.DISABLED)
    assert_identical(ours.reset(seed=3), sync.reset(seed=3), "reset")
    actions = sync.action_space
    actions.seed(3)
    resets = 0
    for step in range(25):
        action = actions.sample()
        out_ours, out_sync = ours.step(action), sync.step(action)
        assert_identical(out_ours, out_sync, f"step {step}")
        ended = out_sync[2] | out_sync[3]
        if ended.any():
            options = {"reset_mask": ended}
            assert_identical(
                ours.reset(options=options), sync.reset(options=options), f"reset {step}"
            )
            resets += 1
    assert resets >= 2


def test_reset_mask_resets_only_the_masked_sub_envs_as_sync_vector_env_does() -> None:
    ours, sync = pair()
    assert_identical(ours.reset(seed=[5, 6, 9]), sync.reset(seed=[5, 6, 9]), "reset")
    run_both(ours, sync, steps=3, seed=4)
    # ``None`` in the list: that sub-env draws its layout from its own generator.
    assert_identical(ours.reset(seed=[None, 8, None]), sync.reset(seed=[None, 8, None]), "list")
    run_both(ours, sync, steps=3, seed=6)
    mask = np.array([False, True, False])
    out_ours = ours.reset(seed=[None, 20, None], options={"reset_mask": mask})
    out_sync = sync.reset(seed=[None, 20, None], options={"reset_mask": mask})
    assert_identical(out_ours, out_sync, "masked reset")
    assert not out_ours[1]["_steps"][0] and out_ours[1]["_steps"][1]
    run_both(ours, sync, steps=15, seed=5)


def test_unseeded_sub_envs_draw_their_own_layouts() -> None:
    vector = CupboardSearchVectorEnv(num_envs=NUM_ENVS, map="none")
    vector.reset()
    seeds = vector.np_random_seed
    assert len(set(seeds)) == NUM_ENVS and all(seed >= 0 for seed in seeds)


def test_info_carries_a_mask_beside_every_key() -> None:
    ours, _ = pair()
    _, info = ours.reset(seed=0)
    keys = [key for key in info if not key.startswith("_")]
    assert keys and all(info[f"_{key}"].tolist() == [True] * NUM_ENVS for key in keys)
    _, _, _, _, info = ours.step(ours.action_space.sample())
    assert info["_success"].dtype == np.bool_ and info["_success"].all()


@pytest.mark.parametrize("action_mode", ["wrist", "probe"])
@pytest.mark.parametrize("steps_before", [0, 2, 5, 8])
def test_pickled_vector_env_continues_as_the_original(action_mode: str, steps_before: int) -> None:
    ours, _ = pair(action_mode=action_mode)
    ours.reset(seed=[1, 2, 3])
    actions = ours.action_space
    actions.seed(steps_before)
    for _ in range(steps_before):
        ours.step(actions.sample())
    # Episodes of different lengths: sub-env 1 begins again, and some autoreset on the way.
    ours.reset(seed=[None, 40, None], options={"reset_mask": np.array([False, True, False])})
    for _ in range(3):
        ours.step(actions.sample())
    copy = pickle.loads(pickle.dumps(ours.unwrapped))
    assert copy.np_random_seed == ours.unwrapped.np_random_seed
    run_both(copy, ours, steps=12, seed=9)


def test_render_returns_each_sub_envs_frame() -> None:
    vector = gym.make_vec(
        ENV_ID, num_envs=2, vectorization_mode="vector_entry_point", render_mode="rgb_array"
    )
    vector.reset(seed=0)
    frames = vector.render()
    assert isinstance(frames, tuple) and len(frames) == 2
    single = gym.make(ENV_ID, render_mode="rgb_array")
    single.reset(seed=1)
    np.testing.assert_array_equal(frames[1], single.render())
    assert CupboardSearchVectorEnv(num_envs=2, render_mode=None).render() is None


def test_autoreset_mode_is_an_attribute_and_metadata() -> None:
    for given in (AutoresetMode.SAME_STEP, "same_step", "SameStep"):
        vector = CupboardSearchVectorEnv(num_envs=2, autoreset_mode=given)
        assert vector.autoreset_mode is AutoresetMode.SAME_STEP
        assert vector.metadata["autoreset_mode"] is AutoresetMode.SAME_STEP
    assert CupboardSearchVectorEnv.metadata["autoreset_mode"] is AutoresetMode.NEXT_STEP
    with pytest.raises(ValueError, match="autoreset_mode of CupboardSearchVectorEnv"):
        CupboardSearchVectorEnv(num_envs=2, autoreset_mode="sometimes")


@pytest.mark.parametrize("actions", [0.5, "left", {"dx": 0}])
def test_an_action_of_the_wrong_type_is_a_type_error(actions: Any) -> None:
    vector = CupboardSearchVectorEnv(num_envs=2)
    vector.reset(seed=0)
    with pytest.raises(TypeError, match="actions must be an array of shape"):
        vector.step(actions)


def test_stepping_before_reset_or_an_ended_disabled_episode_needs_a_reset() -> None:
    vector = CupboardSearchVectorEnv(num_envs=2, autoreset_mode="disabled", max_steps=2)
    with pytest.raises(ResetNeeded, match="never reset"):
        vector.step(np.zeros((2, 3)))
    vector.reset(seed=0)
    vector.step(np.zeros((2, 3)))
    vector.step(np.zeros((2, 3)))  # both truncate
    with pytest.raises(ResetNeeded, match="DISABLED"):
        vector.step(np.zeros((2, 3)))
    vector.reset(options={"reset_mask": np.array([True, True])})
    vector.step(np.zeros((2, 3)))


@pytest.mark.parametrize(
    ("seed", "error"),
    [("7", TypeError), ([1, 2], ValueError), ([1, 2.5, 3], TypeError), (True, TypeError)],
)
def test_bad_reset_seeds_are_refused(seed: Any, error: type) -> None:
    vector = CupboardSearchVectorEnv(num_envs=NUM_ENVS)
    with pytest.raises(error, match="seed"):
        vector.reset(seed=seed)


@pytest.mark.parametrize(
    ("mask", "error"),
    [
        ([True, False, True], TypeError),
        (np.array([1, 0, 1]), TypeError),
        (np.array([True, False]), ValueError),
        (np.zeros(NUM_ENVS, dtype=bool), ValueError),
    ],
)
def test_bad_reset_masks_are_refused(mask: Any, error: type) -> None:
    vector = CupboardSearchVectorEnv(num_envs=NUM_ENVS)
    with pytest.raises(error, match="reset_mask"):
        vector.reset(options={"reset_mask": mask})


def test_gymnasiums_vector_record_video_and_episode_statistics_run_on_it(tmp_path: Any) -> None:
    pytest.importorskip("moviepy")  # RecordVideo writes with it (the dev extra has it)
    from gymnasium.wrappers.vector import RecordEpisodeStatistics, RecordVideo

    vector = gym.make_vec(
        ENV_ID, num_envs=2, vectorization_mode="vector_entry_point", render_mode="rgb_array",
        map="none", max_steps=4,
    )  # fmt: skip
    vector = RecordEpisodeStatistics(RecordVideo(vector, str(tmp_path), video_length=6))
    vector.reset(seed=0)
    ended = []
    for _ in range(6):
        *_, info = vector.step(np.zeros((2, 3)))
        if "episode" in info:
            ended.append(info["_episode"].copy())
    vector.close()
    assert list(tmp_path.glob("*.mp4"))
    assert ended and ended[0].all()  # both episodes ended together at max_steps
