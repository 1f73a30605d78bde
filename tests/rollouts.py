"""Short seeded rollouts of every env face, reduced to arrays, for the pinned-rollout test.

``python tests/rollouts.py --out tests/data/rollouts.npz`` records them (and, with
``--registered-out tests/data/rollouts_registered.npz``, those of every other registered
id: each task and tier, through ``gymnasium.make``, in both action modes).
``tests/test_rollouts_pinned.py`` checks that the step path keeps giving the same
observations, rewards and infos bit for bit, so a change meant to keep what a seed gives
(a faster path, a refactor) is checked against the file. Re-record it only for a change
that alters what a seed gives on purpose (physics settings, the prior's size, seeding),
after checking that the faces it should not touch give the arrays they gave; the commit
that re-records it says why. Runs against the old and the new API alike.
"""

from __future__ import annotations

import argparse
import hashlib
import inspect
from typing import Any

import numpy as np

# The info keys of the base commit (the pinned file holds exactly these).
INFO_KEYS = (
    "reward_success",
    "reward_step",
    "reward_displacement",
    "reward_tip",
    "reward_approach",
    "target_distance",
    "success",
    "tipped",
    "steps",
    "jar_displacement",
    "max_jar_displacement",
    "max_tilt",
    "tips",
    "contacts",
    "rows_added",
    "contacts_skipped",
    "contacts_dropped",
    "gpis_rows",
    "iou",
    "clipped",
    "blocked",
)
# The map modes of the base commit (the pinned file holds exactly these).
MODES = ("gpis", "occupancy", "none")
MAX_STEPS = 15
STEPS = 40


def digest(array: Any) -> str:
    """sha256 of an array's dtype, shape and bytes."""
    array = np.ascontiguousarray(array)
    h = hashlib.sha256(f"{array.dtype.str}{array.shape}".encode())
    h.update(array.tobytes())
    return h.hexdigest()


def vector_kwargs(cls: type) -> dict[str, Any]:
    """The time limit as the class takes it (the base commit had ``max_episode_steps``)."""
    params = inspect.signature(cls.__init__).parameters
    return {"max_episode_steps": MAX_STEPS} if "max_episode_steps" in params else {}


def single(mode: str) -> dict[str, np.ndarray]:
    """One env, random actions (some outside [-1, 1]), reset on termination or MAX_STEPS."""
    from tactile_search import CupboardSearchEnv

    env = CupboardSearchEnv(map=mode, max_steps=MAX_STEPS)
    rng = np.random.default_rng(7)
    seed = 11
    obs, info = env.reset(seed=seed)
    maps, proprio, rewards, terminated, infos = [], [], [], [], []

    def record(obs: dict, info: dict) -> None:
        maps.append(digest(obs["map"]) if "map" in obs else "")
        proprio.append(np.asarray(obs["proprio"]))
        infos.append([float(info[k]) for k in INFO_KEYS])

    record(obs, info)
    for _ in range(STEPS):
        obs, reward, done, _, info = env.step(rng.uniform(-1.2, 1.2, 3))
        record(obs, info)
        rewards.append(reward)
        terminated.append(done)
        if done or info["steps"] >= MAX_STEPS:
            seed += 1
            obs, info = env.reset(seed=seed)
            record(obs, info)
    return {
        "maps": np.array(maps),
        "proprio": np.array(proprio),
        "rewards": np.array(rewards),
        "terminated": np.array(terminated),
        "infos": np.array(infos),
    }


def vector(mode: str) -> dict[str, np.ndarray]:
    """The gymnasium vector env of 3, autoreset, MAX_STEPS time limit."""
    from tactile_search import CupboardSearchVectorEnv

    cls = CupboardSearchVectorEnv
    env = cls(num_envs=3, map=mode, max_steps=MAX_STEPS, **vector_kwargs(cls))
    rng = np.random.default_rng(5)
    obs, info = env.reset(seed=[3, 4, 5])
    maps, proprio, flags, rewards, infos = [], [], [], [], []

    def record(obs: dict, info: dict) -> None:
        maps.append(digest(obs["map"]) if "map" in obs else "")
        proprio.append(np.asarray(obs["proprio"]))
        infos.append(np.array([np.asarray(info[k], dtype=float) for k in INFO_KEYS]))

    record(obs, info)
    for _ in range(STEPS):
        obs, reward, terminated, truncated, info = env.step(rng.uniform(-1, 1, (3, 3)))
        record(obs, info)
        rewards.append(np.asarray(reward))
        flags.append(np.stack([terminated, truncated]))
    return {
        "maps": np.array(maps),
        "proprio": np.array(proprio),
        "rewards": np.array(rewards),
        "flags": np.array(flags),
        "infos": np.array(infos),
    }


def sb3(mode: str) -> dict[str, np.ndarray]:
    """The stable-baselines3 vec env of 3: same-step reset, terminal observations."""
    from tactile_search.envs.sb3_vec_env import CupboardSearchSb3VecEnv

    cls = CupboardSearchSb3VecEnv
    env = cls(num_envs=3, seed=2, map=mode, max_steps=MAX_STEPS, **vector_kwargs(cls))
    rng = np.random.default_rng(9)
    obs = env.reset()
    maps, proprio, rewards, dones, infos, terminal = [digest(obs.get("map", 0))], [], [], [], [], []
    proprio.append(obs["proprio"].copy())
    for _ in range(STEPS):
        env.step_async(rng.uniform(-1, 1, (3, 3)).astype(np.float32))
        obs, reward, done, info = env.step_wait()
        maps.append(digest(obs.get("map", 0)))
        proprio.append(obs["proprio"].copy())
        rewards.append(reward)
        dones.append(done)
        infos.append([[float(i[k]) for k in INFO_KEYS] for i in info])
        for index in np.flatnonzero(done):
            t = info[index]["terminal_observation"]
            flags = (info[index]["TimeLimit.truncated"], info[index]["is_success"])
            terminal.append(
                f"{len(dones)}:{index}:{flags}:{digest(t.get('map', 0))}:{digest(t['proprio'])}"
            )
    return {
        "maps": np.array(maps),
        "proprio": np.array(proprio),
        "rewards": np.array(rewards),
        "dones": np.array(dones),
        "infos": np.array(infos),
        "terminal": np.array(terminal),
    }


def registered(env_id: str, action_mode: str) -> dict[str, np.ndarray]:
    """One env of a registered id other than v0 (a task or tier), through ``gymnasium.make``:
    random actions of its action space (claims included), reset when an episode ends. Every
    info key of today is recorded, each as its own array (``info/<key>``), so that an info
    key added later leaves the pinned ones as they were."""
    import gymnasium as gym

    import tactile_search  # noqa: F401  (registers the ids)

    env = gym.make(env_id, action_mode=action_mode, max_steps=MAX_STEPS)
    env.action_space.seed(3)
    seed = 21
    obs, info = env.reset(seed=seed)
    keys = sorted(info)
    maps, proprio, rewards, flags = [], [], [], []
    infos: dict[str, list[float]] = {key: [] for key in keys}

    def record(obs: dict, info: dict) -> None:
        maps.append(digest(obs["map"]))
        proprio.append(np.asarray(obs["proprio"]))
        for key in keys:
            infos[key].append(float(info[key]))

    record(obs, info)
    for _ in range(STEPS // 2):
        obs, reward, terminated, truncated, info = env.step(env.action_space.sample())
        record(obs, info)
        rewards.append(reward)
        flags.append((terminated, truncated))
        if terminated or truncated:
            seed += 1
            obs, info = env.reset(seed=seed)
            record(obs, info)
    return {
        "maps": np.array(maps),
        "proprio": np.array(proprio),
        "rewards": np.array(rewards),
        "flags": np.array(flags),
        **{f"info/{key}": np.array(values) for key, values in infos.items()},
    }


def record_registered() -> dict[str, np.ndarray]:
    """Every registered id but v0, in both action modes, keyed ``id/action_mode/field``."""
    import tactile_search

    out: dict[str, np.ndarray] = {}
    for env_id in tactile_search.ENV_IDS:
        if env_id == tactile_search.ENV_ID:
            continue
        for action_mode in ("wrist", "probe"):
            for field, value in registered(env_id, action_mode).items():
                out[f"{env_id}/{action_mode}/{field}"] = value
    return out


def record_all() -> dict[str, np.ndarray]:
    """Every rollout, keyed ``face/mode/field``."""
    out: dict[str, np.ndarray] = {}
    for face, run in (("single", single), ("vector", vector), ("sb3", sb3)):
        for mode in MODES:
            for field, value in run(mode).items():
                out[f"{face}/{mode}/{field}"] = value
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", required=True, help="v0's faces (tests/data/rollouts.npz)")
    parser.add_argument(
        "--registered-out", default=None,
        help="the other registered ids (tests/data/rollouts_registered.npz)",
    )  # fmt: skip
    args = parser.parse_args()
    np.savez_compressed(args.out, **record_all())
    if args.registered_out:
        np.savez_compressed(args.registered_out, **record_registered())


if __name__ == "__main__":
    main()
