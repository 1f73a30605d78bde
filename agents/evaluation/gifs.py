"""Example GIFs of an agent's episode, drawn motion by motion (a probe-mode step replayed
in a wrist-mode twin), with their provenance stored in the GIF's comment."""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any

import numpy as np

from agents.rollout import run_episodes
from tactile_search import CupboardSearchEnv


def record_gif(
    path: Path,
    agent: Any,
    env_kwargs: dict[str, Any],
    seed: int,
    max_steps: int = 200,
    stride: int = 2,
    drawn_by: str | None = None,
) -> None:
    """The first ``max_steps`` steps of ``agent`` on layout ``seed`` in the env of
    ``env_kwargs`` as a GIF, one frame every ``stride`` wrist motions plus the last (a frame
    takes ~0.2 s to draw); ``drawn_by`` (``gif_provenance``) is stored in the GIF's comment.

    In the ``probe`` action mode a step is many wrist motions: a ``wrist``-mode twin of the
    env, reset to the same layout, replays each step's motions (``last_motions``) so that
    the GIF shows the finger moving, not only where each probe ends."""
    from tactile_search.render import save_gif

    frames: list[np.ndarray] = []
    twin: CupboardSearchEnv | None = None
    motions_drawn = 0  # wrist motions so far

    def capture(env: CupboardSearchEnv, step: int, done: bool) -> None:
        nonlocal twin, motions_drawn
        if env.config.action_mode == "wrist":
            if step % stride == 0 or done:
                frames.append(env.render())
            return
        if step == 0:
            wrist = {**env_kwargs, "action_mode": "wrist"}
            twin = CupboardSearchEnv(render_mode="rgb_array", **wrist)
            twin.reset(seed=seed)
            frames.append(twin.render())
            return
        assert twin is not None
        motions = env.last_motions()
        # The identify task's actions carry a claim entry after the motion: 0, no claim.
        extra = twin.action_space.shape[0] - motions.shape[1] if len(motions) else 0
        for i, motion in enumerate(motions):
            twin.step(np.r_[motion, np.zeros(extra)])
            motions_drawn += 1
            if motions_drawn % stride == 0 or (done and i == len(motions) - 1):
                frames.append(twin.render())
        if env.render_state().get("claim") is not None and twin.render_state().get("claim") is None:
            # A claim makes no motion: the twin claims too, and the frame shows its ring.
            twin.step(np.r_[np.zeros(3), 1.0])
            frames.append(twin.render())
        if twin.render_state()["hand"] != env.render_state()["hand"]:
            raise RuntimeError(
                f"the wrist-mode replay of layout {seed} left the probe's path at step {step}"
            )

    run_episodes(
        agent, [seed], max_steps=max_steps, on_step=capture, render_mode="rgb_array", **env_kwargs
    )
    if twin is not None:
        twin.close()
    # Through a temporary file: a GIF that exists is a whole one.
    tmp = path.with_name(f"{path.stem}.tmp.gif")
    save_gif(frames, tmp, comment=drawn_by)
    os.replace(tmp, path)


def gif_provenance(fingerprint: str, seed: int, max_steps: int) -> str:
    """What an example GIF shows, as stored in its comment: the agent's fingerprint
    (``code_fingerprints``), the layout and the steps shown. A GIF is kept only if its
    comment says the same (``gif_drawn_by``), so a GIF left by other code is drawn again."""
    return f"tactile_search example: fingerprint {fingerprint}, layout {seed}, {max_steps} steps"


def gif_drawn_by(path: Path) -> str | None:
    """The provenance stored in the GIF at ``path`` (``record_gif``), or None if there is no
    such GIF or it stores none."""
    from PIL import Image

    try:
        with Image.open(path) as image:
            comment = image.info.get("comment")
    except (OSError, ValueError):  # missing, or not an image
        return None
    return comment.decode(errors="replace") if isinstance(comment, bytes) else None
