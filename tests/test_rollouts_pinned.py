"""Same seed and actions give the same observations, rewards and infos as when
``tests/data/rollouts.npz`` (and, for every other registered id, the tasks and tiers,
``rollouts_registered.npz``) was recorded, bit for bit: for the single, the vector and the SB3
env in every map mode (observations compared by sha256 of their bytes, proprio and infos as
arrays). It was recorded by ``tests/rollouts.py`` after the physics and reset speed work
(see that module for what changed on purpose then); the ``info["truncated"]`` key is not in
the pinned file."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from tests.rollouts import record_all, record_registered

PINNED = Path(__file__).parent / "data" / "rollouts.npz"
#: Every other registered id (each task and tier), in both action modes.
PINNED_REGISTERED = Path(__file__).parent / "data" / "rollouts_registered.npz"


def test_rollouts_are_unchanged_bit_for_bit() -> None:
    pytest.importorskip("stable_baselines3")
    pinned = np.load(PINNED)
    now = record_all()
    assert sorted(now) == sorted(pinned.files)
    for key in pinned.files:
        np.testing.assert_array_equal(now[key], pinned[key], err_msg=key)


def test_every_other_registered_ids_rollouts_are_unchanged_bit_for_bit() -> None:
    pinned = np.load(PINNED_REGISTERED)
    now = record_registered()
    # Every id and field pinned is still recorded; an info key added since may be new.
    assert {key.split("/info/")[0] for key in now} == {
        key.split("/info/")[0] for key in pinned.files
    }
    assert set(pinned.files) <= set(now)
    for key in pinned.files:
        np.testing.assert_array_equal(now[key], pinned[key], err_msg=key)
