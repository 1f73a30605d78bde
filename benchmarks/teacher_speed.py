"""A teacher's speed beside the environment's: probes per second of one of the core's planners
(``agents.scripted.CORE_PLANNERS``: the GPIS probe planner, the identify planner, the
mappers), and of the Python reference it replaced, against random probes, side by side in
one run on the same training-range layouts and settings (an env id of the planner's task).

Rows, each over whole episodes (resets included):

- ``random probes``: one env, one thread, random probes (the environment's own rate; on an
  identify id, random probes that never claim);
- ``core planner``: the same env with the core's planner choosing every probe (its static
  tables, made once per settings, made before the clock as the env's are);
- ``its probes replayed``: the same env stepping the planner's probes again without it (the
  environment's own rate on the planner's episodes, which are shorter than random ones, so
  a reset weighs more per probe);
- ``python planner``: the Python reference (``agents.scripted.CORE_PLANNERS``), on fewer
  episodes (it is slow);
- ``vector random`` and ``vector core planner``: a vector env of ``--num-envs`` episodes on
  every core, random probes or the core's planner over the whole batch
  (the face's core class, ``ProbePlanner``, ``IdentifyPlanner`` or ``MapPlanner`` made as
  ``(config, n)``: one planner per episode, acting in parallel).

It prints probes/s per row and the planner's rate as a share of the random rate beside it::

    python -m benchmarks.teacher_speed --episodes 200 --num-envs 16
    python -m benchmarks.teacher_speed --planner identify_planner
"""

from __future__ import annotations

import argparse
import time
from collections.abc import Callable
from typing import Any

import numpy as np

from agents.scripted import CORE_PLANNERS
from benchmarks.arguments import positive_int
from benchmarks.planner_agreement import planner_settings
from tactile_search import CupboardSearchEnv, CupboardSearchVectorEnv

#: Layouts of the training range (the teacher labels training layouts).
FIRST_LAYOUT = 2**32 + 7


def random_probes(rng: np.random.Generator, nvec: np.ndarray, size: tuple = ()) -> np.ndarray:
    """Uniform probes of the action space ``nvec``; a claim entry (the last of four) is 0."""
    actions = rng.integers(nvec, size=(*size, len(nvec)))
    if len(nvec) == 4:
        actions[..., 3] = 0
    return actions


def single_env(
    settings: dict[str, Any],
    episodes: int,
    choose: Callable[[], Any] | None,
    replay: list[list[Any]] | None = None,
) -> tuple[float, int, list[list[Any]]]:
    """Seconds, probes and each episode's probes over ``episodes`` episodes of one env of
    ``settings`` on one thread: random probes, those of a planner ``choose()`` makes
    (``reset``/``act``), or the probes of ``replay`` again (the env alone on a planner's
    episodes)."""
    env = CupboardSearchEnv(threads=1, **settings)
    rng = np.random.default_rng(0)
    probes, made = 0, []
    planner = choose() if choose is not None else None
    if planner is not None:
        # A planner makes its static tables (the settings' probe paths and turns) on its
        # first reset, as the env makes its own when it is made: both before the clock, on
        # a layout before the timed ones.
        observation, info = env.reset(seed=FIRST_LAYOUT - 1)
        planner.reset(env, observation, info)
    started = time.perf_counter()
    for k in range(episodes):
        observation, info = env.reset(seed=FIRST_LAYOUT + k)
        if planner is not None:
            planner.reset(env, observation, info)
        done, episode = False, []
        while not done:
            if replay is not None:
                action = replay[k][len(episode)]
            elif planner is not None:
                action = planner.act(observation)
            else:
                action = random_probes(rng, env.action_space.nvec)
            episode.append(action)
            observation, _, terminated, truncated, _ = env.step(action)
            probes += 1
            done = terminated or truncated
        made.append(episode)
    return time.perf_counter() - started, probes, made


def vector_env(
    settings: dict[str, Any], num_envs: int, probes: int, core_class: Any = None
) -> tuple[float, int]:
    """Seconds and probes over at least ``probes`` probes of a vector env of ``num_envs``
    episodes of ``settings`` on every core, with random probes or the core's planner
    ``core_class`` over the batch."""
    env = CupboardSearchVectorEnv(num_envs=num_envs, autoreset_mode="same_step", **settings)
    rng = np.random.default_rng(0)
    started = time.perf_counter()
    observation, _ = env.reset(seed=FIRST_LAYOUT)
    teacher = core_class(env.config.core, num_envs) if core_class is not None else None
    if teacher is not None:
        for i in range(num_envs):
            teacher.reset(i, observation["map"][i], observation["proprio"][i])
    done_probes = 0
    while done_probes < probes:
        if teacher is not None:
            actions = teacher.act(observation["map"], observation["proprio"])
        else:
            actions = random_probes(rng, env.single_action_space.nvec, (num_envs,))
        observation, _, terminated, truncated, _ = env.step(actions)
        done_probes += num_envs
        if teacher is not None:
            for i in np.flatnonzero(terminated | truncated):
                teacher.reset(int(i), observation["map"][i], observation["proprio"][i])
    seconds = time.perf_counter() - started
    env.close()
    return seconds, done_probes


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--episodes", type=positive_int, default=200)
    parser.add_argument("--python-episodes", type=positive_int, default=20)
    parser.add_argument("--num-envs", type=positive_int, default=16)
    parser.add_argument("--vector-probes", type=positive_int, default=4000)
    parser.add_argument("--planner", choices=sorted(CORE_PLANNERS), default="gpis_probe_planner")
    parser.add_argument("--env-id", help="an id of the planner's task (default: its task's)")
    args = parser.parse_args(argv)
    env_id, settings = planner_settings(parser, args.planner, args.env_id)
    face, reference = CORE_PLANNERS[args.planner]
    *planned, episodes = single_env(settings, args.episodes, face)
    rows = {
        "random probes, one env": single_env(settings, args.episodes, None)[:2],
        "core planner, one env": tuple(planned),
        "its probes replayed, one env": single_env(settings, args.episodes, None, episodes)[:2],
        "python planner, one env": single_env(settings, args.python_episodes, reference)[:2],
        f"vector random, {args.num_envs} envs": vector_env(
            settings, args.num_envs, args.vector_probes
        ),
        f"vector core planner, {args.num_envs} envs": vector_env(
            settings, args.num_envs, args.vector_probes, face.core_class
        ),
    }
    rates = {name: probes / seconds for name, (seconds, probes) in rows.items()}
    base = {
        "core planner, one env": "random probes, one env",
        "its probes replayed, one env": "random probes, one env",
        "python planner, one env": "random probes, one env",
        f"vector core planner, {args.num_envs} envs": f"vector random, {args.num_envs} envs",
    }
    print(f"{args.planner} on {env_id}")
    print(f"{'':40} {'probes':>7} {'seconds':>8} {'probes/s':>9}  share of random")
    for name, (seconds, probes) in rows.items():
        share = f"{100 * rates[name] / rates[base[name]]:6.1f} %" if name in base else ""
        print(f"{name:40} {probes:7d} {seconds:8.2f} {rates[name]:9.1f}  {share}")


if __name__ == "__main__":
    main()
