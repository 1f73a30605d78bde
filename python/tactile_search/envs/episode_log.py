"""``EpisodeLog``: the episodes a batch of N slots holds, kept as each slot's layout seed and
the actions it took since its reset, so that a pickled vector env can rebuild its batch.

The core makes an episode a pure function of its layout seed and its actions, so replaying
them into a fresh batch gives back every slot bit for bit (``replay``). The log holds one
row of N actions per batch step; rows older than the oldest running episode are dropped
when the log fills, so its size follows the longest episode, not the run.
"""

from __future__ import annotations

from typing import Any

import numpy as np

#: Rows the log starts with (it doubles when every row belongs to a running episode).
INITIAL_ROWS = 64


class EpisodeLog:
    """Each slot's layout seed and the actions of its episode so far."""

    def __init__(self, num_envs: int, dtype: Any, action_len: int) -> None:
        self.seeds: list[int | None] = [None] * num_envs  # None: the slot was never reset
        self._start = np.zeros(num_envs, dtype=np.int64)  # each episode's first row
        self._rows = np.zeros((INITIAL_ROWS, num_envs, action_len), dtype=dtype)
        self._count = 0

    def began(self, resets: list[tuple[int, int]]) -> None:
        """Slots ``i`` began new episodes on layouts ``seed`` (``(i, seed)`` pairs), after
        every row logged so far."""
        for index, seed in resets:
            self.seeds[index] = seed
            self._start[index] = self._count

    def stepped(self, actions: Any, resets: list[tuple[int, int]] | None = None) -> None:
        """One batch step: the slots in ``resets`` began new episodes (their action ignored),
        the others took their row of ``actions`` (``(N, action_len)``)."""
        if self._count == len(self._rows):
            self._make_room()
        self._rows[self._count] = actions
        self._count += 1
        if resets:
            self.began(resets)

    def _make_room(self) -> None:
        """Drops the rows no running episode needs; doubles the log if that frees none."""
        first = int(self._start.min())
        kept = self._rows[first : self._count]
        if first == 0:
            grown = np.zeros((2 * len(self._rows), *self._rows.shape[1:]), self._rows.dtype)
            grown[: len(kept)] = kept
            self._rows = grown
        else:
            self._rows[: len(kept)] = kept
        self._start -= first
        self._count -= first

    def episodes(self) -> list[tuple[int | None, np.ndarray]]:
        """Per slot, its layout seed and its actions since the reset, ``(steps,
        action_len)``."""
        return [
            (seed, self._rows[start : self._count, index].copy())
            for index, (seed, start) in enumerate(zip(self.seeds, self._start, strict=True))
        ]

    def __getstate__(self) -> dict[str, Any]:
        # Only the rows running episodes need, not the log's spare capacity.
        first = int(self._start.min())
        return {
            "seeds": self.seeds,
            "start": self._start - first,
            "rows": self._rows[first : self._count].copy(),
        }

    def __setstate__(self, state: dict[str, Any]) -> None:
        self.seeds = state["seeds"]
        self._start = state["start"]
        rows = state["rows"]
        self._rows = np.zeros((max(INITIAL_ROWS, 2 * len(rows)), *rows.shape[1:]), rows.dtype)
        self._rows[: len(rows)] = rows
        self._count = len(rows)

    def replay(self, batch: Any) -> None:
        """Brings ``batch`` (a ``_core.EpisodeBatch`` of the same settings and size) to the
        logged episodes: every slot resets on its layout, then the batch steps as many times
        as the longest episode took, each slot holding (left untouched) until as many steps
        are left as its episode took."""
        episodes = self.episodes()
        batch.reset_many([(i, seed) for i, (seed, _) in enumerate(episodes) if seed is not None])
        longest = max((len(actions) for seed, actions in episodes if seed is not None), default=0)
        row = np.zeros(self._rows.shape[1:], self._rows.dtype)
        for step in range(longest):
            holds = []
            for index, (seed, actions) in enumerate(episodes):
                first = longest - len(actions)  # the step of its first action
                if seed is None or step < first:
                    holds.append(index)
                else:
                    row[index] = actions[step - first]
            batch.step(row, None, holds)
