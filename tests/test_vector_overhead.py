"""``benchmarks.vector_overhead`` measures the vector env's face on the core's very work."""

from __future__ import annotations

import numpy as np


def test_vector_overhead_replays_the_faces_batch_calls_on_the_same_work() -> None:
    from benchmarks.vector_overhead import env_pair, random_actions

    face, core = env_pair("none", "wrist", num_envs=3)
    for action in random_actions(face, 400, seed=0):  # long enough to cross autoresets
        face.step(action)
    calls = face._batch.calls
    assert len(calls) == 400 and any(resets for _, resets in calls)
    for action, resets in calls:
        core._batch.step(action, resets)
    for a, b in zip(face._batch.observe(), core._batch.observe(), strict=True):
        np.testing.assert_array_equal(a, b)  # the core did the face's work, no more
