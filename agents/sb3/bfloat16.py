"""The learner's updates in bfloat16 where the CPU computes it natively: the learner's cost.

A map agent's training spends most of its time in its updates: the clone stage's cloning
passes and PPO's update (``n_epochs`` passes of forward and backward through the map
encoder; ``python -m benchmarks.learner_speed`` measures PPO's). On a CPU with bfloat16
instructions (``amx_bf16``, AMX tiles, or ``avx512_bf16``, AVX-512 bfloat16 dot products,
among ``/proc/cpuinfo``'s flags) oneDNN runs bfloat16 convolutions and matrix products
faster than float32 (several times with AMX, a fifth to a third less time per update with
AVX-512 on an AMD Zen 4); elsewhere bfloat16 is emulated and slower. So a recipe's
``bfloat16_updates: true`` trains with ``bfloat16_update_class(cls)``: the algorithm's
``train`` (the update after each rollout) runs under ``torch.autocast`` with bfloat16 where
the CPU has it natively, and as it is (float32) where it has not; the clone stage's cloning
passes follow the same rule (``agents.imitation.cloning``, ``learner_precision``). The
rollouts, the evaluation and the saved weights stay float32; the probe policies keep their
logits and the distribution over probes in float32 under autocast
(``JointCategoricalDistribution``, ``SpatialProbeHead``), so PPO's probability ratios and the
cloned log-likelihoods are not rounded to bfloat16's 8 bits.

What it gains on a given CPU, ``python -m benchmarks.learner_speed --variants recipe
recipe:bfloat16_updates=true`` prints. The PPO recipes set it, with 4 epochs per rollout,
since a validation ablation kept success (docs/RESULTS.md, "The learner in bfloat16 with
fewer epochs").
"""

from __future__ import annotations

import functools
from pathlib import Path
from typing import Any

from tactile_search._validation import as_bool

#: The flags of ``/proc/cpuinfo`` that say the CPU computes bfloat16 natively: AMX tiles,
#: or AVX-512's bfloat16 dot products.
NATIVE_BF16_FLAGS = ("amx_bf16", "avx512_bf16")
CPUINFO = Path("/proc/cpuinfo")


def cpu_has_native_bf16(cpuinfo: Path = CPUINFO) -> bool:
    """Whether the CPU computes bfloat16 natively (one of ``NATIVE_BF16_FLAGS`` among
    ``cpuinfo``'s flags); False where the file cannot be read (not Linux)."""
    try:
        text = cpuinfo.read_text()
    except OSError:
        return False
    return any(
        flag in line.partition(":")[2].split()
        for line in text.splitlines()
        if line.startswith("flags")
        for flag in NATIVE_BF16_FLAGS
    )


def learner_precision(recipe: dict[str, Any], native: bool | None = None) -> str:
    """The precision ``recipe``'s updates run in: ``bfloat16`` if it sets
    ``bfloat16_updates`` and the CPU computes bfloat16 natively (``native``, default
    ``cpu_has_native_bf16()``), else ``float32``."""
    if not as_bool("bfloat16_updates", recipe.get("bfloat16_updates", False)):
        return "float32"
    native = cpu_has_native_bf16() if native is None else native
    return "bfloat16" if native else "float32"


class BFloat16Updates:
    """Mixin for an SB3 on-policy algorithm: ``train`` (the update after each rollout)
    under bfloat16 autocast on the CPU."""

    def train(self) -> None:
        import torch

        with torch.autocast("cpu", dtype=torch.bfloat16):
            super().train()  # type: ignore[misc]


@functools.cache
def _with_bfloat16_updates(cls: type) -> type:
    return type(f"BFloat16{cls.__name__}", (BFloat16Updates, cls), {"__doc__": cls.__doc__})


def bfloat16_update_class(cls: type, native: bool | None = None) -> type:
    """``cls`` with its update under bfloat16 autocast (``BFloat16Updates``) where the CPU
    computes bfloat16 natively (``native``, default ``cpu_has_native_bf16()``), else ``cls``
    itself. One class per ``cls``: a model saved by either loads with either."""
    if not isinstance(cls, type) or not callable(getattr(cls, "train", None)):
        raise TypeError(f"cls must be an SB3 algorithm class, got {cls!r}")
    native = cpu_has_native_bf16() if native is None else native
    return _with_bfloat16_updates(cls) if native else cls


def update_precision(cls: Any) -> str:
    """The precision of ``cls``'s update: ``bfloat16`` or ``float32`` (what a run's
    ``config.yml`` records)."""
    return "bfloat16" if issubclass(cls, BFloat16Updates) else "float32"
