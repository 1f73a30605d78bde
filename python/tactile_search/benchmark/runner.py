"""``evaluate``: any policy through the standard evaluation on the vector env.

The layouts are the split's first ``episodes`` seeds (``tactile_search.seed_ranges``: the
validation range for every choice, the test range only for a final result). Each episode
is a pure function of its layout seed and the policy's actions, so a row does not depend on
how many episodes run side by side. The vector env runs with ``autoreset_mode="disabled"``:
when an episode ends its slot is reset onto the next seed of the split; once none is left
the slot replays its last layout, its results ignored, until every episode has ended.
"""

from __future__ import annotations

import copy
import dataclasses
import os
import sys
from collections.abc import Callable, Sequence
from typing import Any

import gymnasium
import numpy as np

from tactile_search import ENV_ID, ENV_IDS
from tactile_search.benchmark.checks import ActionCheck, check_policy
from tactile_search.benchmark.map_curve import MapScoreTrace
from tactile_search.benchmark.statistics import Summary, summarize
from tactile_search.envs.config import config_for
from tactile_search.envs.sub_env import SubEnv
from tactile_search.envs.vector import CupboardSearchVectorEnv
from tactile_search.seed_ranges import TEST, held_out_seeds

#: The per-episode row's keys, in order (``wrong_claim``: the identify task's failure by a
#: claim on another jar or none, always False elsewhere; ``map_score_*``: the map task's
#: final outline distance (mm), IoU and the distance's mean over the budget (mm), 0
#: elsewhere; ``map_score_curve``: the distance against the motions, ``map_curve``'s text,
#: empty elsewhere).
ROW_KEYS = (
    "seed", "success", "wrong_claim", "steps", "actions", "tips", "jar_displacement",
    "max_jar_displacement", "iou", "reward", "map_score_mm", "map_score_iou", "map_score_area",
    "map_score_curve",
)  # fmt: skip

#: The layouts an evaluation plays unless told otherwise (the split's first seeds).
DEFAULT_EPISODES = 200


def episode_row(
    seed: int, info: dict[str, Any], actions: int, reward: float, map_score_curve: str = ""
) -> dict[str, Any]:
    """One episode's row from the info of its last step (``steps``: wrist motions, the
    time limit's count; ``actions``: the policy's steps, a probe each in the probe mode;
    ``map_score_curve``: the map task's, ``map_curve.MapScoreTrace.curve``)."""
    return {
        "seed": seed,
        "success": bool(info["success"]),
        "wrong_claim": bool(info["wrong_claim"]),
        "steps": int(info["steps"]),
        "actions": actions,
        "tips": int(info["tips"]),
        "jar_displacement": float(info["jar_displacement"]),
        "max_jar_displacement": float(info["max_jar_displacement"]),
        "iou": float(info["iou"]),
        "reward": float(reward),
        "map_score_mm": float(info["map_score_mm"]),
        "map_score_iou": float(info["map_score_iou"]),
        "map_score_area": float(info["map_score_area"]),
        "map_score_curve": map_score_curve,
    }


@dataclasses.dataclass(frozen=True)
class BenchmarkResult:
    """An evaluation's rows (one dict per episode, in the split's seed order), their
    summary (success with its 95 % Wilson interval, steps to success, tips, displacement
    within successful episodes, final IoU, wrong claims), the registered id and the env
    settings it ran in (the id's, the policy's own, then those given), and its task."""

    rows: list[dict[str, Any]]
    summary: Summary
    split: str
    env_kwargs: dict[str, Any]
    env_id: str = ENV_ID
    task: str = "search"


def evaluate(
    policy: Callable[[dict[str, np.ndarray]], Any],
    split: str = "validation",
    episodes: int = DEFAULT_EPISODES,
    *,
    final: bool = False,
    name: str | None = None,
    num_envs: int | None = None,
    progress: bool = True,
    env_id: str | None = None,
    **env_kwargs: Any,
) -> BenchmarkResult:
    """Runs ``policy`` on the first ``episodes`` layouts of ``split`` and summarises them.

    Args:
        policy: a callable from one env's observation (a dict of arrays) to its action; if
            it also has ``reset(observation, info)``, that is called at each episode's start
            and every slot of the vector env gets its own ``copy.deepcopy`` of it (a stateful
            policy never sees two episodes at once; it must start each episode afresh in
            ``reset``, since a slot's copy plays its episodes one after another). A loaded
            SB3 model goes through ``from_sb3(model)``. Every action is checked against one
            env's action space (``checks.ActionCheck``): one that does not fit the
            ``action_mode`` raises instead of being clipped.
        split: ``"validation"`` (every choice is made here) or ``"test"`` (held out for a
            final result: only with ``final=True``).
        episodes: layouts, the split's first seeds.
        final: this is the final evaluation (the only one allowed to read the test split).
        name: the agent's name in the summary (default: the policy's ``name`` attribute or
            its type's name).
        num_envs: episodes side by side (default: the cores, at most ``episodes``).
        progress: show a progress bar on stderr (tqdm's if installed).
        env_id: the registered id whose task and tier to run (``tactile_search.ENV_IDS``;
            default: the policy's ``env_id`` if it has one, else ``ENV_ID``), its settings
            under the policy's and ``env_kwargs``.
        **env_kwargs: the env's settings (``map``, ``action_mode``, ...), as ``gym.make``
            takes them; the reward terms do not change the rows' success and metrics. A
            policy that knows the settings it was trained in (``env_settings``, a dict: a
            ``model.zip`` from ``load_policy`` has its run's, ``from_sb3`` its model's action
            mode) runs in them, each of ``env_kwargs`` overriding one; its ``check_fits``,
            if any, refuses settings whose spaces are not the model's (``ValueError``).
    """
    if split == "test" and not final:
        lo, hi = TEST
        raise ValueError(
            f"the test split (seeds {lo:,} to {hi - 1:,}) is held out for the final result: "
            "pass final=True only for that evaluation; make every choice on 'validation'"
        )
    check_policy(policy)
    env_id = env_id or getattr(policy, "env_id", None) or ENV_ID
    if env_id not in ENV_IDS:
        raise ValueError(f"env_id must be one of {list(ENV_IDS)}, got {env_id!r}")
    env_kwargs = {
        **gymnasium.spec(env_id).kwargs,
        **dict(getattr(policy, "env_settings", None) or {}),
        **env_kwargs,
    }
    check_fits = getattr(policy, "check_fits", None)
    if callable(check_fits):
        check_fits(env_kwargs)
    seeds = held_out_seeds(split, episodes)
    stateful = callable(getattr(policy, "reset", None))
    rows = run_on_seeds(
        lambda sub_env: copy.deepcopy(policy) if stateful else policy,
        seeds, num_envs=num_envs, progress=progress, check_actions=True, **env_kwargs,
    )  # fmt: skip
    agent = (
        name or getattr(policy, "name", None) or getattr(policy, "__name__", None)
        or type(policy).__name__
    )  # fmt: skip
    config = config_for("evaluate", env_kwargs)
    return BenchmarkResult(
        rows=rows,
        summary=summarize(str(agent), config.map, rows),
        split=split,
        env_kwargs=dict(env_kwargs),
        env_id=env_id,
        task=config.task,
    )


def run_on_seeds(
    make_policy: Callable[[SubEnv], Any],
    seeds: Sequence[int],
    *,
    num_envs: int | None = None,
    on_episode: Callable[[dict[str, Any]], None] | None = None,
    progress: bool = False,
    check_actions: bool = False,
    **env_kwargs: Any,
) -> list[dict[str, Any]]:
    """One episode per layout seed on the vector env; their rows in the order of ``seeds``.

    ``make_policy(sub_env)`` gives the policy of one slot of the vector env (called once per
    slot; ``sub_env`` is that slot's ``SubEnv``, for agents that read the env's geometry,
    decoders or oracle); its ``reset(observation, info)``, if any, is called at each of the
    slot's episodes' start. ``on_episode(row)`` is called as each episode ends (rows come in
    the order episodes end). ``check_actions``: every action is checked against one env's
    action space first (``checks.ActionCheck``: refused, not clipped, with an error in the
    policy's terms). ``evaluate`` is this on a split's seeds with the check, and a summary."""
    if not seeds:
        return []
    if num_envs is None:
        num_envs = min(len(seeds), os.cpu_count() or 1)
    vector = CupboardSearchVectorEnv(
        num_envs=num_envs, autoreset_mode="disabled", copy=True, **env_kwargs
    )
    tick = _progress(len(seeds), progress)

    def finished(row: dict[str, Any]) -> None:
        tick()
        if on_episode is not None:
            on_episode(row)

    try:
        policies = [make_policy(vector.sub_env(i)) for i in range(num_envs)]
        check = ActionCheck(vector.single_action_space) if check_actions else np.asarray
        return _run(vector, policies, list(seeds), finished, check)
    finally:
        vector.close()


class _Slot:
    """One sub-env's episode in progress: its layout, its seed in the evaluation (None: no
    seed left, the slot only idles on ``layout``), steps and return."""

    def __init__(self, layout: int, seed: int | None) -> None:
        self.layout = layout
        self.seed = seed
        self.actions = 0
        self.reward = 0.0
        # The map task's distance against the motions (None in the other tasks).
        self.trace: MapScoreTrace | None = None


def _run(
    vector: CupboardSearchVectorEnv, policies: list[Any], seeds: list[int],
    finished: Callable[[dict[str, Any]], None], check: Callable[[Any], np.ndarray],
) -> list[dict[str, Any]]:  # fmt: skip
    queue = list(seeds)
    first = queue[: vector.num_envs]
    del queue[: vector.num_envs]
    # Slots beyond the episodes (fewer episodes than envs) idle on the first layout.
    layouts = first + [first[0]] * (vector.num_envs - len(first))
    observation, info = vector.reset(seed=layouts)
    slots = [_Slot(layout, layout if i < len(first) else None) for i, layout in enumerate(layouts)]
    for i, policy in enumerate(policies):
        _begin(policy, observation, info, i, vector, slots[i])
    rows: dict[int, dict[str, Any]] = {}
    while len(rows) < len(seeds):
        actions = np.stack(
            [check(policy(_row(observation, i))) for i, policy in enumerate(policies)]
        )
        observation, reward, terminated, truncated, info = vector.step(actions)
        ended = terminated | truncated
        for i, slot in enumerate(slots):
            slot.actions += 1
            slot.reward += float(reward[i])
            if slot.trace is not None:
                slot.trace.step(_row(info, i))
            if ended[i] and slot.seed is not None:
                curve = "" if slot.trace is None else slot.trace.curve(vector.config.max_steps)
                rows[slot.seed] = episode_row(
                    slot.seed, _row(info, i), slot.actions, slot.reward, curve
                )
                finished(rows[slot.seed])
        if ended.any():
            observation, info = _next_episodes(vector, policies, slots, ended, queue)
    return [rows[seed] for seed in seeds]


def _next_episodes(
    vector: CupboardSearchVectorEnv, policies: list[Any], slots: list[_Slot],
    ended: np.ndarray, queue: list[int],
) -> tuple[dict[str, np.ndarray], dict[str, Any]]:  # fmt: skip
    """Resets the ended slots onto the next seeds (or their own layout, to idle)."""
    layouts: list[int | None] = [None] * len(slots)
    for i in np.flatnonzero(ended).tolist():
        next_seed = queue.pop(0) if queue else None
        slots[i] = _Slot(slots[i].layout if next_seed is None else next_seed, next_seed)
        layouts[i] = slots[i].layout
    observation, info = vector.reset(seed=layouts, options={"reset_mask": ended.copy()})
    for i in np.flatnonzero(ended).tolist():
        _begin(policies[i], observation, info, i, vector, slots[i])
    return observation, info


def _begin(
    policy: Any, observation: dict[str, np.ndarray], info: dict[str, Any], index: int,
    vector: CupboardSearchVectorEnv, slot: _Slot,
) -> None:  # fmt: skip
    """Starts slot ``index``'s episode: its map score trace (the map task), its policy's
    ``reset``."""
    if vector.config.task == "map":
        slot.trace = MapScoreTrace(_row(info, index))
    reset = getattr(policy, "reset", None)
    if callable(reset):
        reset(_row(observation, index), _row(info, index))


def _row(batch: dict[str, np.ndarray], index: int) -> dict[str, Any]:
    """Sub-env ``index``'s entry of a batched dict (observation or info; no ``_key``
    masks)."""
    return {key: value[index] for key, value in batch.items() if not key.startswith("_")}


def _progress(total: int, show: bool) -> Callable[[], None]:
    """A callable that advances a progress bar of ``total`` episodes (tqdm's if installed,
    else a line on stderr); a no-op when ``show`` is False."""
    if not show:
        return lambda: None
    try:
        from tqdm.auto import tqdm
    except ModuleNotFoundError:
        done = [0]

        def tick() -> None:
            done[0] += 1
            end = "\n" if done[0] == total else ""
            print(f"\r  episodes {done[0]}/{total}", end=end, file=sys.stderr, flush=True)

        return tick
    bar = tqdm(total=total, unit="episode", leave=False)

    def advance() -> None:
        bar.update()
        if bar.n >= total:
            bar.close()

    return advance
