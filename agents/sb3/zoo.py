"""The training recipes as rl-baselines3-zoo reads them.

rl-zoo3 keys a config file by env id alone, passes every key it does not know to the
algorithm and reads classes only from Python. ``zoo_hyperparams(algo, map_mode)`` turns the
recipe of ``agents/hyperparams/<algo>.yml`` (keyed by env id, then map mode) into that: the
run's keys rl-zoo3 knows (``n_timesteps``, ``n_envs``, ``policy``, ``env_kwargs``), the
algorithm's arguments with the network classes imported (``tactile_search.networks``), and
none of the project's own keys (``max_minutes``, ``deterministic_evaluation``,
``bfloat16_updates``, ``imitation``: rl-zoo3 trains the recipe's network from fresh weights
in float32, without the clone stage of ``agents.imitation.clone_stage``).

Evaluate its agents sampled (``python -m rl_zoo3.enjoy ... --stochastic``), not by rl-zoo3's
default, the policy's most likely action: without the clone of the probe planner that the
recipe's ``deterministic_evaluation: true`` is for, the most likely action of an agent
trained from scratch in the probe mode repeats one probe until the time limit
(docs/results/ablations_imitation/ppo_spatial.yml: 63 % sampled against 47 % on 100
validation layouts). rl-zoo3's evaluations during training (``--eval-freq``) always take the
most likely action, and so does its ``best_model``.
``agents/hyperparams/zoo/<algo>_<map>.py`` are the config files, one per recipe; from the
repository's root (so that ``agents`` imports)::

    python -m rl_zoo3.train --algo ppo --env tactile_search/CupboardSearch-v0 \\
        --gym-packages tactile_search -conf agents/hyperparams/zoo/ppo_gpis.py

rl-zoo3 seeds its envs itself: their layouts come from the env's own draw over its default
layout range, not from the project's training range (``tactile_search.seed_ranges``); the
held-out ranges are a vanishing share of that draw, so a held-out layout is almost never
trained on.
"""

from __future__ import annotations

from typing import Any

from agents.sb3.recipes import algorithm_kwargs, load_hyperparams
from tactile_search import ENV_ID

#: The run's keys rl-zoo3 reads itself (the others go to the algorithm).
ZOO_RUN_KEYS = ("n_timesteps", "n_envs", "policy", "env_kwargs")


def zoo_hyperparams(algo: str, map_mode: str) -> dict[str, dict[str, Any]]:
    """rl-zoo3's ``hyperparams`` for the recipe of ``algo`` on ``map_mode``: ``{ENV_ID:
    {...}}`` (see the module docstring)."""
    recipe = load_hyperparams(algo, map_mode)
    run = {key: recipe[key] for key in ZOO_RUN_KEYS if key in recipe}
    return {ENV_ID: {**run, **algorithm_kwargs(recipe, make_schedules=False)}}
