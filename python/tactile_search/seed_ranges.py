"""The evaluation protocol's three disjoint ranges of layout seeds (``docs/DESIGN.md`` §7),
defined here once: the agents, the benchmarks, the experiments and the docs import them.

- ``TRAINING`` ``[2**32, 2**63)``: every layout a training run draws (``agents.train``,
  the RLlib env, the soak).
- ``VALIDATION`` ``[1,000,000, 2,000,000)``: every choice made while developing (recipes,
  planner constants, ablations) is measured here; the default of ``agents.evaluate``.
- ``TEST`` ``[2,000,000, 3,000,000)``: read only by the final results (``make results``,
  ``agents.pipeline --budget full``); ``agents.evaluate`` reads it only when told this is
  the final evaluation (``--final``).

A number tuned on a range is not reported as held-out on it.

``ANY`` ``[0, 2**63)`` is the range a ``gymnasium.make`` env draws its layouts from when
``reset()`` is given no seed (and the vector envs' default): every layout, held-out ones
included.
"""

from __future__ import annotations

ANY = (0, 2**63)
TRAINING = (2**32, ANY[1])
VALIDATION = (1_000_000, 2_000_000)
TEST = (2_000_000, 3_000_000)
#: The held-out ranges by name.
SPLITS: dict[str, tuple[int, int]] = {"validation": VALIDATION, "test": TEST}

assert VALIDATION[1] <= TEST[0] and TEST[1] <= TRAINING[0], "the ranges must be disjoint"


def held_out_seeds(split: str, episodes: int) -> list[int]:
    """The first ``episodes`` layout seeds of the held-out range ``split``."""
    if split not in SPLITS:
        raise ValueError(f"split must be one of {sorted(SPLITS)}, got {split!r}")
    low, high = SPLITS[split]
    if isinstance(episodes, bool) or not isinstance(episodes, int) or episodes < 1:
        raise ValueError(f"episodes must be an int >= 1, got {episodes!r}")
    if episodes > high - low:
        raise ValueError(f"the {split} range holds {high - low} layouts, asked for {episodes}")
    return list(range(low, low + episodes))
