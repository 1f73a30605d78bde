"""A spatial probe head: one set of sweep logits per lane and depth, read off the map where
the probe goes.

The recipe's policy squeezes the map into one vector and asks a linear layer for the
probe's lane, depth and sweep; the lane the planner picks is where a shadow lies on the
map, so the network has to learn the same thing 29 times over. Here a small convolutional
trunk keeps the map's grid, and each probe of the core's grid (lane x, depth y) reads the
trunk's features at two points of the map: where the wrist will stand and a finger's reach
ahead of it (bilinear sampling, ``grid_sample``). A per-probe MLP, shared by every lane and
depth, turns those features and a global summary (the whole map and the proprioception)
into the probe's sweep logits; all of them together are one categorical over every probe
(``JointCategoricalDistribution``), ordered as the ``MultiDiscrete`` action's row-major
index. Where the task claims, the claim is one outcome more, its logit from the global
summary (``ProbeOrClaimDistribution``). The value head reads the global summary.

The points come from the env's static geometry (``probe_points``, written into the policy's
arguments when the model is made: ``recipe_classes.policy_kwargs``), so a saved model
keeps the grid it was trained on.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any, cast

import gymnasium as gym
import numpy as np
import torch as th
from torch import nn

from tactile_search._validation import as_count
from tactile_search.networks.encoders import ImpalaStage, MapExtractor, _positive_ints
from tactile_search.networks.joint_probe import Float32Linear, JointProbePolicy


def probe_points(geometry: dict[str, Any]) -> list[list[float]]:
    """For every probe (lane, depth) in row-major order, its two map points in
    ``grid_sample``'s coordinates ([-1, 1] over the map's extent, x then y): the wrist's end
    position and a finger's reach ahead of it, from the env's ``geometry()``. Plain Python
    floats, not numpy scalars: the points go into the policy's arguments, which rl-zoo3
    prints and writes to a run's ``config.yml``."""
    xs, ys = np.asarray(geometry["xs"]), np.asarray(geometry["ys"])
    half = 0.5 * float(geometry["cell"])
    x0, x1 = float(xs[0, 0]) - half, float(xs[0, -1]) + half
    y0, y1 = float(ys[0, 0]) - half, float(ys[-1, 0]) + half
    reach = float(geometry["reach"])
    points = []
    for x in geometry["probe_lanes"]:
        for y in geometry["probe_depths"]:
            for ahead in (0.0, reach):
                points.append(
                    [
                        2 * (float(x) - x0) / (x1 - x0) - 1,
                        2 * (float(y) + ahead - y0) / (y1 - y0) - 1,
                    ]
                )
    return points


class SpatialProbeExtractor(MapExtractor):
    """The map's trunk (IMPALA stages per ``channels``), its features sampled at
    ``probe_points`` (two per probe), and a global summary (one more stage, flattened, to
    ``global_features``, beside the proprio features). ``features_dim`` = the global size +
    probes x 2 x ``channels[-1]``: the global part first, then each probe's two points'
    features.
    """

    #: The probes' map points (a buffer, ``grid_sample``'s layout).
    points: th.Tensor
    #: The trunk and the summary's head: always built (the extractor needs the map).
    map_net: nn.Module
    map_head: nn.Module

    def __init__(
        self,
        observation_space: gym.Space[Any],
        probe_points: Sequence[Sequence[float]] = (),
        channels: Sequence[int] = (8, 16),
        res_blocks: int = 1,
        global_features: int = 128,
        proprio_features: int = 64,
        map_key: str = "map",
        channels_last: bool = True,
    ) -> None:
        points = np.asarray(probe_points, dtype=np.float32)
        if points.ndim != 2 or points.shape[1] != 2 or len(points) == 0 or len(points) % 2:
            raise ValueError(
                "probe_points must be pairs of (x, y) points, two per probe (spatial_probe."
                f"probe_points), got an array of shape {points.shape}"
            )
        self.channels = _positive_ints("channels", channels)
        self.res_blocks = as_count("res_blocks", res_blocks, minimum=0)
        self.global_features = as_count("global_features", global_features)
        self.probes = len(points) // 2
        super().__init__(
            observation_space,
            proprio_features=proprio_features,
            map_key=map_key,
            channels_last=channels_last,
        )
        if not self.has_map:
            raise ValueError("SpatialProbeExtractor needs the map observation")
        self.register_buffer("points", th.as_tensor(points)[None, :, None, :])
        self.point_features = 2 * self.channels[-1]
        vector_dim = self._features_dim - self.global_features
        self.global_dim = self.global_features + vector_dim
        self._features_dim = self.global_dim + self.probes * self.point_features

    def _build_map(self, shape: tuple[int, int, int]) -> int:
        stages, in_channels = [], shape[0]
        for out_channels in self.channels:
            stages.append(ImpalaStage(in_channels, out_channels, self.res_blocks))
            in_channels = out_channels
        self.map_net = nn.Sequential(*stages, nn.ReLU())
        self.summary = nn.Sequential(
            ImpalaStage(in_channels, in_channels, self.res_blocks), nn.ReLU(), nn.Flatten()
        )
        c, h, w = self.map_feature_shape() or (0, 0, 0)
        with th.no_grad():
            flat = self.summary(th.zeros(1, c, h, w)).shape[1]
        self.map_head = nn.Sequential(nn.Linear(flat, self.global_features), nn.ReLU())
        return self.global_features

    def forward(self, observations: dict[str, th.Tensor]) -> th.Tensor:
        image = observations[self.map_key].float()
        if self.channels_last:
            image = image.contiguous(memory_format=th.channels_last)
        grid = self.map_net(image)
        # (B, C, P, 1) -> (B, P / 2, 2 C): each probe's two points side by side.
        points = self.points.expand(len(grid), -1, -1, -1)
        sampled = nn.functional.grid_sample(grid, points, align_corners=False)
        per_probe = sampled[..., 0].transpose(1, 2).reshape(len(grid), self.probes, -1)
        parts = [self.map_head(self.summary(grid))]
        if self.vector_keys:
            vector = th.cat(
                [observations[k].flatten(start_dim=1).float() for k in self.vector_keys], dim=1
            )
            parts.append(self.proprio_net(vector))
        return th.cat([*parts, per_probe.flatten(start_dim=1)], dim=1)


class SpatialProbeHead(nn.Module):
    """Features -> one logit per probe: for every probe, its points' features beside the
    global summary through a small MLP shared by all probes, to one logit per sweep. With
    ``claims``, one logit more, last: the claim's, from the global summary alone (the
    proprioception says whether the finger touches; the map, what it has felt)."""

    def __init__(
        self, global_dim: int, probes: int, point_features: int, sweeps: int, claims: bool = False
    ) -> None:
        super().__init__()
        self.global_dim, self.probes, self.point_features = global_dim, probes, point_features
        self.context = nn.Linear(global_dim, 32)
        self.mlp = nn.Sequential(
            nn.Linear(point_features + 32, 64), nn.ReLU(), Float32Linear(64, sweeps)
        )
        self.claim = Float32Linear(32, 1) if claims else None

    def forward(self, features: th.Tensor) -> th.Tensor:
        batch = len(features)
        context = th.relu(self.context(features[:, : self.global_dim]))
        per_probe = features[:, self.global_dim :].reshape(batch, self.probes, -1)
        # The first layer reads [probe's features, context]; the context's half is the same
        # for every probe, so it is applied once per sample, not once per probe (the same
        # function as the layer on the concatenation, at half its cost; same parameters).
        first, last = cast(nn.Linear, self.mlp[0]), self.mlp[2]
        weight = first.weight
        probe_part = nn.functional.linear(per_probe, weight[:, : self.point_features])
        context_part = nn.functional.linear(context, weight[:, self.point_features :], first.bias)
        hidden = th.relu(probe_part + context_part[:, None, :])
        logits: th.Tensor = last(hidden).reshape(batch, -1)  # typed: a module's call is Any
        if self.claim is None:
            return logits
        return th.cat([logits, self.claim(context)], dim=1)


class SpatialProbePolicy(JointProbePolicy):
    """``JointProbePolicy`` with ``SpatialProbeExtractor`` and ``SpatialProbeHead``: the
    policy's latent is the extractor's features as they are (``net_arch`` ``pi=[]``), the
    value's an MLP on the global summary alone."""

    #: ``recipe_classes.policy_kwargs`` writes the env's ``probe_points`` into the
    #: extractor's arguments.
    needs_probe_points = True

    def __init__(self, observation_space: Any, action_space: Any, *args: Any, **kwargs: Any):
        kwargs.setdefault("features_extractor_class", SpatialProbeExtractor)
        kwargs["net_arch"] = {"pi": [], "vf": [64, 64]}
        kwargs.setdefault("activation_fn", nn.ReLU)
        super().__init__(observation_space, action_space, *args, **kwargs)

    def _build(self, lr_schedule: Any) -> None:
        extractor = self.features_extractor
        if not isinstance(extractor, SpatialProbeExtractor):
            raise ValueError(
                f"SpatialProbePolicy needs SpatialProbeExtractor, got {type(extractor).__name__}"
            )
        nvec = cast(gym.spaces.MultiDiscrete, self.action_space).nvec  # checked by the base
        # A probe's (lane, depth, sweep), and the claim where the task claims.
        lanes, depths, sweeps = (int(n) for n in nvec[:3])
        if len(nvec) not in (3, 4):
            raise ValueError(
                "SpatialProbePolicy needs MultiDiscrete([lanes, depths, sweeps]) or, where the "
                f"task claims, [lanes, depths, sweeps, 2]; got {list(nvec)}"
            )
        if extractor.probes != lanes * depths:
            raise ValueError(
                f"the extractor's probe_points hold {extractor.probes} probes, the action "
                f"space {lanes} x {depths} (lanes x depths)"
            )
        super()._build(lr_schedule)
        self.action_net = SpatialProbeHead(
            extractor.global_dim,
            extractor.probes,
            extractor.point_features,
            sweeps,
            claims=len(nvec) == 4,
        )
        # The value MLP reads the global summary only (the first global_dim features).
        self.mlp_extractor.value_net = nn.Sequential(
            _Columns(extractor.global_dim),
            nn.Linear(extractor.global_dim, 64),
            nn.ReLU(),
            nn.Linear(64, 64),
            nn.ReLU(),
        )
        self.optimizer = self.optimizer_class(  # type: ignore[call-arg]  # SB3's own call
            self.parameters(), lr=lr_schedule(1), **self.optimizer_kwargs
        )


class _Columns(nn.Module):
    """The first ``n`` features."""

    def __init__(self, n: int) -> None:
        super().__init__()
        self.n = n

    def forward(self, x: th.Tensor) -> th.Tensor:
        return x[:, : self.n]
