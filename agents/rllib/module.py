"""An RLlib (new API stack) torch RLModule for ``CupboardSearch-v0``'s Dict observation.

``CupboardSearchRLModule`` reads the observation as RLlib's default env-to-module connectors
deliver it: a dict of tensors, ``{"map": uint8 (B, 2, H, W), "proprio": float32 (B, P)}``
(``BatchIndividualItems`` batches each key, ``NumpyToTensor`` keeps numpy's dtypes; there
is no ``map`` with ``map="none"``). The map is scaled to [0, 1] and read by a small CNN
(3x3 convolutions, two of them with stride 2, then an adaptive average pool to a fixed
``pool_shape`` grid that keeps where things are, flattened); its features are concatenated
with ``proprio`` and go through an MLP. Without a map the MLP reads ``proprio`` alone.

The MLP's output (the embedding) feeds two linear heads, the action head and the value.
The action head follows the env's action mode:

- ``probe`` (``MultiDiscrete([lanes, depths, sweeps])``, what the recipes train): one
  categorical head per index, their logits side by side (29 + 10 + 9 by default), read by
  RLlib's ``TorchMultiCategorical``; initialised near uniform.
- ``wrist`` (``Box(-1, 1, (3,))``): the mean of a diagonal Gaussian; the log-std is a
  state-independent parameter (initialised at ``log_std_init``, -1.0 as in the SB3 recipe:
  actions are clipped to [-1, 1], so a wide start is a random walk). ``ACTION_DIST_INPUTS``
  is ``[mean, log_std]`` (2 x 3 values), what ``TorchDiagGaussian`` reads.

``model_config`` keys (all optional): ``conv_channels`` (default ``(16, 32, 32)``),
``conv_strides`` (``(2, 2, 1)``, at most two of them 2), ``pool_shape`` (``(5, 10)``),
``hidden`` (``(256, 256)``), ``log_std_init`` (``-1.0``, the wrist mode's). RLlib merges its own
``DefaultModelConfig`` keys into ``model_config``; they are ignored. The policy and the value
share the encoder (the value head reuses ``forward_train``'s ``EMBEDDINGS``).
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from typing import Any

import gymnasium as gym
import numpy as np
import torch
from ray.rllib.core.columns import Columns
from ray.rllib.core.distribution.torch.torch_distribution import (
    TorchDiagGaussian,
    TorchMultiCategorical,
)
from ray.rllib.core.rl_module.apis import ValueFunctionAPI
from ray.rllib.core.rl_module.torch import TorchRLModule
from torch import nn

DEFAULT_MODEL_CONFIG: dict[str, Any] = {
    "conv_channels": (16, 32, 32),
    "conv_strides": (2, 2, 1),
    "pool_shape": (5, 10),
    "hidden": (256, 256),
    "log_std_init": -1.0,
}


def _int_tuple(name: str, value: Any, allowed: Sequence[int] | None = None) -> tuple[int, ...]:
    """``value`` as a non-empty tuple of positive ints (in ``allowed``, if given)."""
    if isinstance(value, (str, bytes)) or not isinstance(value, Sequence) or not value:
        raise TypeError(
            f"model_config[{name!r}] must be a non-empty sequence of ints, got {value!r}"
        )
    items = tuple(value)
    if not all(isinstance(v, (int, np.integer)) and not isinstance(v, bool) for v in items):
        raise TypeError(f"model_config[{name!r}] must hold ints, got {value!r}")
    if any(v < 1 for v in items) or (allowed is not None and any(v not in allowed for v in items)):
        valid = f"in {tuple(allowed)}" if allowed is not None else "positive"
        raise ValueError(f"model_config[{name!r}] must hold ints {valid}, got {value!r}")
    return tuple(int(v) for v in items)


class CupboardSearchRLModule(TorchRLModule, ValueFunctionAPI):
    """PPO's actor-critic for the Dict observation (see the module docstring)."""

    def setup(self) -> None:
        config = self._checked_model_config()
        proprio_space, map_space = self._checked_spaces()

        features = int(proprio_space.shape[0])
        self._cnn: nn.Module | None = None
        if map_space is not None:
            in_channels = int(map_space.shape[0])
            layers: list[nn.Module] = []
            for channels, stride in zip(
                config["conv_channels"], config["conv_strides"], strict=True
            ):
                layers += [nn.Conv2d(in_channels, channels, 3, stride, padding=1), nn.ReLU()]
                in_channels = channels
            layers += [nn.AdaptiveAvgPool2d(config["pool_shape"]), nn.Flatten()]
            self._cnn = nn.Sequential(*layers)
            features += in_channels * math.prod(config["pool_shape"])

        mlp: list[nn.Module] = []
        for width in config["hidden"]:
            mlp += [nn.Linear(features, width), nn.Tanh()]
            features = width
        self._mlp = nn.Sequential(*mlp)
        self._log_std: nn.Parameter | None = None
        if isinstance(self.action_space, gym.spaces.MultiDiscrete):  # the probe mode
            counts = [int(n) for n in self.action_space.nvec]
            self._action_head = nn.Linear(features, sum(counts))  # logits, index by index
            self.action_dist_cls = TorchMultiCategorical.get_partial_dist_cls(input_lens=counts)
        else:  # the wrist mode
            action_dim = int(self.action_space.shape[0])
            self._action_head = nn.Linear(features, action_dim)  # the Gaussian's mean
            self._log_std = nn.Parameter(torch.full((action_dim,), float(config["log_std_init"])))
            self.action_dist_cls = TorchDiagGaussian
        self._value = nn.Linear(features, 1)
        # Small initial action outputs (near-uniform probes, means near 0) and values, as
        # SB3's orthogonal init with gains 0.01 and 1.
        nn.init.orthogonal_(self._action_head.weight, gain=0.01)
        nn.init.zeros_(self._action_head.bias)
        nn.init.orthogonal_(self._value.weight, gain=1.0)
        nn.init.zeros_(self._value.bias)

    def _checked_model_config(self) -> dict[str, Any]:
        # RLlib merges its DefaultModelConfig's keys (fcnet_hiddens, ...) into
        # model_config; only this module's keys are read.
        given = self.model_config or {}
        if not isinstance(given, Mapping):
            raise TypeError(f"model_config must be a dict, got {type(given).__name__}")
        config = {key: given.get(key, default) for key, default in DEFAULT_MODEL_CONFIG.items()}
        config["conv_channels"] = _int_tuple("conv_channels", config["conv_channels"])
        config["conv_strides"] = _int_tuple("conv_strides", config["conv_strides"], (1, 2))
        if len(config["conv_strides"]) != len(config["conv_channels"]):
            raise ValueError(
                f"model_config: conv_strides must have one stride per conv layer "
                f"({len(config['conv_channels'])}), got {config['conv_strides']!r}"
            )
        if config["conv_strides"].count(2) > 2:
            raise ValueError(
                f"model_config['conv_strides'] may hold at most two 2s (keeps the map's "
                f"resolution), got {config['conv_strides']!r}"
            )
        config["pool_shape"] = _int_tuple("pool_shape", config["pool_shape"])
        if len(config["pool_shape"]) != 2:
            raise ValueError(
                f"model_config['pool_shape'] must be (rows, cols), got {config['pool_shape']!r}"
            )
        config["hidden"] = _int_tuple("hidden", config["hidden"])
        log_std_init = config["log_std_init"]
        if isinstance(log_std_init, bool) or not isinstance(log_std_init, (int, float)):
            raise TypeError(f"model_config['log_std_init'] must be a float, got {log_std_init!r}")
        if not math.isfinite(log_std_init):
            raise ValueError(f"model_config['log_std_init'] must be finite, got {log_std_init!r}")
        return config

    def _checked_spaces(self) -> tuple[gym.spaces.Box, gym.spaces.Box | None]:
        space = self.observation_space
        if not isinstance(space, gym.spaces.Dict) or "proprio" not in space.spaces:
            raise TypeError(
                f"observation_space must be a Dict with 'proprio' (and 'map'), got {space!r}"
            )
        extra = sorted(set(space.spaces) - {"proprio", "map"})
        if extra:
            raise ValueError(f"observation_space has unexpected keys {extra}: {space!r}")
        proprio = space["proprio"]
        if not isinstance(proprio, gym.spaces.Box) or len(proprio.shape) != 1:
            raise TypeError(f"observation_space['proprio'] must be a 1-D Box, got {proprio!r}")
        map_space = space.spaces.get("map")
        if map_space is not None and (
            not isinstance(map_space, gym.spaces.Box) or len(map_space.shape) != 3
        ):
            raise TypeError(f"observation_space['map'] must be a (C, H, W) Box, got {map_space!r}")
        action = self.action_space
        box = isinstance(action, gym.spaces.Box) and len(action.shape) == 1
        probes = isinstance(action, gym.spaces.MultiDiscrete) and len(action.shape) == 1
        if not (box or probes):
            raise TypeError(
                "action_space must be a 1-D Box (the wrist mode) or a 1-D MultiDiscrete (the "
                f"probe mode), got {action!r}"
            )
        return proprio, map_space

    def _embed(self, batch: Mapping[str, Any]) -> torch.Tensor:
        """The MLP's output for ``batch[OBS]`` (any leading dims, flattened and restored)."""
        obs = batch[Columns.OBS]
        proprio = torch.as_tensor(obs["proprio"], dtype=torch.float32)
        lead = proprio.shape[:-1]
        x = proprio.reshape(-1, proprio.shape[-1])
        if self._cnn is not None:
            maps = torch.as_tensor(obs["map"])
            # The map is uint8 in [0, 255] (its space's range): scale to [0, 1].
            maps = maps.reshape(-1, *maps.shape[-3:]).to(torch.float32) / 255.0
            x = torch.cat([self._cnn(maps), x], dim=-1)
        return self._mlp(x).reshape(*lead, -1)

    def _dist_inputs(self, embeddings: torch.Tensor) -> torch.Tensor:
        """The probe mode's logits, or the wrist mode's ``[mean, log_std]``."""
        out = self._action_head(embeddings)
        if self._log_std is None:
            return out
        return torch.cat([out, self._log_std.expand_as(out)], dim=-1)

    def _forward(self, batch: dict[str, Any], **kwargs: Any) -> dict[str, Any]:
        return {Columns.ACTION_DIST_INPUTS: self._dist_inputs(self._embed(batch))}

    def _forward_train(self, batch: dict[str, Any], **kwargs: Any) -> dict[str, Any]:
        embeddings = self._embed(batch)
        return {
            Columns.ACTION_DIST_INPUTS: self._dist_inputs(embeddings),
            Columns.EMBEDDINGS: embeddings,
        }

    def compute_values(
        self, batch: dict[str, Any], embeddings: torch.Tensor | None = None
    ) -> torch.Tensor:
        if embeddings is None:
            embeddings = self._embed(batch)
        return self._value(embeddings).squeeze(-1)
