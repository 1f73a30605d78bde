"""What a training run hooks into SB3: its logger (``progress.csv`` kept across resumes,
TensorBoard), checkpoints at rollout boundaries, and a wall-clock limit."""

from __future__ import annotations

import copy
import os
import time
from pathlib import Path
from typing import Any

from agents.run_dir import (
    CHECKPOINT_PREFIX,
    checkpoint_dir,
    checkpoints,
    progress_path,
    save_model_atomically,
    write_atomically,
)


def wall_clock_limit(minutes: float) -> Any:
    """An SB3 callback that stops training once ``minutes`` of wall-clock time have passed
    (checked after every step; the model is then saved as usual)."""
    from stable_baselines3.common.callbacks import BaseCallback

    class StopAfter(BaseCallback):
        def _on_training_start(self) -> None:
            self.deadline = time.perf_counter() + 60.0 * minutes

        def _on_step(self) -> bool:
            return time.perf_counter() < self.deadline

    return StopAfter()


def make_logger(run_dir: Path, kept: tuple[list[str], list[str]] | None = None) -> Any:
    """SB3's logger writing ``progress.csv`` and TensorBoard events into ``run_dir``.

    With ``kept`` (a header and rows from ``kept_progress``), ``progress.csv`` is first
    replaced (atomically) by those rows and the new rows are appended: SB3's own CSV writer
    opens the file with mode ``"w"`` and would wipe the rows of the run's earlier part.
    """
    from stable_baselines3.common.logger import CSVOutputFormat, Logger, make_output_format

    class AppendingCSVOutputFormat(CSVOutputFormat):
        """SB3's CSV writer, continuing a file that already holds ``header`` and ``rows``."""

        def __init__(self, filename: Path, header: list[str], rows: list[str]) -> None:
            buffer = [",".join(header) + "\n", *rows]
            write_atomically(filename, "".join(buffer))
            self.file = open(filename, "r+")  # closed by Logger.close
            self.file.seek(0, os.SEEK_END)
            self.keys = list(header)
            self.separator = ","
            self.quotechar = '"'

    path = progress_path(run_dir)
    if kept is None:
        csv_format = CSVOutputFormat(str(path))
    else:
        csv_format = AppendingCSVOutputFormat(path, *kept)
    return Logger(str(run_dir), [csv_format, make_output_format("tensorboard", str(run_dir))])


def rollout_checkpoints(run_dir: Path, every: int, keep: int, on_save: Any = None) -> Any:
    """SB3's ``CheckpointCallback`` saving into ``<run_dir>/checkpoints/`` at rollout
    boundaries: at the start of the first rollout at least ``every`` env steps after the last
    checkpoint, when the policy has been updated with every rollout counted in
    ``num_timesteps``. (SB3's own callback saves every so many steps, mid-rollout: a run
    resumed from such a checkpoint counts steps its policy never learned from and ends at
    another total.) Keeps the newest ``keep``; ``on_save(timesteps, path)`` runs after each.
    ``save_interrupted()`` saves the state at the start of the rollout under way (after
    Ctrl-C)."""
    from stable_baselines3.common.callbacks import CheckpointCallback

    class RolloutCheckpoints(CheckpointCallback):
        def __init__(self) -> None:
            super().__init__(
                save_freq=every,
                save_path=str(checkpoint_dir(run_dir)),
                name_prefix=CHECKPOINT_PREFIX,
            )
            self._last_saved = 0
            self._boundary: int | None = None
            self._collecting = False
            self._before_update: tuple | None = None

        def _on_training_start(self) -> None:
            self._last_saved = self.model.num_timesteps

        def _on_rollout_start(self) -> None:
            self._boundary = self.model.num_timesteps
            self._before_update = None
            self._collecting = True
            if self._boundary - self._last_saved >= every:
                self.save()

        def _on_rollout_end(self) -> None:
            # The policy (and its optimizer) as the rollout found it: Ctrl-C during the
            # update that follows restores it rather than keep a half-done update.
            policy = self.model.policy
            self._before_update = (
                copy.deepcopy(policy.state_dict()),
                copy.deepcopy(policy.optimizer.state_dict()),
                self.model._n_updates,
            )
            self._collecting = False

        def _on_step(self) -> bool:
            return True

        def save(self) -> Path:
            self.num_timesteps = self.model.num_timesteps
            path = Path(self._checkpoint_path(extension="zip"))
            path.parent.mkdir(parents=True, exist_ok=True)
            save_model_atomically(self.model, path)
            self._last_saved = self.model.num_timesteps
            for _, old in checkpoints(run_dir)[:-keep]:
                old.unlink(missing_ok=True)
            if on_save is not None:
                on_save(self.model.num_timesteps, path)
            return path

        def save_interrupted(self) -> Path:
            model = self.model
            if self._boundary is not None:
                if not self._collecting and self._before_update is not None:
                    state, optimizer, n_updates = self._before_update
                    model.policy.load_state_dict(state)
                    model.policy.optimizer.load_state_dict(optimizer)
                    model._n_updates = n_updates
                model.num_timesteps = self._boundary
            return self.save()

    return RolloutCheckpoints()
