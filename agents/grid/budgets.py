"""The pipeline's budgets: what each trains (agents, timesteps, training seeds, CPUs per
trial), where its runs and results go, and the held-out layouts it evaluates on.

``demo`` (``make demo``) trains the GPIS-map and the no-map PPO agents briefly, each
warm-started from its published model, and evaluates them on 50 validation layouts;
``full`` (``make results``) trains every learned agent with training seeds 0, 1 and 2 by its
recipe (the PPO agents: the planner cloned, then ``n_timesteps`` of PPO) into
``docs/results/models/`` and evaluates on 500 test layouts.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Any

from agents.run_dir import PUBLISHED_RUNS
from agents.sb3.learned import learned_agent_name


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
    # The learned agents evaluated a second time sampling their probes (``<results>/sampled/``),
    # beside the main table's recipe's way (their mode: what SB3's ``evaluate_policy`` and
    # rl-zoo3 do by default).
    sampled_too: bool = False


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
        sampled_too=True,
    ),
}


SCRIPTED = ("random", "gpis_probe_planner", "oracle")


# The agent every other is compared with.
REFERENCE_AGENT = learned_agent_name("ppo", "gpis")
