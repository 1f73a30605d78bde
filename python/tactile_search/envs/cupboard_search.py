"""``tactile_search/CupboardSearch-v0``: find a hidden spice jar by touch, with a GPIS map."""

from __future__ import annotations

from typing import Any

import gymnasium as gym
import numpy as np
from gymnasium import spaces
from gymnasium.error import ResetNeeded
from gymnasium.utils import EzPickle

from tactile_search import _core, seed_ranges
from tactile_search.envs.config import (
    CupboardSearchConfig,
    config_for,
    with_settings_signature,
)
from tactile_search.envs.episode_reads import EpisodeReads
from tactile_search.envs.observation import MAP_CHANNELS, fill_docstring
from tactile_search.envs.time_limit import DeclaredTimeLimit
from tactile_search.render import episode_frame


def observation_space(config: CupboardSearchConfig, proprio_len: int) -> spaces.Dict:
    """The Dict observation space of one environment."""
    entries: dict[str, spaces.Space[Any]] = {}
    # The image's channel count is the map mode's, from the core's table (0: no image).
    channels = sum(1 for mode, _ in MAP_CHANNELS if mode == config.map)
    if channels:
        height, width = config.grid_shape
        entries["map"] = spaces.Box(0, 255, (channels, height, width), np.uint8)
    entries["proprio"] = spaces.Box(-1.0, 1.0, (proprio_len,), np.float32)
    return spaces.Dict(entries)


def action_space(batch: _core.EpisodeBatch) -> spaces.Space[Any]:
    """The action space of one environment of ``batch`` (a ``_core.EpisodeBatch``): the
    ``wrist`` mode's ``Box(-1, 1, (3,))``, or the ``probe`` mode's ``MultiDiscrete`` over the
    core's (lanes, depths, sweeps) counts; where the task claims (``identify``), each with
    the core's claim entry 4th (``Box(-1, 1, (4,))``, ``MultiDiscrete([..., 2])``)."""
    nvec = batch.probe_nvec
    if nvec is None:
        return spaces.Box(-1.0, 1.0, (batch.action_len,), np.float32)
    return spaces.MultiDiscrete(np.asarray(nvec, dtype=np.int64))


#: An observation: the ``map`` image (absent for ``map="none"``) and ``proprio``, by key.
Observation = dict[str, np.ndarray]


class CupboardSearchEnv(
    DeclaredTimeLimit, EpisodeReads, gym.Env[Observation, np.ndarray], EzPickle
):
    """Mechanical search by touch: reach into a cupboard and touch a hidden spice jar.

    ## Description
    A cupboard compartment (0.60 m wide, 0.30 m deep, open at the front) holds 3 to 7 round
    and square spice jars. One of them, the target, stands behind the others so that the
    depth camera in front of the opening sees at most 10 % of it. The agent moves the wrist
    of an Exploratory Hand in the horizontal slice plane; its long finger is compliant (a
    low-stiffness joint), so touching a jar deflects the finger instead of knocking the jar
    over. Each touch yields a contact point and the jar's outward normal. The agent's map is
    a Gaussian Process Implicit Surface (GPIS) built from the camera's first look and
    refined by every touch (paper: "Tactile-visuo Search in Cluttered Spaces").

    ## Action Space
    ``Box(-1, 1, (3,), float32)``: wrist motion per step, scaled by the hand's bounds.

    | index | action | scale (default) |
    |---|---|---|
    | 0 | dx, along the opening | 0.01 m |
    | 1 | dy, into the cupboard | 0.01 m |
    | 2 | dyaw, about the vertical | 0.1 rad |

    Components outside [-1, 1] are clipped (``info["clipped"]``); NaN or infinite actions
    raise ``ValueError``. A motion that would drive the wrist or arm into a wall stops at
    contact (``info["blocked"]``).

    With ``action_mode="probe"`` an action is a probe instead: ``MultiDiscrete([probe_lanes,
    probe_depths, probe_sweeps])`` (their defaults in the table below), a lane across the opening, a
    wrist depth and a sweep angle of the finger. An observation-only controller in the core
    drives the wrist there, leaving and entering the cupboard only straight along a lane,
    and stops at a touch on the way in or while sweeping, never pressing on into a jar the
    finger touches. Every wrist motion it makes is a step of the time limit and of the reward
    (the step's reward is their sum; ``info["motions"]`` counts them). The indices are
    integers (a float action raises ``TypeError``); an index outside
    its count raises ``ValueError``. The same option serves every map mode.

    ## Observation Space
    ``Dict``:

    | key | space | content |
    |---|---|---|
    | ``map`` | ``Box(0, 255, (2, H, W), uint8)`` | the map image (absent for ``map="none"``) |
    | ``proprio`` | ``Box(-1, 1, (11,), float32)`` | proprioception and touch |

    ``map`` channels (from ``tactile_search._core.observation_layout()``):

    {map_channel_table}

    ``proprio`` entries, all in [-1, 1] (from the same table; decoders index them by name,
    ``tactile_search.envs.observation.PROPRIO``):

    {proprio_table}

    Row ``i`` of the map runs along y (into the cupboard), column ``j`` along x; the grid
    covers the cupboard's interior with square cells.

    ## Rewards
    ``r = r_success + r_step + r_displacement + r_tip + r_approach``, each term in ``info``:

    - ``r_success = reward_success`` when the finger touches the target, else 0;
    - ``r_step = -reward_step_cost``;
    - ``r_displacement = -reward_displacement * max(0, D_t - D_{t-1})`` with ``D_t`` the
      planar displacement of all jars from where they stood at reset (m), summed: moving
      jars back towards their start earns nothing back;
    - ``r_tip = -reward_tip`` when a jar tips over (leans more than ``tip_angle``);
    - ``r_approach = reward_approach * (d_{t-1} - d_t)``, shaping by a difference of
      potentials with ``d_t = info["target_distance"]``, the fingertip's path distance to the
      target around the other jars (m). Off by default (``reward_approach = 0``); the
      training recipes in ``agents/hyperparams`` turn it on. It can change which policies
      are optimal: undiscounted, an episode's terms sum to ``reward_approach * (d_0 - d_T)``,
      a bonus for ending nearer the target (the final potential is not zero), and under a
      learner's discounting approach made early is worth more. Among successful episodes
      (``d_T`` near 0 at the touch) the undiscounted bonus is the same whatever the path.

    ## Starting State
    A new seeded layout, the depth camera's first look (a noisy horizontal slice at mid-jar
    height), the GPIS prior from it, and the hand just outside the opening.

    ## Episode End
    - Termination: the finger touches the target (success) or a jar tips over (failure).
    - Truncation: the episode's own time limit, ``max_steps`` steps (default 200): the core
      reports it (``truncated``), so what ``gymnasium.make(..., max_steps=N)`` says is what
      truncates, in the vector envs too, and the made env's ``spec.max_episode_steps`` is
      N (the ids register no limit, so no ``TimeLimit`` wrapper). Gymnasium's
      ``make(..., max_episode_steps=N)`` is the same limit: the env takes N as its
      ``max_steps`` and ``make`` wraps ``TimeLimit`` at N (``envs/time_limit.py``); a
      ``max_steps`` beside it that differs is a ``ValueError``. Stepping on after
      truncation is allowed (``time_left`` goes below 0, floored at -1).

    ## Arguments
    ``render_mode``: ``None`` or ``"rgb_array"``; ``threads`` (see Threads). Then every
    setting of the core, by keyword
    (``gymnasium.make("tactile_search/CupboardSearch-v0", map="occupancy", jar_count=5)``);
    the table below is generated from the core's settings table, so it lists every one with
    its default. A value of the wrong type raises ``TypeError``, one out of range
    ``ValueError``, each naming the argument. ``map`` and ``grid_shape`` shape the
    observation; ``max_steps`` is the time limit.

    {settings_table}

    ## Pickling
    A pickled env carries its settings, its random generator and its episode so far (the
    layout seed and the actions since the reset, 24 bytes a step); unpickling rebuilds the
    env and replays the episode, which the core makes bit-identical, so the copy goes on
    exactly as the original would (replaying costs a step's time per step taken).

    ## Threads
    One env serves one thread at a time: a call while another thread's call on the same
    env is running raises ``RuntimeError`` (the steps would interleave in the scheduler's
    order). Give each thread its own env, or step a vector env from one thread.
    ``threads`` (default 2; 1 on a one-core machine) is how many threads the env's own
    work may use: with two, a reset's approach field and GPIS grid update are shared
    between two pool workers while the calling thread waits, with the same results
    (``python -m benchmarks.peer_envs --variant threads=1`` compares one thread). The
    workers sleep between resets, and where processes already fill the cores they cost
    nothing measurable (``python -m benchmarks.env_threads_side_by_side``); ``threads=1``
    runs everything on the calling thread, ``None`` gives every core.

    ## Version History
    - v0: first release. The ``probe`` action mode is an option (``action_mode``); the
      default ``wrist`` mode is v0's behaviour, unchanged. The vector env
      (``vector_entry_point``) now seeds as gymnasium's ``SyncVectorEnv`` does (sub-env
      ``i`` as ``reset(seed=seed + i)``, each with its own generator; before, one batch
      generator drew every layout) and its info carries the ``_key`` masks; the single
      env's episodes are unchanged. The info's ``truncated`` key is gone (it repeated the
      step's own ``truncated``); ``spec.max_episode_steps`` is the env's ``max_steps``, and
      ``make``'s ``max_episode_steps`` sets it.
    """

    # Declared as gymnasium's Env declares it.
    metadata: dict[str, Any] = {"render_modes": ["rgb_array"], "render_fps": 10}  # noqa: RUF012
    #: The env's episode in its batch of one (``EpisodeReads``).
    _episode_index = 0

    def __init__(
        self, render_mode: str | None = None, threads: int | None = 2, **settings: Any
    ) -> None:
        EzPickle.__init__(self, render_mode=render_mode, threads=threads, **settings)
        if render_mode not in (None, "rgb_array"):
            raise ValueError(f"render_mode must be None or 'rgb_array', got {render_mode!r}")
        self.render_mode = render_mode
        self.config = config_for("CupboardSearchEnv", settings)
        self._batch = self.config.make_batch(1, threads=threads)
        self.observation_space = observation_space(self.config, self._batch.proprio_len)
        self.action_space = action_space(self._batch)
        # The episode so far, for pickling: its layout seed and the actions since its reset.
        self._episode_seed: int | None = None
        # As the core steps them: float64 wrist motions (a float32 action replays exactly),
        # int64 probe indices.
        probe = self._batch.probe_counts is not None
        self._actions = np.empty(
            (0, self._batch.action_len), dtype=np.int64 if probe else np.float64
        )
        self._steps_taken = 0

    def reset(
        self, *, seed: int | None = None, options: dict[str, Any] | None = None
    ) -> tuple[Observation, dict[str, Any]]:
        super().reset(seed=seed)
        # A given seed is the layout's seed (so reset(seed=s) here equals episode i of a
        # vector env reset with seed[i] = s); otherwise draw one from the env's generator.
        episode_seed = seed if seed is not None else int(self.np_random.integers(*seed_ranges.ANY))
        self._batch.reset(0, episode_seed)
        self._episode_seed = episode_seed
        self._steps_taken = 0
        return self._batch.observation(0), self._batch.info(0)

    def step(self, action: Any) -> tuple[Observation, float, bool, bool, dict[str, Any]]:
        if self._episode_seed is None:
            raise ResetNeeded("CupboardSearchEnv: call reset() before step()")
        # One call: the core checks the action once (its shape; finite motions, integer
        # probe indices within their counts; TypeError or ValueError naming what came) and
        # returns fresh observation arrays and an info dict of scalars.
        result = self._batch.step_single(action)
        # Kept for pickling.
        if self._steps_taken == len(self._actions):
            self._grow_actions()
        self._actions[self._steps_taken] = action
        self._steps_taken += 1
        return result

    def _remake_with_max_steps(self, max_steps: int) -> None:
        """Builds the env again with the arguments it was made with (EzPickle keeps them for
        pickling), ``max_steps`` over them: ``gymnasium.make``'s ``max_episode_steps``
        (``DeclaredTimeLimit``)."""
        CupboardSearchEnv.__init__(self, **{**self._ezpickle_kwargs, "max_steps": max_steps})

    def _grow_actions(self) -> None:
        """Doubles the storage of the episode's actions."""
        rows = max(2 * len(self._actions), 64)
        grown = np.empty((rows, self._actions.shape[1]), dtype=self._actions.dtype)
        grown[: self._steps_taken] = self._actions[: self._steps_taken]
        self._actions = grown

    def __getstate__(self) -> dict[str, Any]:
        state: dict[str, Any] = EzPickle.__getstate__(self)
        state["np_random"] = self._np_random
        state["episode_seed"] = self._episode_seed
        state["actions"] = self._actions[: self._steps_taken].copy()
        return state

    def __setstate__(self, state: dict[str, Any]) -> None:
        state = dict(state)
        np_random = state.pop("np_random", None)
        episode_seed = state.pop("episode_seed", None)
        actions = state.pop("actions", ())
        EzPickle.__setstate__(self, state)
        self._np_random = np_random
        if episode_seed is not None:
            self._batch.reset(0, episode_seed)
            self._episode_seed = episode_seed
            for action in actions:
                self.step(action)

    def render(self) -> np.ndarray | None:  # type: ignore[override]  # gymnasium's TypeVar
        """The scene from above beside the map, as an RGB array, in the ``rgb_array`` mode
        (drawn with numpy alone). Without a render mode it warns and returns None
        (gymnasium's convention)."""
        if self.render_mode is None:
            gym.logger.warn(
                "You are calling render() without a render mode: make the env with "
                "render_mode='rgb_array' to get frames."
            )
            return None
        return episode_frame(self._batch, self._episode_index)


CupboardSearchEnv.__doc__ = fill_docstring(CupboardSearchEnv.__doc__ or "")
with_settings_signature(CupboardSearchEnv.__init__)
