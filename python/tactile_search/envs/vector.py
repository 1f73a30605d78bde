"""The batched ``CupboardSearch-v0``: N episodes stepped in parallel in Rust.

``gymnasium.make_vec("tactile_search/CupboardSearch-v0", num_envs=N,
vectorization_mode="vector_entry_point")``. It behaves as gymnasium's ``SyncVectorEnv`` of N
``gymnasium.make`` envs would, bit for bit (``tests/test_vector_equivalence.py``):

- ``reset(seed=s)`` resets sub-env ``i`` as ``reset(seed=s + i)`` resets the single env (a
  list gives each its seed; ``None`` draws); each sub-env keeps its own generator, seeded by
  its seed, and draws its later episodes' layouts from it;
- the info carries, beside each key's array, its ``_key`` mask (which sub-envs report it);
- ``reset(options={"reset_mask": mask})`` resets only the masked sub-envs;
- ``autoreset_mode``: ``NEXT_STEP`` (the default: the step after an episode ends resets
  it and returns its first observation with reward 0 and both flags False, its action
  ignored; the reset runs in the same parallel call as the others' steps), ``SAME_STEP``
  (the step that ends an episode resets it and returns its last observation and info in
  ``info["final_obs"]`` and ``info["final_info"]``) or ``DISABLED`` (the caller resets
  ended episodes with ``reset_mask``);
- ``render_mode="rgb_array"``: ``render()`` returns every sub-env's frame;
- pickling carries the settings, the generators and the episodes so far.

Truncation is the core's: an episode truncates when its steps reach ``max_steps``, which
``spec.max_episode_steps`` declares (``envs/time_limit.py``).

The step path: the core writes observations, rewards, flags and the info (one array per
key, never per-env dicts) into arrays allocated once per batch. With ``copy=True`` (the
default, like gymnasium's own vector envs) each step returns fresh copies of them; with
``copy=False`` it returns the batch's own arrays, which the next step overwrites.
"""

from __future__ import annotations

import functools
import numbers
from collections.abc import Sequence
from typing import Any

import numpy as np
from gymnasium.error import ClosedEnvironmentError, ResetNeeded
from gymnasium.utils import seeding
from gymnasium.vector import AutoresetMode, VectorEnv
from gymnasium.vector.utils import batch_space

from tactile_search import seed_ranges
from tactile_search.envs.config import (
    checked_layout_seeds,
    config_for,
    with_settings_signature,
)
from tactile_search.envs.cupboard_search import (
    CupboardSearchEnv,
    Observation,
    action_space,
    observation_space,
)
from tactile_search.envs.episode_log import EpisodeLog
from tactile_search.envs.sub_env import SubEnv
from tactile_search.envs.time_limit import DeclaredTimeLimit, max_steps_of
from tactile_search.render import episode_frame

#: The layout-seed range of ``gymnasium.make``'s env: its ``reset()`` draws from it.
SINGLE_ENV_LAYOUT_SEEDS = seed_ranges.ANY


def observation_dict(maps: np.ndarray | None, proprio: np.ndarray) -> dict[str, np.ndarray]:
    """The observation dict of the batch's arrays (no ``map`` in the ``none`` mode)."""
    return {"proprio": proprio} if maps is None else {"proprio": proprio, "map": maps}


def with_masks(
    info: dict[str, np.ndarray], mask: np.ndarray | None = None, copy: bool = True
) -> dict[str, np.ndarray]:
    """``info`` with gymnasium's ``_key`` mask beside each key: ``mask`` (which sub-envs
    report it; None: all), the values of the others zeroed, as ``SyncVectorEnv`` leaves
    them. The values are copies unless ``copy`` is False and every sub-env reports.

    Every step passes here, so when every sub-env reports, all keys share one fresh
    all-True mask (a write of True through any ``_key``, as ``VectorEnv._add_info`` makes,
    changes nothing; 27 separate arrays would cost a tenth of a wrist step's time)."""
    keys = tuple(info)
    if mask is None or mask.all():
        values = [value.copy() for value in info.values()] if copy else info.values()
        out = dict(zip(keys, values, strict=True))
        out.update(dict.fromkeys(mask_keys(keys), np.ones(len(out[keys[0]]), dtype=bool)))
        return out
    values = [
        np.where(mask.reshape(-1, *[1] * (value.ndim - 1)), value, 0).astype(value.dtype)
        for value in info.values()
    ]
    out = dict(zip(keys, values, strict=True))
    out.update(zip(mask_keys(keys), np.repeat(mask[np.newaxis], len(keys), axis=0), strict=True))
    return out


@functools.cache
def mask_keys(keys: tuple[str, ...]) -> tuple[str, ...]:
    """The ``_key`` names of ``keys`` (the info's keys are the core's, fixed)."""
    return tuple(f"_{key}" for key in keys)


class CupboardSearchVectorEnv(DeclaredTimeLimit, VectorEnv[Observation, np.ndarray, np.ndarray]):
    """``num_envs`` cupboard-search episodes stepped on all cores (see ``CupboardSearchEnv``
    and the module docstring).

    Args:
        num_envs: number of episodes.
        threads: worker threads (default: every core).
        copy: return fresh arrays each step (True) or the batch's own arrays, overwritten
            by the next step (False; saves a copy of every output per step).
        layout_seeds: ``[low, high)``, the range the sub-envs' generators draw layout seeds
            from; a seed given to ``reset`` inside it is the layout's seed, one outside it
            seeds the generator that draws it. The default is the single env's range, the
            one for which the vector env equals ``SyncVectorEnv``; keep training out of the
            validation and test ranges with ``tactile_search.seed_ranges.TRAINING``.
        render_mode: ``None`` or ``"rgb_array"`` (``render()`` returns each sub-env's frame).
        autoreset_mode: ``"next_step"`` (default), ``"same_step"`` or ``"disabled"`` (or
            the ``gymnasium.vector.AutoresetMode`` member or value).
        max_episode_steps: gymnasium's name of the time limit, ``max_steps``:
            ``gymnasium.make_vec`` passes a spec's declared limit under it (so
            ``make_vec(vector.spec)`` re-makes this env). Beside ``max_steps`` it must agree.
        **kwargs: the fields of ``CupboardSearchConfig`` (``max_steps`` is the time limit).
    """

    # Declared as gymnasium's VectorEnv declares it: a class default an instance replaces.
    metadata: dict[str, Any] = {  # noqa: RUF012
        "autoreset_mode": AutoresetMode.NEXT_STEP,
        "render_modes": CupboardSearchEnv.metadata["render_modes"],
        "render_fps": CupboardSearchEnv.metadata["render_fps"],
    }

    def __init__(
        self,
        num_envs: int = 2,
        threads: int | None = None,
        copy: bool = True,
        layout_seeds: tuple[int, int] = SINGLE_ENV_LAYOUT_SEEDS,
        render_mode: str | None = None,
        autoreset_mode: str | AutoresetMode = AutoresetMode.NEXT_STEP,
        max_episode_steps: int | None = None,
        **kwargs: Any,
    ) -> None:
        if max_episode_steps is not None:
            kwargs["max_steps"] = max_steps_of(max_episode_steps, kwargs.get("max_steps"))
        if isinstance(num_envs, bool) or not isinstance(num_envs, int):
            raise TypeError(f"num_envs must be an int, got {type(num_envs).__name__}")
        if num_envs < 1:
            raise ValueError(f"num_envs must be >= 1, got {num_envs}")
        if render_mode not in (None, *self.metadata["render_modes"]):
            raise ValueError(f"render_mode must be None or 'rgb_array', got {render_mode!r}")
        self._arguments = {
            "num_envs": num_envs, "threads": threads, "copy": copy,
            "layout_seeds": layout_seeds, "render_mode": render_mode,
            "autoreset_mode": autoreset_mode, **kwargs,
        }  # fmt: skip
        self.autoreset_mode = checked_autoreset_mode(autoreset_mode)
        self.metadata = {**type(self).metadata, "autoreset_mode": self.autoreset_mode}
        self.render_mode = render_mode
        self.layout_seeds = checked_layout_seeds(layout_seeds)
        self.num_envs = num_envs
        self.copy = bool(copy)
        self.config = config_for("CupboardSearchVectorEnv", kwargs)
        self._batch = self.config.make_batch(num_envs, threads=threads)
        self.single_observation_space = observation_space(self.config, self._batch.proprio_len)
        self.single_action_space = action_space(self._batch)
        self.observation_space = batch_space(self.single_observation_space, num_envs)
        self.action_space = batch_space(self.single_action_space, num_envs)
        self._generators: list[np.random.Generator | None] = [None] * num_envs
        self._generator_seeds: list[int | None] = [None] * num_envs
        self._needs_reset = np.zeros(num_envs, dtype=bool)
        # The actions as the core steps them: float64 wrist motions (a float32 action
        # replays exactly), int64 probe indices.
        probe = self._batch.probe_counts is not None
        self._log = EpisodeLog(num_envs, np.int64 if probe else np.float64, self._batch.action_len)
        self._all_reset = False  # every sub-env reset at least once
        # The step's info with its masks, the batch's own arrays (copy=False: built once).
        self._mask_keys = mask_keys(tuple(self._batch.info_arrays()))
        self._masked_info: dict[str, np.ndarray] | None = None

    # ---- generators ----------------------------------------------------------------------
    # Per sub-env, as gymnasium's SyncVectorEnv gives them (its VectorEnv types one).
    @property  # type: ignore[misc]
    def np_random(self) -> tuple[np.random.Generator, ...]:  # type: ignore[override]
        """Each sub-env's generator (made from OS entropy if it was never seeded)."""
        return tuple(self._generator(i) for i in range(self.num_envs))

    @property
    def np_random_seed(self) -> tuple[int, ...]:  # type: ignore[override]
        """Each sub-env's generator seed (-1 until ``reset`` made its generator)."""
        return tuple(-1 if seed is None else seed for seed in self._generator_seeds)

    def _generator(self, index: int) -> np.random.Generator:
        if self._generators[index] is None:
            self._seed(index, None)
        return self._generators[index]  # type: ignore[return-value]

    def _seed(self, index: int, seed: int | None) -> None:
        self._generators[index], self._generator_seeds[index] = seeding.np_random(seed)

    def _draw_layout(self, index: int) -> int:
        """The next layout seed from sub-env ``index``'s generator (the single env's draw)."""
        low, high = self.layout_seeds
        # int64 draws while the range fits them (the single env's range does).
        dtype = np.int64 if high <= seed_ranges.ANY[1] else np.uint64
        return int(self._generator(index).integers(low, high, dtype=dtype))

    def _layout(self, index: int, seed: int | None) -> int:
        """The layout of sub-env ``index``'s next episode: drawn from its generator (``seed``
        None), else that of a reset with ``seed`` (which reseeds the generator)."""
        if seed is None:
            return self._draw_layout(index)
        self._seed(index, seed)
        low, high = self.layout_seeds
        return seed if low <= seed < high else self._draw_layout(index)

    # ---- reset ---------------------------------------------------------------------------
    def reset(
        self,
        *,
        seed: int | Sequence[int | None] | None = None,
        options: dict[str, Any] | None = None,
    ) -> tuple[Observation, dict[str, Any]]:
        self._check_open()
        seeds = self._reset_seeds(seed)
        mask = self._reset_mask(options)
        resets = [(i, self._layout(i, seeds[i])) for i in np.flatnonzero(mask).tolist()]
        self._batch.reset_many(resets)
        self._log.began(resets)
        self._needs_reset[mask] = False
        observation = observation_dict(*self._batch.observe())
        return self._out(observation), with_masks(self._batch.info_arrays(), mask)

    def _reset_seeds(self, seed: Any) -> list[int | None]:
        """Each sub-env's seed, as ``SyncVectorEnv`` spreads them."""
        if seed is None:
            return [None] * self.num_envs
        if isinstance(seed, numbers.Integral) and not isinstance(seed, bool):
            return [int(seed) + i for i in range(self.num_envs)]
        if not isinstance(seed, (list, tuple, np.ndarray)):
            raise TypeError(
                f"seed must be None, an int or a list of {self.num_envs} ints, "
                f"got {type(seed).__name__}"
            )
        if len(seed) != self.num_envs:
            raise ValueError(f"seed must be a list of {self.num_envs} ints, got {len(seed)}")
        seeds = []
        for s in seed:
            if s is not None and (isinstance(s, bool) or not isinstance(s, numbers.Integral)):
                raise TypeError(f"each seed must be an int or None, got {s!r}")
            seeds.append(None if s is None else int(s))
        return seeds

    def _reset_mask(self, options: dict[str, Any] | None) -> np.ndarray:
        """Which sub-envs reset: ``options["reset_mask"]`` (a bool array of ``num_envs``
        with at least one True), or all."""
        if options is None or "reset_mask" not in options:
            return np.ones(self.num_envs, dtype=bool)
        mask = options["reset_mask"]
        if not isinstance(mask, np.ndarray) or mask.dtype != np.bool_:
            raise TypeError(
                f"options['reset_mask'] must be a numpy bool array, got "
                f"{getattr(mask, 'dtype', type(mask).__name__)}"
            )
        if mask.shape != (self.num_envs,):
            raise ValueError(
                f"options['reset_mask'] must have shape ({self.num_envs},), got {mask.shape}"
            )
        if not mask.any():
            raise ValueError("options['reset_mask'] must have at least one True value")
        return np.array(mask, dtype=np.bool_)  # a copy

    # ---- step ----------------------------------------------------------------------------
    def step(
        self, actions: Any
    ) -> tuple[Observation, np.ndarray, np.ndarray, np.ndarray, dict[str, Any]]:
        self._check_steppable(actions)
        resets = None
        generator_states = []
        if self.autoreset_mode == AutoresetMode.NEXT_STEP and self._needs_reset.any():
            # Most steps reset nothing: skip the numpy calls then.
            resetting = np.flatnonzero(self._needs_reset).tolist()
            generator_states = [(i, self._generator(i).bit_generator.state) for i in resetting]
            resets = [(i, self._layout(i, None)) for i in resetting]
        try:
            maps, proprio, rewards, terminated, truncated, info = self._batch.step(actions, resets)
        except Exception:
            # A step the core refuses (bad actions) changes nothing: the seeds drawn for
            # these resets are drawn again by the next step.
            for index, state in generator_states:
                self._generator(index).bit_generator.state = state
            raise
        self._log.stepped(actions, resets)
        self._needs_reset = terminated | truncated
        if self.autoreset_mode == AutoresetMode.SAME_STEP and self._needs_reset.any():
            return self._same_step_resets(rewards, terminated, truncated, info)
        observation = observation_dict(maps, proprio)
        info = self._step_info(info)
        if self.copy:
            return (
                self._out(observation), rewards.copy(), terminated.copy(), truncated.copy(),
                info,
            )  # fmt: skip
        return observation, rewards, terminated, truncated, info

    def _step_info(self, info: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
        """A step's info where every sub-env reports: ``with_masks``'s, on the hot path
        (copies of the values and one fresh all-True mask; with ``copy=False`` the batch's
        own arrays and a mask made once, in a new dict each step)."""
        if self.copy:
            out = {key: value.copy() for key, value in info.items()}
            out.update(dict.fromkeys(self._mask_keys, np.ones(self.num_envs, dtype=bool)))
            return out
        if self._masked_info is None:
            self._masked_info = with_masks(info, copy=False)
        return dict(self._masked_info)

    def _check_open(self) -> None:
        """``ClosedEnvironmentError`` after ``close()`` (gymnasium's ``closed`` flag, set by
        ``VectorEnv.close``, which stays idempotent), as gymnasium's ``AsyncVectorEnv``
        refuses a closed env."""
        if self.closed:
            raise ClosedEnvironmentError(
                f"{type(self).__name__} is closed (close() was called): make a new one"
            )

    def _check_steppable(self, actions: Any) -> None:
        """``ClosedEnvironmentError`` after ``close()``; ``ResetNeeded`` before every
        sub-env's first reset; ``TypeError`` for actions that are not an array of them; in
        the ``DISABLED`` mode, ``ResetNeeded`` while an ended episode waits for its reset.
        (The core checks the shape and values.)"""
        self._check_open()
        if not self._all_reset:
            self._all_reset = all(seed is not None for seed in self._log.seeds)
            if not self._all_reset:
                never = [i for i, seed in enumerate(self._log.seeds) if seed is None]
                raise ResetNeeded(f"sub-envs {never} were never reset: call reset() before step()")
        if not isinstance(actions, np.ndarray) or actions.ndim == 0:
            scalar = isinstance(actions, numbers.Number) or getattr(actions, "ndim", None) == 0
            if scalar or isinstance(actions, str | bytes | dict):
                raise TypeError(
                    f"actions must be an array of shape {self.action_space.shape}, "
                    f"got {type(actions).__name__}"
                )
        if self.autoreset_mode is AutoresetMode.DISABLED and self._needs_reset.any():
            ended = np.flatnonzero(self._needs_reset).tolist()
            raise ResetNeeded(
                f"sub-envs {ended} ended and autoreset_mode is DISABLED: reset them with "
                "reset(options={'reset_mask': mask}) before stepping"
            )

    def _same_step_resets(
        self, rewards: np.ndarray, terminated: np.ndarray, truncated: np.ndarray,
        step_info: dict[str, np.ndarray],
    ) -> tuple[Observation, np.ndarray, np.ndarray, np.ndarray, dict[str, Any]]:  # fmt: skip
        """The ``SAME_STEP`` mode's end of a step where episodes ended: their last
        observation and info into ``final_obs`` / ``final_info``, then their resets."""
        ended = np.flatnonzero(self._needs_reset).tolist()
        maps, proprio = self._batch.observe()
        finals: dict[str, Any] = {}
        for index in ended:
            final_obs = {
                key: value[index].copy() for key, value in observation_dict(maps, proprio).items()
            }
            final_info = {key: value[index].item() for key, value in step_info.items()}
            finals = self._add_info(
                finals, {"final_obs": final_obs, "final_info": final_info}, index
            )
        rewards, terminated, truncated = rewards.copy(), terminated.copy(), truncated.copy()
        resets = [(i, self._layout(i, None)) for i in ended]
        self._batch.reset_many(resets)
        self._log.began(resets)
        self._needs_reset[:] = False
        observation = observation_dict(*self._batch.observe())
        info = with_masks(self._batch.info_arrays())
        return self._out(observation), rewards, terminated, truncated, {**info, **finals}

    def _out(self, arrays: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
        """``arrays`` as returned: copies unless ``copy=False``."""
        if self.copy:
            return {key: value.copy() for key, value in arrays.items()}
        return dict(arrays)

    # ---- render, scripted actions, pickling ----------------------------------------------
    def render(self) -> tuple[np.ndarray, ...] | None:  # type: ignore[override]  # as above
        """Each sub-env's frame (the scene from above beside its map) in the ``rgb_array``
        mode; None without a render mode."""
        if self.render_mode is None:
            return None
        return tuple(episode_frame(self._batch, i) for i in range(self.num_envs))

    def sub_env(self, index: int) -> SubEnv:
        """Episode ``index`` with the single env's read-only methods (``envs/sub_env.py``)."""
        return SubEnv(self, index)

    def oracle_actions(self) -> np.ndarray:
        """Actions ``(num_envs, 3)`` of a scripted searcher that knows each target."""
        return self._batch.oracle_actions().astype(np.float32)

    def __getstate__(self) -> dict[str, Any]:
        return {
            "arguments": self._arguments,
            "generators": self._generators,
            "generator_seeds": self._generator_seeds,
            "needs_reset": self._needs_reset.copy(),
            "log": self._log,
        }

    def __setstate__(self, state: dict[str, Any]) -> None:
        self.__init__(**state["arguments"])  # type: ignore[misc]
        self._generators = state["generators"]
        self._generator_seeds = state["generator_seeds"]
        self._log = state["log"]
        self._log.replay(self._batch)
        self._needs_reset = state["needs_reset"]


def checked_autoreset_mode(mode: Any) -> AutoresetMode:
    """``mode`` as an ``AutoresetMode``: the member, its value (``"NextStep"``) or its name
    in any case (``"next_step"``); else ``ValueError`` naming the choices."""
    if isinstance(mode, AutoresetMode):
        return mode
    for member in AutoresetMode:
        if isinstance(mode, str) and mode.lower() in (member.value.lower(), member.name.lower()):
            return member
    names = ", ".join(repr(m.name.lower()) for m in AutoresetMode)
    raise ValueError(
        f"autoreset_mode of CupboardSearchVectorEnv must be one of {names}, got {mode!r}"
    )


with_settings_signature(CupboardSearchVectorEnv.__init__)
