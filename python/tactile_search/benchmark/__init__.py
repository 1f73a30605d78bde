"""The standard evaluation for any agent: ``tactile_search.benchmark.evaluate``.

A researcher with their own policy reports a number comparable to the project's results
table without copying its code::

    from tactile_search.benchmark import evaluate

    result = evaluate(my_policy, split="validation", episodes=200, map="gpis")
    result.summary.success_rate, result.summary.success_low, result.summary.success_high
    result.rows  # one dict per episode: seed, success, steps, actions, tips, ...

``my_policy`` is any callable from one env's observation to its action (optionally with
``reset(observation, info)``, called at each episode's start); a loaded stable-baselines3
model is one through ``from_sb3(model)``, and a saved one through ``load_policy`` (which
reads its run's ``config.yml``, so that it runs as it was trained)::

    result = evaluate(load_policy("docs/results/models/ppo_gpis_seed0/model.zip"))

Every action must fit the env's action space
(``action_mode="wrist"`` or ``"probe"``): one that does not is refused, not clipped
(``tactile_search.benchmark.checks``). The layouts come from the one
place that defines the splits (``tactile_search.seed_ranges``): every choice is made on
``validation``; ``test`` is read only by a final evaluation (``final=True``). The command
line: ``python -m tactile_search.benchmark --policy module:callable`` (or a
stable-baselines3 ``model.zip``). Needs only numpy and gymnasium (a model.zip needs the
``agents`` extra). A model.zip is checked against the digest recorded beside it
(``model_digest``) before it is loaded; ``--json`` writes a result file (``result_file``),
and ``python -m tactile_search.benchmark.leaderboard`` makes a leaderboard page of such files.
"""

from tactile_search.benchmark.policies import from_sb3, load_policy
from tactile_search.benchmark.runner import ROW_KEYS, BenchmarkResult, episode_row, evaluate
from tactile_search.benchmark.statistics import Summary, summarize, wilson_interval

__all__ = [
    "ROW_KEYS",
    "BenchmarkResult",
    "Summary",
    "episode_row",
    "evaluate",
    "from_sb3",
    "load_policy",
    "summarize",
    "wilson_interval",
]
