"""Map encoders for the Dict observation (``"map"`` image, ``"proprio"`` vector) as SB3
features extractors that keep where things are on the map.

SB3's ``MultiInputPolicy`` runs ``NatureCNN`` (8x8 stride 4, 4x4 stride 2, 3x3 convs) on the
map, which squeezes the 40x80 GPIS map to a 1x6 grid. The extractors here keep a grid:

* ``ImpalaMapExtractor``: the IMPALA residual CNN (Espeholt et al. 2018), 40x80 -> 5x10
  after its three default stages, flattened and projected to ``map_features``; with
  ``space_to_depth=2`` the map is first rearranged to 4x the channels at 20x40 (nothing is
  lost) and two stages reach the same 5x10 grid at ~0.4x the training cost.
* ``SpatialSoftmaxMapExtractor``: 3x3 convs (strides 1, 2, 1: 40x80 -> 20x40), then a
  spatial softmax per channel giving its expected (x, y) in [-1, 1] (Levine et al. 2016)
  and a global average pool.

Every key other than ``map_key`` (``"proprio"``) is flattened and concatenated after the map
features, by default unchanged (``proprio_features=0``), or through Linear + ReLU. Without a
map (``map="none"``) both reduce to the proprio features alone, so every map mode trains
the same policy class::

    from stable_baselines3 import PPO
    from tactile_search.networks.encoders import ImpalaMapExtractor

    model = PPO(
        "MultiInputPolicy",
        env,
        policy_kwargs={
            "features_extractor_class": ImpalaMapExtractor,
            "features_extractor_kwargs": {"channels": (16, 32, 32), "map_features": 256},
        },
    )

The map arrives as SB3's ``preprocess_obs`` leaves it: a uint8 Box with bounds [0, 255] is
an image to SB3 (``is_image_space`` skips the channel-count check by default, so the
2-channel map qualifies) and is scaled to [0, 1] unless the policy has
``normalize_images=False``. Saved models pickle the class reference
``tactile_search.networks.encoders.<Class>``: they load wherever the package is installed
with its ``agents`` extra.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import gymnasium as gym
import torch as th
from gymnasium import spaces
from stable_baselines3.common.preprocessing import get_flattened_obs_dim
from stable_baselines3.common.torch_layers import BaseFeaturesExtractor
from torch import nn

from tactile_search._validation import as_bool, as_count

__all__ = [
    "ImpalaMapExtractor",
    "MapExtractor",
    "SpatialSoftmaxMapExtractor",
    "map_feature_shape",
]


def _positive_ints(name: str, values: Any) -> tuple[int, ...]:
    """``values`` (a non-empty sequence of positive ints, e.g. a YAML list) as a tuple."""
    if isinstance(values, (str, bytes)) or not isinstance(values, Sequence):
        raise TypeError(
            f"{name} must be a non-empty sequence of positive ints, "
            f"got {type(values).__name__} {values!r}"
        )
    if len(values) == 0:
        raise ValueError(f"{name} must be a non-empty sequence of positive ints, got {values!r}")
    return tuple(as_count(f"{name}[{i}]", v) for i, v in enumerate(values))


class MapExtractor(BaseFeaturesExtractor):
    """The shared part of the map extractors: splits the Dict observation into the map
    (``map_key``, a 3-D ``(C, H, W)`` Box, optional) and the other keys (flattened,
    concatenated in the space's key order, then unchanged or through Linear + ReLU to
    ``proprio_features``). Subclasses build ``self.map_net`` (the map's conv trunk, whose
    output grid ``map_feature_shape`` reports) and ``self.map_head`` (the trunk's output to
    a flat vector) with ``_build_map``, returning the head's output size.

    ``features_dim`` = map features + proprio features (the proprio size itself with
    ``proprio_features=0``).

    Args:
        observation_space: the env's ``Dict`` space (with or without ``map_key``).
        proprio_features: 0 (the other keys as they are) or the width of a Linear + ReLU.
        map_key: the key of the map image.
        channels_last: run the convs on a channels-last (NHWC) copy of the map: on CPU
            (oneDNN) these small-channel convs run faster so, with the same features up to
            float rounding.
    """

    def __init__(
        self,
        observation_space: gym.Space[Any],
        proprio_features: int = 0,
        map_key: str = "map",
        channels_last: bool = True,
    ) -> None:
        if not isinstance(observation_space, spaces.Dict):
            raise TypeError(
                f"{type(self).__name__} needs a gymnasium.spaces.Dict observation space, "
                f"got {type(observation_space).__name__} {observation_space!r}"
            )
        if not isinstance(map_key, str):
            raise TypeError(f"map_key must be a str, got {type(map_key).__name__} {map_key!r}")
        proprio_features = as_count("proprio_features", proprio_features, minimum=0)
        channels_last = as_bool("channels_last", channels_last)
        # BaseFeaturesExtractor asserts features_dim > 0; the real value is set below (as
        # SB3's CombinedExtractor does).
        super().__init__(observation_space, features_dim=1)
        self.map_key = map_key
        self.channels_last = channels_last
        self.vector_keys = tuple(k for k in observation_space.spaces if k != map_key)
        map_space = observation_space.spaces.get(map_key)
        if map_space is None and not self.vector_keys:
            raise ValueError(f"observation space has no keys to encode: {observation_space!r}")
        self.has_map = map_space is not None
        self.map_net: nn.Module | None = None
        self.map_head: nn.Module | None = None
        map_dim = 0
        if map_space is not None:
            if not isinstance(map_space, spaces.Box) or len(map_space.shape) != 3:
                raise ValueError(
                    f"observation space {map_key!r} must be a Box of shape (C, H, W), "
                    f"got {map_space!r}"
                )
            channels, height, width = (int(n) for n in map_space.shape)
            self.map_shape: tuple[int, int, int] = (channels, height, width)
            map_dim = self._build_map(self.map_shape)
        vector_dim = sum(get_flattened_obs_dim(observation_space[k]) for k in self.vector_keys)
        if proprio_features and vector_dim:
            self.proprio_net: nn.Module = nn.Sequential(
                nn.Linear(vector_dim, proprio_features), nn.ReLU()
            )
            vector_dim = proprio_features
        else:
            self.proprio_net = nn.Identity()
        self._features_dim = map_dim + vector_dim

    def _build_map(self, shape: tuple[int, int, int]) -> int:
        """Builds ``self.map_net`` and ``self.map_head`` for maps of ``shape``; returns the
        number of map features."""
        raise NotImplementedError

    def map_feature_shape(self) -> tuple[int, int, int] | None:
        """``(C, h, w)`` of the map trunk's output (the grid the map features keep), or None
        without a map."""
        if self.map_net is None:
            return None
        param = next(self.map_net.parameters())
        with th.no_grad():
            zeros = th.zeros((1, *self.map_shape), dtype=param.dtype, device=param.device)
            out = self.map_net(zeros)
        channels, height, width = (int(n) for n in out.shape[1:])
        return (channels, height, width)

    def forward(self, observations: dict[str, th.Tensor]) -> th.Tensor:
        parts = []
        if self.map_net is not None and self.map_head is not None:
            image = observations[self.map_key].float()
            if self.channels_last:
                image = image.contiguous(memory_format=th.channels_last)
            parts.append(self.map_head(self.map_net(image)))
        if self.vector_keys:
            vector = th.cat(
                [observations[k].flatten(start_dim=1).float() for k in self.vector_keys], dim=1
            )
            parts.append(self.proprio_net(vector))
        return parts[0] if len(parts) == 1 else th.cat(parts, dim=1)


class ResidualBlock(nn.Module):
    """IMPALA's residual block: ``x + conv(relu(conv(relu(x))))``, 3x3 convs, same size."""

    def __init__(self, channels: int) -> None:
        super().__init__()
        self.conv0 = nn.Conv2d(channels, channels, kernel_size=3, padding=1)
        self.conv1 = nn.Conv2d(channels, channels, kernel_size=3, padding=1)

    def forward(self, x: th.Tensor) -> th.Tensor:
        # Typed here: torch types a module's call as Any.
        residual: th.Tensor = self.conv1(th.relu(self.conv0(th.relu(x))))
        return x + residual


class ImpalaStage(nn.Sequential):
    """One IMPALA stage: 3x3 conv to ``out_channels``, 3x3 max-pool stride 2 (padding 1:
    H -> ceil(H / 2)), then ``res_blocks`` residual blocks."""

    def __init__(self, in_channels: int, out_channels: int, res_blocks: int = 2) -> None:
        super().__init__(
            nn.Conv2d(in_channels, out_channels, kernel_size=3, padding=1),
            nn.MaxPool2d(kernel_size=3, stride=2, padding=1),
            *(ResidualBlock(out_channels) for _ in range(res_blocks)),
        )


class SpaceToDepth(nn.Module):
    """Each ``factor`` x ``factor`` block of cells as ``factor²`` channels of one cell, after
    zero-padding the bottom and right to a multiple of ``factor``: ``(B, C, H, W) -> (B, C
    factor², ceil(H / factor), ceil(W / factor))``, channel ``c factor² + dy factor + dx``
    holding cell ``(factor i + dy, factor j + dx)`` of channel ``c`` (``PixelUnshuffle``'s
    order).

    It runs as a fixed convolution (kernel and stride ``factor``, one weight 1 per output
    channel, the rest 0, a buffer, not trained), which copies every value exactly and keeps
    a channels-last input channels-last: on CPU that is faster than ``PixelUnshuffle`` of a
    channels-last map, and than a reshape and permute."""

    #: The fixed convolution's weight (a buffer).
    weight: th.Tensor

    def __init__(self, channels: int, factor: int) -> None:
        super().__init__()
        self.factor = factor
        weight = th.zeros(channels * factor * factor, channels, factor, factor)
        for c in range(channels):
            for dy in range(factor):
                for dx in range(factor):
                    weight[(c * factor + dy) * factor + dx, c, dy, dx] = 1.0
        self.register_buffer("weight", weight)

    def forward(self, x: th.Tensor) -> th.Tensor:
        f = self.factor
        pad_h, pad_w = -x.shape[-2] % f, -x.shape[-1] % f
        if pad_h or pad_w:
            x = nn.functional.pad(x, (0, pad_w, 0, pad_h))
        weight = self.weight
        if x.is_contiguous(memory_format=th.channels_last):
            weight = weight.contiguous(memory_format=th.channels_last)
        return nn.functional.conv2d(x, weight.to(x.dtype), stride=f)


class ImpalaMapExtractor(MapExtractor):
    """IMPALA-style residual CNN on the map (Espeholt et al. 2018), keeping a spatial grid.

    Per entry of ``channels`` a stage (3x3 conv, 3x3 max-pool stride 2, ``res_blocks``
    residual blocks of ReLU-conv-ReLU-conv), halving height and width (rounding up): the
    default three stages turn a 40x80 map into a 5x10 grid of ``channels[-1]`` features.
    Then ReLU, flatten, Linear to ``map_features`` and ReLU. The proprio part is described
    in ``MapExtractor``: ``features_dim`` = ``map_features`` + proprio size (256 + 11 for
    the default env), or the proprio size alone without a map.

    ``space_to_depth`` = s > 1 first rearranges each s x s block of map cells into s² times
    as many channels (torch's ``PixelUnshuffle``; the map is zero-padded at the bottom and
    right to a multiple of s): the same numbers on a grid s times coarser, so the first
    stage's conv, max-pool and residual blocks run on s² fewer cells. With s = 2 two
    stages reach the grid three stages reach without it.

    Cost: the defaults take ~23 M multiply-adds per 40x80 map (NatureCNN: ~1.8 M), mostly in
    the residual blocks at 20x40 and 10x20; ``res_blocks=0`` cuts that to ~7 M, and
    ``channels=(8, 16, 16), res_blocks=1`` to ~4 M, with the same 5x10 grid. On CPU a PPO
    update's time goes mostly to the full-resolution stage's conv and max-pool backward
    passes, not the multiply-adds: ``space_to_depth=2, channels=(16, 16), res_blocks=1``
    (the same 5x10 grid of 16 features) trains at ~0.4x the cost per sample of
    ``channels=(8, 16, 16), res_blocks=1`` (``python -m benchmarks.learner_speed``).
    """

    def __init__(
        self,
        observation_space: gym.Space[Any],
        channels: Sequence[int] = (16, 32, 32),
        map_features: int = 256,
        res_blocks: int = 2,
        proprio_features: int = 0,
        map_key: str = "map",
        channels_last: bool = True,
        space_to_depth: int = 1,
    ) -> None:
        self.channels = _positive_ints("channels", channels)
        self.map_features = as_count("map_features", map_features)
        self.res_blocks = as_count("res_blocks", res_blocks, minimum=0)
        self.space_to_depth = as_count("space_to_depth", space_to_depth)
        super().__init__(
            observation_space,
            proprio_features=proprio_features,
            map_key=map_key,
            channels_last=channels_last,
        )

    def _build_map(self, shape: tuple[int, int, int]) -> int:
        stages: list[nn.Module] = []
        in_channels = shape[0]
        if self.space_to_depth > 1:
            stages.append(SpaceToDepth(in_channels, self.space_to_depth))
            in_channels *= self.space_to_depth**2
        for out_channels in self.channels:
            stages.append(ImpalaStage(in_channels, out_channels, self.res_blocks))
            in_channels = out_channels
        self.map_net = nn.Sequential(*stages, nn.ReLU())
        c, h, w = self.map_feature_shape() or (0, 0, 0)
        self.map_head = nn.Sequential(
            nn.Flatten(), nn.Linear(c * h * w, self.map_features), nn.ReLU()
        )
        return self.map_features


class SpatialSoftmax(nn.Module):
    """Per channel, the softmax over the grid of ``x / temperature`` and the expected
    ``(x, y)`` under it, in [-1, 1] (left/top = -1): ``(B, C, H, W) -> (B, 2 C)`` as
    ``[x_0, y_0, x_1, y_1, ...]``. The temperature is learned (from 1) if ``learn_temperature``.
    """

    #: Each cell's (x, y) and, when learned, the temperature's log (buffers or parameters).
    coords: th.Tensor
    log_temperature: th.Tensor

    def __init__(self, height: int, width: int, learn_temperature: bool = True) -> None:
        super().__init__()
        ys, xs = th.meshgrid(
            th.linspace(-1.0, 1.0, height), th.linspace(-1.0, 1.0, width), indexing="ij"
        )
        # (H W, 2): each grid cell's (x, y).
        self.register_buffer("coords", th.stack([xs.reshape(-1), ys.reshape(-1)], dim=1))
        log_temperature = th.zeros(())
        if learn_temperature:
            self.log_temperature = nn.Parameter(log_temperature)
        else:
            self.register_buffer("log_temperature", log_temperature)

    def forward(self, x: th.Tensor) -> th.Tensor:
        b, c = x.shape[:2]
        logits = x.reshape(b, c, -1) * th.exp(-self.log_temperature)
        weights = th.softmax(logits, dim=-1)  # (B, C, H W)
        return (weights @ self.coords).reshape(b, 2 * c)


class SpatialSoftmaxHead(nn.Module):
    """The spatial-softmax keypoints (``2 C``) of the last conv's output (its logits, before
    the ReLU that would flatten every negative response to the same weight), then the global
    average of its ReLU (``C``): ``(B, C, h, w) -> (B, 3 C)``."""

    def __init__(self, height: int, width: int, learn_temperature: bool = True) -> None:
        super().__init__()
        self.spatial_softmax = SpatialSoftmax(height, width, learn_temperature)

    def forward(self, x: th.Tensor) -> th.Tensor:
        return th.cat([self.spatial_softmax(x), th.relu(x).mean(dim=(2, 3))], dim=1)


class SpatialSoftmaxMapExtractor(MapExtractor):
    """Convs that keep most of the resolution, then where each channel responds (spatial
    softmax, Levine et al. 2016) and how much (global average pool).

    3x3 convs (padding 1) with ``channels`` and ``strides`` (default (16, 32, 32) and
    (1, 2, 1): 40x80 -> 40x80 -> 20x40 -> 20x40), ReLU between them; on the last conv's
    output a spatial softmax per channel gives its expected (x, y) in [-1, 1] (with a learned
    temperature unless ``learn_temperature=False``), and a global average pool of its ReLU
    one more number per channel. ``features_dim`` = 3 ``channels[-1]`` + proprio size (96 +
    11 for the default env), or the proprio size alone without a map.

    Cost: the defaults take ~12 M multiply-adds per 40x80 map (NatureCNN: ~1.8 M), mostly the
    last conv at 20x40; ``strides=(2, 2, 1)`` (a 10x20 grid) cuts that to ~3 M.
    """

    def __init__(
        self,
        observation_space: gym.Space[Any],
        channels: Sequence[int] = (16, 32, 32),
        strides: Sequence[int] = (1, 2, 1),
        learn_temperature: bool = True,
        proprio_features: int = 0,
        map_key: str = "map",
        channels_last: bool = True,
    ) -> None:
        self.channels = _positive_ints("channels", channels)
        self.strides = _positive_ints("strides", strides)
        if len(self.strides) != len(self.channels):
            raise ValueError(
                f"strides must have one entry per conv, like channels {self.channels}: "
                f"got {self.strides}"
            )
        learn_temperature = as_bool("learn_temperature", learn_temperature)
        self.learn_temperature = learn_temperature
        super().__init__(
            observation_space,
            proprio_features=proprio_features,
            map_key=map_key,
            channels_last=channels_last,
        )

    def _build_map(self, shape: tuple[int, int, int]) -> int:
        layers: list[nn.Module] = []
        in_channels = shape[0]
        for i, (out_channels, stride) in enumerate(zip(self.channels, self.strides, strict=True)):
            if i:
                layers.append(nn.ReLU())
            layers.append(
                nn.Conv2d(in_channels, out_channels, kernel_size=3, stride=stride, padding=1)
            )
            in_channels = out_channels
        self.map_net = nn.Sequential(*layers)
        c, h, w = self.map_feature_shape() or (0, 0, 0)
        self.map_head = SpatialSoftmaxHead(h, w, self.learn_temperature)
        return 3 * c


def map_feature_shape(extractor: Any) -> tuple[int, int, int] | None:
    """``(C, h, w)`` of the map features of ``extractor`` (a ``MapExtractor``, e.g. a
    model's ``policy.features_extractor``) for the observation space it was built for: the
    grid its map encoding keeps. None if that space has no map."""
    if not isinstance(extractor, MapExtractor):
        raise TypeError(
            "map_feature_shape needs a MapExtractor (ImpalaMapExtractor or "
            f"SpatialSoftmaxMapExtractor), got {type(extractor).__name__}"
        )
    return extractor.map_feature_shape()
