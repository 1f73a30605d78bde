"""Draws the environment pages' GIFs: on each registered id, the scripted planner of its task
searches one validation layout, drawn motion by motion as ``agents.evaluation.gifs`` draws
the evaluation's GIFs, then written small: one palette of few colours shared by every frame
(the drawing's solid colours and the map's ramps), no dithering, so that a frame stores
only what changed. The site's build reads only the files; drawing them needs the
repository's ``agents`` package and Pillow (the ``plots`` extra), not torch.

    python -m docs.site.gifs            # every id's GIF, into docs/site/_static/envs/
    python -m docs.site.gifs --check    # exit 1 if a registered id has no GIF
"""

from __future__ import annotations

import argparse
import os
import sys
import tempfile
from pathlib import Path
from typing import Any

import gymnasium as gym
import numpy as np

import tactile_search
from tactile_search import render
from tactile_search.seed_ranges import VALIDATION

#: Where the GIFs are, one per registered id, named by the id's name (``gif_path``).
GIF_DIR = Path(__file__).resolve().parent / "_static" / "envs"
#: The layout every GIF shows: the first validation layout.
LAYOUT = VALIDATION[0]
#: At most this many probes are shown, one frame every ``STRIDE`` wrist motions.
MAX_PROBES = 12
STRIDE = 6
#: Colours of the shared palette.
COLOURS = 64


def gif_path(env_id: str) -> Path:
    """The GIF of ``env_id`` (``tactile_search/CupboardSearch-v0`` ->
    ``CupboardSearch-v0.gif``)."""
    return GIF_DIR / f"{env_id.split('/')[-1]}.gif"


def shown_agent(env_id: str) -> str:
    """The name of the scripted agent a GIF shows: the first of the core's planners (the
    learned agents' teachers) that plays the id's task."""
    from agents.scripted import CORE_PLANNERS, scripted_agents_for

    task = gym.spec(env_id).kwargs.get("task", "search")
    planners = [name for name in scripted_agents_for(task) if name in CORE_PLANNERS]
    if not planners:
        raise ValueError(f"no core planner plays the task {task!r} of {env_id}")
    return planners[0]


def caption(env_id: str, agent: str) -> str:
    """What the GIF of ``env_id`` shows (the page's caption, and the GIF's comment)."""
    return (
        f"The scripted `{agent}` on validation layout {LAYOUT} of `{env_id}` "
        f"(at most {MAX_PROBES} probes; `python -m docs.site.gifs`)."
    )


def shared_palette(last_frame: Any) -> Any:
    """A palette image of ``COLOURS`` colours: every solid colour ``tactile_search.render``
    draws with (walls, jars, hand, contacts, outlines: few pixels, which a palette fitted to
    the pixels alone would merge away), then the rest fitted to the last frame (the map's
    ramps at their widest)."""
    from PIL import Image

    solid = [
        int(channel)
        for value in vars(render).values()
        if isinstance(value, np.ndarray) and value.dtype == np.uint8 and value.shape == (3,)
        for channel in value
    ]
    fitted = last_frame.quantize(colors=COLOURS - len(solid) // 3, dither=Image.Dither.NONE)
    palette = Image.new("P", (1, 1))
    palette.putpalette(solid + fitted.getpalette()[: 3 * (COLOURS - len(solid) // 3)])
    return palette


def draw(env_id: str) -> Path:
    """Draws the GIF of ``env_id`` and returns its path."""
    from PIL import Image, ImageSequence

    from agents.evaluation.gifs import record_gif
    from agents.scripted import SCRIPTED_AGENTS

    agent = shown_agent(env_id)
    env_kwargs = {**gym.spec(env_id).kwargs, "action_mode": "probe"}
    path = gif_path(env_id)
    path.parent.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory() as folder:
        drawn = Path(folder) / "drawn.gif"
        record_gif(
            drawn, SCRIPTED_AGENTS[agent](), env_kwargs, LAYOUT, max_steps=MAX_PROBES, stride=STRIDE
        )
        with Image.open(drawn) as gif:
            frames = [frame.convert("RGB") for frame in ImageSequence.Iterator(gif)]
        palette = shared_palette(frames[-1])
        small = [frame.quantize(palette=palette, dither=Image.Dither.NONE) for frame in frames]
        written = Path(folder) / "small.gif"
        small[0].save(
            written,
            save_all=True,
            append_images=small[1:],
            duration=120,
            loop=0,
            optimize=True,
            comment=caption(env_id, agent).encode(),
        )
        os.replace(written, path)
    return path


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--check", action="store_true", help="exit 1 if an id has no GIF")
    args = parser.parse_args()
    if args.check:
        missing = [env_id for env_id in tactile_search.ENV_IDS if not gif_path(env_id).is_file()]
        for env_id in missing:
            print(f"no GIF for {env_id}: {gif_path(env_id)} (python -m docs.site.gifs)")
        return 1 if missing else 0
    for env_id in tactile_search.ENV_IDS:
        path = draw(env_id)
        print(f"{env_id}: {path} ({path.stat().st_size / 1000:.0f} kB)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
