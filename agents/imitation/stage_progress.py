"""The clone stage's progress as a user sees it: the stages listed up front, then one bar
per stage (the teacher's demonstrations, each cloning pass, each DAgger round's rollouts)
with its count, rate and expected time left (tqdm). PPO's own bar follows (SB3's)."""

from __future__ import annotations

import contextlib
from collections.abc import Callable, Iterator
from typing import Any


def stage_plan(settings: Any, ppo_timesteps: int | None = None) -> str:
    """The stages a clone stage of ``settings`` (``ImitationSettings``) runs, in words."""
    parts = [
        f"the teacher's demonstrations ({settings.demo_episodes:,} episodes)",
        f"behaviour cloning ({settings.cloning.epochs} epochs)",
    ]
    if settings.dagger_rounds:
        plural = "s" if settings.dagger_rounds > 1 else ""
        rounds = f"{settings.dagger_rounds} DAgger round{plural}"
        parts.append(
            f"{rounds} ({settings.dagger_episodes:,} episodes, {settings.dagger_epochs} epochs "
            "each)"
        )
    if ppo_timesteps is not None:
        parts.append(f"PPO fine-tuning ({ppo_timesteps:,} probes)")
    return "stages: " + ", ".join(parts)


@contextlib.contextmanager
def stage_bar(
    description: str, total: int, unit: str, enabled: bool
) -> Iterator[Callable[[int], Any] | None]:
    """A bar of ``total`` ``unit``s named ``description`` while the block runs: yields its
    ``update`` (None when not ``enabled``)."""
    if not enabled:
        yield None
        return
    from tqdm.auto import tqdm

    with tqdm(total=total, desc=description, unit=unit, dynamic_ncols=True) as bar:
        yield bar.update
