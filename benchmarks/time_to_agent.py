"""Where the time to a trained agent goes: one training seed of a recipe, stage by stage.

Runs ``agents.train``'s path (``train_with_clone_stage``: the clone stage, then PPO's
fine-tuning) for one seed of a map's recipe and times each stage as it runs:

- the teacher's demonstrations and each DAgger round's rollouts, each split into the time
  in the teacher (its ``act`` and ``follow``), in the student's policy, and the rest
  (the environment and the bookkeeping);
- each cloning pass (behaviour cloning, then one per DAgger round);
- PPO's fine-tuning;
- the rest (building the model, mirror images, agreement, saving).

It prints each stage's wall-clock and share of the total, and writes them as JSON beside
the run (``--out``). ``--scale`` shrinks the recipe's episodes and PPO budget by a factor,
for a quick look; the published figures are at ``--scale 1``. ``--imitation KEY=VALUE``
overrides the recipe's imitation section (a variant's time); ``--env-id`` runs the recipe
keyed by another registered id (its task's teacher)::

    python -m benchmarks.time_to_agent --map gpis --seed 0 --out /tmp/time_to_agent
    python -m benchmarks.time_to_agent --env-id tactile_search/IdentifyByTouch-v0 --scale 0.01
"""

from __future__ import annotations

import argparse
import contextlib
import dataclasses
import json
import time
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

from agents.command_args import parse_setting
from agents.sb3.recipes import algorithm_class, load_hyperparams
from tactile_search import ENV_ID, ENV_IDS

#: The stages' rows, in the order a run meets them.
TEACHER, STUDENT = "teacher", "student policy"


@dataclasses.dataclass
class StageClock:
    """Wall-clock seconds by stage, in the order the stages first ran."""

    seconds: dict[str, float] = dataclasses.field(default_factory=dict)

    def add(self, stage: str, seconds: float) -> None:
        self.seconds[stage] = self.seconds.get(stage, 0.0) + seconds

    @contextlib.contextmanager
    def timing(self, stage: str) -> Iterator[None]:
        started = time.perf_counter()
        try:
            yield
        finally:
            self.add(stage, time.perf_counter() - started)

    def call_outside(
        self, stage: str, inside: list[str], function: Callable[..., Any], args: Any, kwargs: Any
    ) -> Any:
        """Calls ``function``, adding its time to ``stage`` less what the ``inside`` stages
        (timed within the call) took."""
        before = sum(self.seconds.get(name, 0.0) for name in inside)
        with self.timing(stage):
            result = function(*args, **kwargs)
        self.add(stage, before - sum(self.seconds.get(name, 0.0) for name in inside))
        return result

    def timed(self, stage: Callable[[], str], function: Callable[..., Any]) -> Callable[..., Any]:
        """``function`` with each call's time added to the stage ``stage()`` names then."""

        def wrapper(*args: Any, **kwargs: Any) -> Any:
            with self.timing(stage()):
                return function(*args, **kwargs)

        return wrapper


class _TimedPlanner:
    """The core's batch planner with every call's time added to the teacher's row."""

    def __init__(self, clock: StageClock, row: Callable[[], str], planner: Any) -> None:
        self._planner = planner
        for name in ("reset", "act", "follow"):
            setattr(self, name, clock.timed(row, getattr(planner, name)))


def instrument(clock: StageClock, algorithm: type) -> contextlib.ExitStack:
    """Wraps the recipe's stages (the functions ``agents.imitation`` and the PPO stage call,
    and ``algorithm``'s rollouts and updates) with ``clock``'s timers; closing the stack puts
    the originals back."""
    from agents.imitation import batched, clone_stage, demonstrations, training

    stack = contextlib.ExitStack()
    rounds = {"record": 0, "clone": 0}
    current = {"rollouts": "demonstrations"}
    teacher_class = type(demonstrations.make_teacher(training.PLANNER))

    def row(part: str) -> Callable[[], str]:
        return lambda: f"{current['rollouts']} ({part})"

    def patch(owner: Any, name: str, replacement: Any) -> None:
        original = getattr(owner, name)
        setattr(owner, name, replacement)
        stack.callback(setattr, owner, name, original)

    def recording(original: Callable[..., Any]) -> Callable[..., Any]:
        def timed(*args: Any, **kwargs: Any) -> Any:
            index = rounds["record"]
            rounds["record"] += 1
            current["rollouts"] = "demonstrations" if index == 0 else f"DAgger round {index}"
            # The teacher's and the student's time inside are rows of their own.
            inside = [row(part)() for part in (TEACHER, STUDENT)]
            return clock.call_outside(row("env and rest")(), inside, original, args, kwargs)

        return timed

    def cloning_stage() -> str:
        index = rounds["clone"]
        rounds["clone"] += 1
        return "behaviour cloning" if index == 0 else f"DAgger round {index} (cloning)"

    def timed_student(factory: Callable[..., Any]) -> Callable[..., Any]:
        def make(model: Any) -> Any:
            made = factory(model)
            if factory is original_student:  # per episode: a policy per layout
                return lambda layout: clock.timed(row(STUDENT), made(layout))
            return clock.timed(row(STUDENT), made)

        return make

    original_student = training._sampling_student
    original_planner = batched.core_planner
    patch(training, "record", recording(training.record))
    patch(training, "record_batched", recording(training.record_batched))
    patch(training, "clone", clock.timed(cloning_stage, training.clone))
    patch(training, "_sampling_student", timed_student(training._sampling_student))
    patch(training, "_sampling_batch_student", timed_student(training._sampling_batch_student))
    patch(
        batched,
        "core_planner",
        lambda *args: _TimedPlanner(clock, row(TEACHER), original_planner(*args)),
    )
    # PPO's fine-tuning split into its rollouts (the env and the policy's sampling) and its
    # updates; the rest (callbacks, logging) is a row of its own.
    ppo_rows = [f"PPO fine-tuning ({part})" for part in ("rollouts", "updates")]

    def fine_tuning(*args: Any, **kwargs: Any) -> Any:
        rest = "PPO fine-tuning (rest)"
        return clock.call_outside(rest, ppo_rows, original_train, args, kwargs)

    original_train = clone_stage.train
    patch(clone_stage, "train", fine_tuning)
    for method, stage in zip(("collect_rollouts", "train"), ppo_rows, strict=True):
        patch(algorithm, method, clock.timed(lambda stage=stage: stage, getattr(algorithm, method)))
    for method in ("act", "follow"):
        patch(teacher_class, method, clock.timed(row(TEACHER), getattr(teacher_class, method)))
    return stack


def scaled_overrides(recipe: dict[str, Any], scale: float) -> tuple[dict[str, Any], int]:
    """The imitation overrides and PPO timesteps of ``recipe`` shrunk by ``scale``."""
    section = recipe["imitation"]
    overrides = {
        "demo_episodes": max(20, round(section["demo_episodes"] * scale)),
        "dagger_episodes": max(10, round(section["dagger_episodes"] * scale)),
    }
    return overrides, max(
        recipe["n_envs"] * recipe["n_steps"], round(recipe["n_timesteps"] * scale)
    )


def table(seconds: dict[str, float], total: float) -> str:
    rows = [
        *seconds.items(),
        ("other (model, mirror, agreement, saving)", total - sum(seconds.values())),
    ]
    width = max(len(name) for name, _ in rows)
    lines = [f"{'stage':<{width}}  {'seconds':>9}  {'share':>6}"]
    lines += [f"{name:<{width}}  {value:9.1f}  {100 * value / total:5.1f}%" for name, value in rows]
    lines.append(f"{'total':<{width}}  {total:9.1f}  100.0%")
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> None:
    from agents.imitation.clone_stage import train_with_clone_stage
    from agents.sb3.training import TrainSettings

    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--map", default="gpis", dest="map_mode")
    parser.add_argument("--algo", default="ppo")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument(
        "--env-id", choices=ENV_IDS, default=ENV_ID, help="the registered id whose recipe runs"
    )
    parser.add_argument("--scale", type=float, default=1.0, help="share of the recipe to run")
    parser.add_argument("--out", type=Path, default=Path("runs/time_to_agent"))
    parser.add_argument(
        "--torch-threads",
        type=int,
        default=None,
        help="torch's threads (default agents.train's); 1 when runs share the cores",
    )
    parser.add_argument(
        "--env-threads",
        type=int,
        default=None,
        help="the environment batch's threads (default every core); 1 when runs share them",
    )
    parser.add_argument(
        "--imitation",
        nargs="+",
        type=parse_setting,
        default=[],
        metavar="KEY=VALUE",
        help="override keys of the recipe's imitation section, as agents.train takes them",
    )
    args = parser.parse_args(argv)
    if not 0.0 < args.scale <= 1.0:
        parser.error(f"--scale must be in (0, 1], got {args.scale}")
    recipe = load_hyperparams(args.algo, args.map_mode, args.env_id)
    overrides, timesteps = scaled_overrides(recipe, args.scale)
    overrides.update(dict(args.imitation))
    settings = TrainSettings(
        args.algo,
        args.map_mode,
        env_id=args.env_id,
        out=args.out,
        seed=args.seed,
        timesteps=timesteps,
        progress_bar=False,
        env_threads=args.env_threads,
        **({} if args.torch_threads is None else {"torch_threads": args.torch_threads}),
    )
    if settings.run_dir.exists():
        parser.error(f"{settings.run_dir} exists: give another --out (the profile starts afresh)")
    clock = StageClock()
    started = time.perf_counter()
    with instrument(clock, algorithm_class(args.algo)):
        run_dir = train_with_clone_stage(settings, overrides)
    total = time.perf_counter() - started
    print(
        f"{args.env_id} {args.algo} {args.map_mode} seed {args.seed}, scale {args.scale}: "
        f"{overrides}, "
        f"{timesteps} PPO probes"
    )
    print(table(clock.seconds, total))
    (run_dir / "time_to_agent.json").write_text(
        json.dumps({"scale": args.scale, "total": total, "stages": clock.seconds}, indent=2)
    )


if __name__ == "__main__":
    main()
