"""The pipeline's budgets: what each trains (agents, timesteps, training seeds, CPUs per
trial), where its runs and results go, and the held-out layouts it evaluates on.

``demo`` (``make demo``) trains the GPIS-map and the no-map PPO agents briefly, each
warm-started from its published model, and evaluates them on 50 validation layouts;
``full`` (``make results``) trains every learned agent with training seeds 0, 1 and 2 by its
recipe (the PPO agents: the task's planner cloned, then ``n_timesteps`` of PPO) into
``docs/results/models/`` and evaluates on 500 test layouts, on every task (``Task``): the
search task (``CupboardSearch-v0``, v0's results, ``docs/results/``), identify and map by
touch, each trained on its own id (``docs/results/models/<id's name>/``, results in
``docs/results/<id's name>/``), and the dense tiers played by the agents of the default
tier (how they generalise).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from agents.evaluation.evaluation import task_of
from agents.run_dir import PUBLISHED_RUNS, task_folder
from agents.sb3.learned import learned_agent_name
from agents.scripted import scripted_agents_for
from tactile_search import ENV_ID

# The search task's scripted baselines, in the order of v0's tables.
SCRIPTED = ("random", "gpis_probe_planner", "oracle")


@dataclass(frozen=True)
class Task:
    """A registered id a budget evaluates on (``env_id``), and whose agents play it: its own,
    trained on it by the budget, or (``trained_on``) those the budget trains on another id
    (a dense tier played by its default tier's agents). ``sampled_too``: its learned agents
    evaluated a second time sampling their probes (``<results>/sampled/``), beside the main
    table's recipe's way (their mode: what SB3's ``evaluate_policy`` and rl-zoo3 do by
    default)."""

    env_id: str = ENV_ID
    trained_on: str | None = None
    sampled_too: bool = False

    def __post_init__(self) -> None:
        for env_id in (self.env_id, self.trained_on or self.env_id):
            task_folder(env_id)  # a registered id, or a clear error

    @property
    def agents_from(self) -> str:
        """The id whose trained agents play this task."""
        return self.trained_on or self.env_id

    @property
    def task(self) -> str:
        """The ``task`` setting of ``env_id`` (``search``, ``identify`` or ``map``)."""
        return task_of(self.env_id)

    def agent_name(self, algo: str, map_mode: str) -> str:
        """A learned agent's name in this task's rows: as the evaluation names it on this id
        (with the id's name, ``agents.evaluation.evaluation``), without a training seed."""
        folder = task_folder(self.env_id)
        name = learned_agent_name(algo, map_mode)
        return f"{name} [{folder}]" if folder else name

    def reference_agent(self) -> str:
        """The agent every other is compared with here: the GPIS PPO agent."""
        return self.agent_name(*REFERENCE)

    def scripted(self) -> tuple[str, ...]:
        """The scripted agents evaluated beside the learned ones: the task's
        (``agents.scripted.scripted_agents_for``), the search task's in v0's order."""
        if self.task == "search":
            return SCRIPTED
        return tuple(scripted_agents_for(self.task))


@dataclass(frozen=True)
class Budget:
    """What one budget trains and how many held-out episodes it evaluates.

    ``cpus_per_trial``: the CPUs a training trial declares, its torch threads and its
    environment batch's threads. Part of what fixes a model (torch may sum in another order
    with another thread count), so the same in every scheduler: on Ray, this machine runs
    ``cores / cpus_per_trial`` trials at once."""

    agents: tuple[tuple[str, str], ...]
    timesteps: int | None  # None: each recipe's n_timesteps
    episodes: int
    runs: Path
    results: Path
    cpus_per_trial: int
    # The held-out layouts (tactile_search.seed_ranges): the test range is the final results' alone.
    split: str = "validation"
    # Training seeds (one run per agent each); the CLI's --seeds overrides.
    seeds: tuple[int, ...] = (0,)
    # Where the published models are (docs/results/models/<run>/): a run of this budget
    # warm-starts from the published run of the same agent and seed when there is one.
    warm_start_from: Path | None = None
    # Overrides of the PPO recipes' imitation sections (the clone stage before PPO); a run
    # that warm-starts clones nothing.
    imitation: dict[str, Any] | None = None
    # The ids it trains on and evaluates on; the first is the default id's.
    tasks: tuple[Task, ...] = (Task(),)

    def __post_init__(self) -> None:
        trained = {task.env_id for task in self.tasks if task.trained_on is None}
        for task in self.tasks:
            if task.agents_from not in trained:
                raise ValueError(
                    f"{task.env_id} is played by the agents of {task.agents_from}, which this "
                    f"budget does not train (it trains on {sorted(trained)})"
                )

    def trained_ids(self) -> list[str]:
        """The ids the budget trains its agents on, in the order of ``tasks``."""
        return [task.env_id for task in self.tasks if task.trained_on is None]

    def only(self, env_ids: Sequence[str]) -> Budget:
        """This budget with only the tasks of ``env_ids`` (in the budget's order): a piece of
        its grid that trains, evaluates and writes those tasks' sections alone, so that a
        grid longer than a sitting runs in pieces. A dense tier needs the id whose agents
        play it among ``env_ids`` too (``__post_init__`` says so)."""
        known = [task.env_id for task in self.tasks]
        unknown = [env_id for env_id in env_ids if env_id not in known]
        if unknown or not env_ids:
            raise ValueError(f"tasks must be some of this budget's {known}, got {list(env_ids)}")
        return dataclasses.replace(
            self, tasks=tuple(task for task in self.tasks if task.env_id in env_ids)
        )


# The documented budget's models (model.zip beside config.yml, one folder per run).
PUBLISHED_MODELS = Path(PUBLISHED_RUNS)


BUDGETS = {
    "demo": Budget(
        agents=(("ppo", "gpis"), ("ppo", "none")),
        timesteps=4096,
        episodes=50,
        runs=Path("runs/demo"),
        results=Path("results"),
        cpus_per_trial=2,
        warm_start_from=PUBLISHED_MODELS,
        # Without a published model to start from, a clone in a few minutes.
        imitation={"demo_episodes": 200, "dagger_rounds": 1, "dagger_episodes": 100},
    ),
    # The published models are the full budget's run directories themselves (their
    # checkpoints and event files stay out of git): a rerun skips the finished ones.
    "full": Budget(
        agents=(("ppo", "gpis"), ("ppo", "occupancy"), ("ppo", "none"), ("recurrent_ppo", "none")),
        timesteps=None,
        # 500 test layouts per training seed: enough to tell the GPIS and the occupancy
        # agents apart to within a few points.
        episodes=500,
        runs=PUBLISHED_MODELS,
        results=Path("docs/results"),
        cpus_per_trial=1,
        split="test",
        seeds=(0, 1, 2),
        tasks=(
            Task(sampled_too=True),
            Task("tactile_search/IdentifyByTouch-v0"),
            Task("tactile_search/MapByTouch-v0"),
            Task("tactile_search/CupboardSearchDense-v0", trained_on=ENV_ID),
            Task(
                "tactile_search/IdentifyByTouchDense-v0",
                trained_on="tactile_search/IdentifyByTouch-v0",
            ),
        ),
    ),
}


# The agent every other is compared with.
REFERENCE = ("ppo", "gpis")
REFERENCE_AGENT = learned_agent_name(*REFERENCE)
