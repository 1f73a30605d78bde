"""Threads: an env, a scene or a map serves one thread at a time. A call that meets another
thread's call still running raises a RuntimeError saying so (not pyo3's bare "Already
borrowed"), leaves the object usable, and objects of their own run side by side in threads
with the same results as one after another. A vector env's own threads (the calling thread
and its helpers, taking the episodes' tasks from one queue, resets first) give the same
results however many there are."""

from __future__ import annotations

import multiprocessing
import pickle
import queue
import threading
from collections.abc import Callable
from typing import Any

import numpy as np
import pytest

from tactile_search import CupboardSearchEnv, CupboardSearchVectorEnv, Gpis
from tactile_search._core import Scene

IN_USE = "in use by another thread"


def collide(call: Callable[[], object], attempts: int = 400) -> list[str]:
    """Runs ``call`` in a background thread ``attempts`` times while this thread calls it
    too, until a call fails; returns the messages of the RuntimeErrors raised on both sides.

    The background calls release the GIL while they compute and hold the object meanwhile,
    so this thread's call, which gets the GIL exactly then, finds it in use."""
    messages: list[str] = []
    stop = threading.Event()

    def background() -> None:
        for _ in range(attempts):
            if stop.is_set():
                return
            try:
                call()
            except RuntimeError as error:
                messages.append(str(error))

    thread = threading.Thread(target=background)
    thread.start()
    try:
        for _ in range(attempts):
            try:
                call()
            except RuntimeError as error:
                messages.append(str(error))
                break
    finally:
        stop.set()
        thread.join()
    return messages


def test_two_threads_stepping_one_env_get_a_clear_error_and_the_env_survives() -> None:
    env = CupboardSearchEnv(max_steps=10_000)
    env.reset(seed=1)
    messages = collide(lambda: env.step(np.zeros(3)))
    assert messages, "no call ever met another thread's call"
    assert all(IN_USE in m and "give each thread its own" in m for m in messages), messages
    obs, *_ = env.step(np.zeros(3))  # still usable
    assert np.isfinite(obs["proprio"]).all()


def test_two_threads_adding_to_one_map_get_a_clear_error() -> None:
    gpis = Gpis(((-1.0, 1.0), (-1.0, 1.0)), (60, 60), max_rows=10**6)
    points = np.random.default_rng(0).uniform(-0.9, 0.9, (3, 2))

    def add_and_clear() -> None:
        gpis.add_values(points, noise_std=0.01)
        if gpis.n_rows > 300:
            gpis.clear()

    messages = collide(add_and_clear)
    assert messages and all(IN_USE in m and "Gpis" in m for m in messages), messages
    assert np.isfinite(gpis.mean).all()


def test_two_threads_stepping_one_scene_get_a_clear_error() -> None:
    scene = Scene(3)
    # A scene step is short (tens of microseconds), so two threads' calls meet less often
    # than an env's; on a loaded machine 400 attempts once saw none. collide stops at the
    # first meeting, so the larger bound costs nothing when they meet early.
    messages = collide(lambda: scene.step(0.0, 0.0, 0.0), attempts=20_000)
    assert messages and all(IN_USE in m and "Scene" in m for m in messages), messages
    assert scene.steps > 0


@pytest.mark.parametrize("mode", ["gpis", "none"])
def test_envs_of_their_own_run_side_by_side_in_threads_as_one_after_another(mode: str) -> None:
    actions = np.random.default_rng(2).uniform(-1, 1, (30, 3))

    def run(seed: int, out: dict[int, list]) -> None:
        env = CupboardSearchEnv(map=mode, max_steps=30)
        obs, _ = env.reset(seed=seed)
        trace = [obs["proprio"]]
        for action in actions:
            obs, reward, *_ = env.step(action)
            trace += [obs["proprio"], obs.get("map", np.zeros(1)), np.array([reward])]
        out[seed] = trace

    threaded: dict[int, list] = {}
    threads = [threading.Thread(target=run, args=(seed, threaded)) for seed in (5, 6)]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join()
    sequential: dict[int, list] = {}
    for seed in (5, 6):
        run(seed, sequential)
    for seed in (5, 6):
        for a, b in zip(threaded[seed], sequential[seed], strict=True):
            np.testing.assert_array_equal(a, b)


@pytest.mark.parametrize("action_mode", ["wrist", "probe"])
def test_a_vector_env_gives_the_same_rollouts_on_one_two_or_three_threads(
    action_mode: str,
) -> None:
    """Short episodes, so autoresets (queued first) run in the same calls as steps; three
    threads is more than this machine's cores, and each call's tasks land on threads
    differently."""
    traces = []
    for threads in (1, 2, 3):
        env = CupboardSearchVectorEnv(
            num_envs=5, threads=threads, action_mode=action_mode, max_steps=6
        )
        env.action_space.seed(4)
        obs, _ = env.reset(seed=8)
        trace = [obs[key] for key in sorted(obs)]
        ended = 0
        for _ in range(14):
            obs, rewards, terminated, truncated, info = env.step(env.action_space.sample())
            trace += [obs[key] for key in sorted(obs)]
            trace += [rewards, terminated, truncated, *(info[key] for key in sorted(info))]
            ended += int((terminated | truncated).sum())
        assert ended >= 5, f"only {ended} episodes ended: too few autoresets to test"
        traces.append(trace)
    for other in traces[1:]:
        for a, b in zip(traces[0], other, strict=True):
            np.testing.assert_array_equal(a, b)


def test_a_single_env_lending_its_resets_to_a_helper_thread_gives_the_same_episodes() -> None:
    """``CupboardSearchEnv(threads=2)``: a helper thread takes tiles of each reset's GPIS
    grid update; observations, rewards and infos are those of one thread, a pickled copy
    keeps the setting, and a numpy int is a count too."""
    traces = []
    for threads in (1, 2):
        env = CupboardSearchEnv(threads=threads, action_mode="probe", max_steps=3)
        env.action_space.seed(2)
        trace = []
        for seed in (11, 12, 13):
            obs, info = env.reset(seed=seed)
            trace += [obs["map"], obs["proprio"], info["gpis_rows"]]
            for _ in range(3):
                obs, reward, terminated, truncated, info = env.step(env.action_space.sample())
                trace += [obs["map"], obs["proprio"], reward, info["iou"]]
                if terminated or truncated:
                    break
        traces.append(trace)
    for a, b in zip(*traces, strict=True):
        np.testing.assert_array_equal(a, b)
    copy = pickle.loads(pickle.dumps(CupboardSearchEnv(threads=2)))
    assert copy._batch.threads == 2
    # The default: a helper wherever there is a second core (as many threads as cores
    # is what the vector env of one episode takes by default).
    cores = CupboardSearchVectorEnv(num_envs=1)._batch.threads
    assert CupboardSearchEnv()._batch.threads == min(2, cores)
    assert CupboardSearchEnv(threads=1)._batch.threads == 1
    assert CupboardSearchEnv(threads=np.int64(2))._batch.threads == 2


def random_steps(env: object, count: int) -> list[np.ndarray]:
    """``count`` steps of ``env``'s seeded random actions: each step's observation arrays
    and reward (a single env resets when its episode ends; a vector env autoresets)."""
    trace = []
    for _ in range(count):
        obs, reward, terminated, truncated, _ = env.step(env.action_space.sample())
        trace += [*(np.asarray(obs[key]) for key in sorted(obs)), np.asarray(reward)]
        if isinstance(env, CupboardSearchEnv) and (terminated or truncated):
            env.reset()
    return trace


def step_in_the_child(env: object, count: int, results: Any) -> None:
    results.put(random_steps(env, count))


@pytest.mark.parametrize("env_type", [CupboardSearchEnv, CupboardSearchVectorEnv])
def test_an_env_forked_with_its_helper_threads_steps_on_in_the_child(env_type: type) -> None:
    """A fork copies only the forking thread: the child's env starts helpers of its own
    rather than wait for ever on the parent's (``multiprocessing`` forks a process that
    holds an env). Its steps are those the parent takes with the same actions."""
    kwargs = {"num_envs": 3} if env_type is CupboardSearchVectorEnv else {}
    env = env_type(threads=2, action_mode="probe", max_steps=4, **kwargs)
    env.reset(seed=21)
    env.action_space.seed(5)
    random_steps(env, 2)  # the helpers have run in the parent
    context = multiprocessing.get_context("fork")
    results = context.Queue()
    child = context.Process(target=step_in_the_child, args=(env, 12, results))
    child.start()
    try:
        in_child = results.get(timeout=120)
    except queue.Empty:
        pytest.fail("the forked env did not finish 12 steps in 120 s: it waits on helpers")
    finally:
        child.join(timeout=10)
        if child.is_alive():
            child.kill()
    assert child.exitcode == 0
    for a, b in zip(random_steps(env, 12), in_child, strict=True):
        np.testing.assert_array_equal(a, b)


@pytest.mark.parametrize("env", [CupboardSearchEnv, CupboardSearchVectorEnv])
def test_a_thread_count_that_is_not_a_positive_int_is_refused_naming_threads(env: type) -> None:
    for wrong_type in (True, "2", 2.0):
        with pytest.raises(TypeError, match=r"^threads must be a positive int or None, got "):
            env(threads=wrong_type)
    for wrong_value in (0, -3):
        with pytest.raises(ValueError, match=r"^threads must be a positive int or None, got "):
            env(threads=wrong_value)
