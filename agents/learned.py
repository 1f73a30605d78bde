"""A trained stable-baselines3 model as an evaluation agent (the ``Agent`` protocol of
``agents/scripted/base.py``): deterministic actions, with the LSTM state carried across
steps for RecurrentPPO."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np
import yaml

from agents.train import algorithm_class


class LearnedAgent:
    """The model in ``run_dir`` (``model.zip`` beside the ``config.yml`` that trained it)."""

    def __init__(
        self, run_dir: Path, name: str | None = None, deterministic: bool = True, seed: int = 0
    ) -> None:
        run_dir = Path(run_dir)
        model_path = run_dir / "model.zip"
        config_path = run_dir / "config.yml"
        for path in (model_path, config_path):
            if not path.is_file():
                raise ValueError(f"{run_dir} is not a training run: {path.name} is missing")
        self.config: dict[str, Any] = yaml.safe_load(config_path.read_text())
        self.map_mode: str = self.config["map"]
        self.name = name or f"{self.config['algo']} ({self.map_mode} map)"
        self.model = algorithm_class(self.config["algo"]).load(model_path, device="cpu")
        self._recurrent = self.config["algo"] == "recurrent_ppo"
        # Stochastic actions sample the policy's Gaussian from torch's generator, seeded
        # here, so an evaluation (same agents, same order) repeats exactly.
        self.deterministic = deterministic
        if not deterministic:
            import torch

            torch.manual_seed(seed)
        self._state: Any = None
        self._episode_start = np.ones((1,), dtype=bool)

    def reset(self, env: Any, observation: dict, info: dict) -> None:
        self._state = None
        self._episode_start = np.ones((1,), dtype=bool)

    def act(self, observation: dict) -> np.ndarray:
        if self._recurrent:
            action, self._state = self.model.predict(
                observation,
                state=self._state,
                episode_start=self._episode_start,
                deterministic=self.deterministic,
            )
            self._episode_start = np.zeros((1,), dtype=bool)
        else:
            action, _ = self.model.predict(observation, deterministic=self.deterministic)
        return np.asarray(action, dtype=np.float32).reshape(3)
