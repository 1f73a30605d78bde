"""The PPO update in bfloat16 where the CPU has AMX: the learner's cost.

A map agent's training spends most of its time in PPO's update (``n_epochs`` passes of
forward and backward through the map encoder; ``python -m benchmarks.learner_speed``
measures it). On a CPU with AMX tiles (``amx_bf16`` among
``/proc/cpuinfo``'s flags) oneDNN runs bfloat16 convolutions and matrix products several
times faster than float32; elsewhere bfloat16 is emulated and slower. So a recipe's
``bfloat16_updates: true`` trains with ``bfloat16_update_class(cls)``: the algorithm's
``train`` (the update after each rollout) runs under ``torch.autocast`` with bfloat16 where
the CPU has AMX, and as it is (float32) where it has not. The rollouts, the evaluation and
the saved weights stay float32; the probe policies keep their logits and the distribution
over probes in float32 under autocast (``JointCategoricalDistribution``,
``SpatialProbeHead``), so PPO's probability ratios are not rounded to bfloat16's 8 bits.

What it gains on a given CPU, ``python -m benchmarks.learner_speed --variants recipe
recipe:bfloat16_updates=true`` prints. The PPO recipes set it, with 4 epochs per rollout,
since a validation ablation kept success (docs/RESULTS.md, "The learner in bfloat16 with
fewer epochs").
"""

from __future__ import annotations

import functools
from pathlib import Path
from typing import Any

#: The flag of ``/proc/cpuinfo`` that says the CPU has AMX tiles for bfloat16.
AMX_BF16_FLAG = "amx_bf16"
CPUINFO = Path("/proc/cpuinfo")


def cpu_has_amx_bf16(cpuinfo: Path = CPUINFO) -> bool:
    """Whether the CPU has AMX tiles for bfloat16 (``amx_bf16`` among ``cpuinfo``'s
    flags); False where the file cannot be read (not Linux)."""
    try:
        text = cpuinfo.read_text()
    except OSError:
        return False
    return any(
        AMX_BF16_FLAG in line.partition(":")[2].split()
        for line in text.splitlines()
        if line.startswith("flags")
    )


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


def bfloat16_update_class(cls: type, cpu_has_amx: bool | None = None) -> type:
    """``cls`` with its update under bfloat16 autocast (``BFloat16Updates``) where the CPU
    has AMX (``cpu_has_amx``, default ``cpu_has_amx_bf16()``), else ``cls`` itself. One class
    per ``cls``: a model saved by either loads with either."""
    if not isinstance(cls, type) or not callable(getattr(cls, "train", None)):
        raise TypeError(f"cls must be an SB3 algorithm class, got {cls!r}")
    has_amx = cpu_has_amx_bf16() if cpu_has_amx is None else cpu_has_amx
    return _with_bfloat16_updates(cls) if has_amx else cls


def update_precision(cls: Any) -> str:
    """The precision of ``cls``'s update: ``bfloat16`` or ``float32`` (what a run's
    ``config.yml`` records)."""
    return "bfloat16" if issubclass(cls, BFloat16Updates) else "float32"
