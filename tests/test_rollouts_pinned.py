"""Same seed and actions give the same observations, rewards and infos as when
``tests/data/rollouts.npz`` was recorded, bit for bit: for the single, the vector and the SB3
env in every map mode (observations compared by sha256 of their bytes, proprio and infos as
arrays). It was recorded by ``tests/rollouts.py`` after the physics and reset speed work
(see that module for what changed on purpose then); the ``info["truncated"]`` key is not in
the pinned file."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from tests.rollouts import record_all

PINNED = Path(__file__).parent / "data" / "rollouts.npz"


def test_rollouts_are_unchanged_bit_for_bit() -> None:
    pytest.importorskip("stable_baselines3")
    pinned = np.load(PINNED)
    now = record_all()
    assert sorted(now) == sorted(pinned.files)
    for key in pinned.files:
        np.testing.assert_array_equal(now[key], pinned[key], err_msg=key)
