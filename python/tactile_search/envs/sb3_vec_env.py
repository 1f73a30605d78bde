"""``CupboardSearchSb3VecEnv``: the Rust episode batch as a stable-baselines3 ``VecEnv``.

stable-baselines3 does not take a gymnasium ``VectorEnv``; its ``VecEnv`` resets an episode
in the same step that ends it, returns the new episode's first observation, and keeps the
last one in ``infos[i]["terminal_observation"]`` (with ``"TimeLimit.truncated"`` set when
the time limit ended it, and ``"is_success"``, which SB3 logs as ``rollout/success_rate``).
This adapter gives the batch exactly those semantics, so SB3 trains on all cores:
``PPO("MultiInputPolicy", CupboardSearchSb3VecEnv(num_envs=8))``.
The time limit is the core's (``max_steps``). A step is one call into the core
(``EpisodeBatch.step_autoreset``): it steps every episode, starts the ended ones over on the
next layout seeds and returns fresh observation arrays (SB3 keeps the previous step's
observation while it takes the next) with SB3's per-env info dicts built in Rust. The
layout seeds come from one generator, drawn in order as episodes end.
``render_mode="rgb_array"`` renders each episode's frame (SB3 tiles them;
``VecVideoRecorder`` records them). ``get_attr`` and ``env_method`` reach each
episode as SB3 reaches a sub-env: ``env_method("reset", indices=[1])`` resets episode 1
alone. The env pickles with its settings, generator and episodes so far; after ``close()``
it refuses ``reset`` and stepping (``gymnasium.error.ClosedEnvironmentError``). Needs the
``agents`` extra (stable-baselines3).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np
from gymnasium.error import ClosedEnvironmentError

try:
    from stable_baselines3.common.vec_env.base_vec_env import VecEnv
except ModuleNotFoundError as error:
    raise ModuleNotFoundError(
        "tactile_search.envs.sb3_vec_env needs stable-baselines3, which is not installed: "
        "pip install 'tactile_search[agents]'",
        name=error.name,
    ) from error

from tactile_search.envs.config import (
    checked_layout_seeds,
    config_for,
    with_settings_signature,
)
from tactile_search.envs.cupboard_search import (
    CupboardSearchEnv,
    action_space,
    observation_space,
)
from tactile_search.envs.episode_log import EpisodeLog
from tactile_search.envs.vector import SINGLE_ENV_LAYOUT_SEEDS, observation_dict
from tactile_search.render import episode_frame


class CupboardSearchSb3VecEnv(VecEnv):
    """``num_envs`` cupboard-search episodes for stable-baselines3 (see ``CupboardSearchEnv``).

    Args:
        num_envs: number of episodes.
        seed: seed of the generator that draws each new episode's layout seed.
        layout_seeds: ``[low, high)``, the range layout seeds are drawn from (keep training
            out of the ranges evaluation holds out: ``tactile_search.seed_ranges.TRAINING``,
            as ``agents.train`` does).
        threads: worker threads (default: every core).
        render_mode: ``None`` or ``"rgb_array"`` (``get_images()`` returns each episode's
            frame: the scene from above beside its map).
        **kwargs: the fields of ``CupboardSearchConfig`` (``max_steps`` is the time limit).
    """

    def __init__(
        self,
        num_envs: int = 2,
        seed: int | None = None,
        layout_seeds: tuple[int, int] = SINGLE_ENV_LAYOUT_SEEDS,
        threads: int | None = None,
        render_mode: str | None = None,
        **kwargs: Any,
    ) -> None:
        if isinstance(num_envs, bool) or not isinstance(num_envs, int) or num_envs < 1:
            raise ValueError(f"num_envs must be a positive int, got {num_envs!r}")
        if render_mode not in (None, *CupboardSearchEnv.metadata["render_modes"]):
            raise ValueError(f"render_mode must be None or 'rgb_array', got {render_mode!r}")
        self._arguments = {
            "num_envs": num_envs, "seed": seed, "layout_seeds": layout_seeds,
            "threads": threads, "render_mode": render_mode, **kwargs,
        }  # fmt: skip
        self.layout_seeds = checked_layout_seeds(layout_seeds)
        self.config = config_for("CupboardSearchSb3VecEnv", kwargs)
        self._rng = np.random.default_rng(seed)
        # Seeds drawn from ``_rng`` but not yet used, in the order they were drawn: a step
        # hands the core the next ``num_envs`` and takes off those its ended episodes used.
        self._drawn_seeds: list[int] = []
        # The generator's first num_envs draws are passed over: the adapter once started its
        # episodes on them at construction, and skipping them keeps the layouts that a seed
        # gives (and so a seed's training run) what they were.
        self._new_seeds(num_envs)
        self._batch = self.config.make_batch(num_envs, threads=threads)
        probe = self._batch.probe_counts is not None
        self._log = EpisodeLog(num_envs, np.int64 if probe else np.float64, self._batch.action_len)
        self.render_mode = render_mode
        self._sub_envs = [EpisodeView(self, index) for index in range(num_envs)]
        super().__init__(
            num_envs,
            observation_space(self.config, self._batch.proprio_len),
            action_space(self._batch),
        )
        self._actions: Any = np.zeros((num_envs, self._batch.action_len))
        #: Set by ``close()``: the env then refuses ``reset`` and stepping.
        self.closed = False

    def _next_seeds(self, count: int) -> list[int]:
        """The next ``count`` layout seeds of the generator, left unused (the generator's
        draws in one call or several are the same stream)."""
        if len(self._drawn_seeds) < count:
            low, high = self.layout_seeds
            draws = self._rng.integers(
                low, high, size=count - len(self._drawn_seeds), dtype=np.uint64
            )
            self._drawn_seeds += [int(s) for s in draws]
        return self._drawn_seeds[:count]

    def _new_seeds(self, count: int) -> list[int]:
        """The next ``count`` layout seeds, used."""
        seeds = self._next_seeds(count)
        del self._drawn_seeds[:count]
        return seeds

    def seed(self, seed: int | None = None) -> Sequence[int | None]:
        self._rng = np.random.default_rng(seed)
        self._drawn_seeds = []
        return [seed] * self.num_envs

    def _check_open(self) -> None:
        """``ClosedEnvironmentError`` (gymnasium's, as its vector envs raise) after
        ``close()``."""
        if self.closed:
            raise ClosedEnvironmentError(
                f"{type(self).__name__} is closed (close() was called): make a new one"
            )

    def reset(self) -> dict[str, np.ndarray]:
        self._check_open()
        self._reset_episodes(list(enumerate(self._new_seeds(self.num_envs))))
        return self._observation()

    def _reset_episodes(self, resets: list[tuple[int, int]]) -> None:
        """Episodes ``i`` begin anew on layouts ``seed`` (``(i, seed)`` pairs)."""
        self._check_open()
        self._batch.reset_many(resets)
        self._log.began(resets)

    def _observation(self) -> dict[str, np.ndarray]:
        """A copy of the batch's observation arrays (the batch overwrites its own)."""
        return {k: v.copy() for k, v in observation_dict(*self._batch.observe()).items()}

    def step_async(self, actions: np.ndarray) -> None:
        self._check_open()
        self._actions = actions  # checked once, by the core, in step_wait

    def step_wait(
        self,
    ) -> tuple[dict[str, np.ndarray], np.ndarray, np.ndarray, list[dict[str, Any]]]:
        self._check_open()
        observation, rewards, dones, infos = self._batch.step_autoreset(
            self._actions, self._next_seeds(self.num_envs)
        )
        self._log.stepped(self._actions)
        ended = np.flatnonzero(dones).tolist()
        if ended:
            self._log.began(list(zip(ended, self._new_seeds(len(ended)), strict=True)))
        return observation, rewards, dones, infos

    def close(self) -> None:
        """Marks the env closed (again: no-op): ``reset`` and stepping then raise."""
        self.closed = True

    # ---- render ------------------------------------------------------------------------
    def get_images(self) -> Sequence[np.ndarray | None]:
        """Each episode's frame in the ``rgb_array`` mode (SB3's ``render()`` tiles them)."""
        return [sub_env.render() for sub_env in self._sub_envs]

    # ---- the sub-envs, as SB3 reaches them -----------------------------------------------
    def get_attr(self, attr_name: str, indices: Any = None) -> list[Any]:
        return [getattr(self._sub_envs[i], attr_name) for i in self._indices(indices)]

    def set_attr(self, attr_name: str, value: Any, indices: Any = None) -> None:
        chosen = sorted(set(self._indices(indices)))
        if chosen != list(range(self.num_envs)):
            raise ValueError(
                f"set_attr({attr_name!r}) must set every episode (indices=None): the "
                f"episodes share their settings, got indices {chosen}"
            )
        setattr(self, attr_name, value)

    def env_method(self, method_name: str, *args: Any, indices: Any = None, **kw: Any) -> list[Any]:
        return [
            getattr(self._sub_envs[i], method_name)(*args, **kw) for i in self._indices(indices)
        ]

    def env_is_wrapped(self, wrapper_class: type, indices: Any = None) -> list[bool]:
        return [False for _ in self._indices(indices)]

    def _indices(self, indices: Any) -> list[int]:
        chosen = list(self._get_indices(indices))
        for index in chosen:
            if isinstance(index, bool) or not isinstance(index, int | np.integer):
                raise TypeError(f"indices must be ints, got {index!r}")
            if not 0 <= index < self.num_envs:
                raise ValueError(f"indices must be 0 to {self.num_envs - 1}, got {index}")
        return [int(index) for index in chosen]

    # ---- pickling ----------------------------------------------------------------------
    def __getstate__(self) -> dict[str, Any]:
        return {
            "arguments": self._arguments, "rng": self._rng, "log": self._log,
            "drawn_seeds": self._drawn_seeds,
        }  # fmt: skip

    def __setstate__(self, state: dict[str, Any]) -> None:
        self.__init__(**state["arguments"])  # type: ignore[misc]
        self._rng = state["rng"]
        self._drawn_seeds = list(state.get("drawn_seeds", []))
        self._log = state["log"]
        self._log.replay(self._batch)


class EpisodeView:
    """Episode ``index`` of a ``CupboardSearchSb3VecEnv`` as ``get_attr`` and ``env_method``
    reach a sub-env: its own ``reset`` and ``render``; every other attribute is the
    batch's, shared by all its episodes (settings, spaces, ``render_mode``)."""

    def __init__(self, vec_env: CupboardSearchSb3VecEnv, index: int) -> None:
        self._vec_env = vec_env
        self.index = index

    @property
    def layout_seed(self) -> int | None:
        """The seed of the layout this episode plays."""
        return self._vec_env._log.seeds[self.index]

    def reset(
        self, *, seed: int | None = None, options: dict[str, Any] | None = None
    ) -> tuple[dict[str, np.ndarray], dict[str, Any]]:
        """Begins this episode anew, on layout ``seed`` (else one drawn as ``reset`` draws)
        and returns its first observation and info, as a gymnasium env's ``reset`` does."""
        if seed is not None and (isinstance(seed, bool) or not isinstance(seed, int)):
            raise TypeError(f"seed must be an int or None, got {type(seed).__name__}")
        vec_env = self._vec_env
        layout = vec_env._new_seeds(1)[0] if seed is None else seed
        vec_env._reset_episodes([(self.index, layout)])
        observation = vec_env._observation()
        row = {key: value[self.index] for key, value in observation.items()}
        return row, vec_env._batch.infos()[self.index]

    def render(self) -> np.ndarray | None:
        """This episode's frame in the ``rgb_array`` mode; None without a render mode."""
        vec_env = self._vec_env
        if vec_env.render_mode is None:
            return None
        return episode_frame(vec_env._batch, self.index)

    def __getattr__(self, name: str) -> Any:
        if name == "_vec_env":  # not yet set (a copy being built)
            raise AttributeError(name)
        return getattr(self._vec_env, name)


with_settings_signature(CupboardSearchSb3VecEnv.__init__)
