"""Agents for ``tactile_search/CupboardSearch-v0``: training, evaluation and baselines.

The top-level modules are the commands (argparse and ``main`` only)::

    python -m agents.train        # one SB3 agent            (agents.sb3.training)
    python -m agents.evaluate     # held-out evaluation      (agents.evaluation.evaluation)
    python -m agents.pipeline     # the grid, then results   (agents.grid.pipeline)
    python -m agents.comparison   # pooled seeds, differences (agents.evaluation.comparison)
    python -m agents.probe_trace  # how probes are spent     (agents.evaluation.probe_trace)
    python -m agents.rllib_ppo    # RLlib's PPO              (agents.rllib.training)

Two contracts stand on their own: ``run_dir`` (what a training run's folder holds) and
``rollout`` (the ``Agent`` protocol and the episode loop). The subpackages, one concept each:
``scripted`` (random, oracle, the GPIS planner), ``sb3`` (recipes, encoders, training, the
learned agent), ``evaluation`` (rows, statistics, reports, comparison, probe traces),
``grid`` (trials, the pipeline, the Ray scheduler) and ``rllib``. See ``docs/DESIGN.md``.
"""
