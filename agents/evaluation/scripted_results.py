"""The scripted baselines as result files of the benchmark (``python -m
tactile_search.benchmark --json``'s), so that the leaderboard lists them beside any policy.

A scripted agent reads its ``SubEnv`` (geometry, decoders, the oracle's ground truth), which
the benchmark's ``module:callable`` policies do not see; so it is played here as
``agents.evaluate`` plays it (its own settings under the registered id's,
``agents.evaluation.agent_specs.make_agent``) through the same runner
(``agents.rollout.evaluate_agent`` is ``tactile_search.benchmark.runner.run_on_seeds``),
on a split's first layouts, and summarised by the benchmark's ``summarize``.
"""

from __future__ import annotations

from agents.evaluation.agent_specs import make_agent
from agents.evaluation.evaluation import env_id_settings, evaluation_seeds, task_of
from agents.rollout import evaluate_agent
from agents.scripted import SCRIPTED_AGENTS, SCRIPTED_TASKS
from tactile_search import ENV_ID
from tactile_search.benchmark.runner import DEFAULT_EPISODES, BenchmarkResult
from tactile_search.benchmark.statistics import summarize
from tactile_search.envs.config import config_for


def scripted_result(
    name: str,
    env_id: str = ENV_ID,
    split: str = "validation",
    episodes: int = DEFAULT_EPISODES,
    *,
    final: bool = False,
    num_envs: int | None = None,
) -> BenchmarkResult:
    """The scripted agent ``name`` (``agents.scripted.SCRIPTED_AGENTS``) on the first
    ``episodes`` layouts of ``split`` in registered id ``env_id`` (the test split only for
    the final evaluation, ``final``); ``ValueError`` for an agent that does not play the
    id's task."""
    if name not in SCRIPTED_AGENTS:
        raise ValueError(f"a scripted agent is one of {list(SCRIPTED_AGENTS)}, got {name!r}")
    settings = env_id_settings(env_id)  # a registered id, or ValueError
    task = task_of(env_id)
    if task not in SCRIPTED_TASKS[name]:
        raise ValueError(
            f"{name} plays the tasks {list(SCRIPTED_TASKS[name])}, and {env_id} is the {task} task"
        )
    seeds = evaluation_seeds(split, episodes, final)
    agent, agent_settings = make_agent(name)
    env_kwargs = {**agent_settings, **settings}
    rows = evaluate_agent(agent, seeds, num_envs=num_envs, **env_kwargs)
    config = config_for("evaluate", env_kwargs)
    return BenchmarkResult(
        rows=rows,
        summary=summarize(name, config.map, rows),
        split=split,
        env_kwargs=env_kwargs,
        env_id=env_id,
        task=config.task,
    )


def result_file_name(env_id: str, name: str) -> str:
    """The result file of scripted agent ``name`` on ``env_id``: ``<id's name>_<agent>.json``."""
    return f"{env_id.split('/')[-1]}_{name}.json"
