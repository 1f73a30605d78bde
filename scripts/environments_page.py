"""Writes ``docs/ENVIRONMENTS.md``: one section per registered id in the shape of Gymnasium's
environment docs (Description, Action Space, Observation Space, Rewards, Starting State,
Episode End, Arguments, Version History), every fact read from the core: the registry
(``_core.registered_envs()``: the id's task, settings, description, episode end and
history), the spaces of an env made with those settings, the info table's reward terms and
the settings table. ``tests/test_environments_page.py`` checks the committed page is this
script's output. The documentation site's environment pages are made of the same sections
(``docs/site/env_pages.py`` imports them).

    python scripts/environments_page.py            # rewrite docs/ENVIRONMENTS.md
    python scripts/environments_page.py --check    # exit 1 if it is out of date
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Callable
from pathlib import Path
from typing import Any

import gymnasium as gym

from tactile_search import _core
from tactile_search.envs.config import SETTINGS, arguments_table, markdown_table
from tactile_search.envs.observation import STEP_INFO, map_channel_table, proprio_table

PAGE = Path(__file__).resolve().parents[1] / "docs" / "ENVIRONMENTS.md"
DEFAULTS: dict[str, Any] = {s["key"]: s["default"] for s in SETTINGS}
INTRO = (
    "Every registered id, in the shape of Gymnasium's environment docs. Each id is the same "
    "environment class with the settings of its task and tier."
)
#: What each entry of an action is, by action mode (the claim entry only where the task
#: claims: the made env's action space says how many entries there are).
ENTRIES = {
    "wrist": [
        "dx, along the opening: ± max_step_translation ({max_step_translation} m)",
        "dy, into the cupboard: ± max_step_translation ({max_step_translation} m)",
        "dyaw, about the vertical: ± max_step_yaw ({max_step_yaw} rad)",
        "claim: above {claim_threshold} claims the jar the finger touches (no motion)",
    ],
    "probe": [
        "lane across the opening: 0 to probe_lanes - 1",
        "wrist depth: 0 to probe_depths - 1",
        "sweep angle: 0 to probe_sweeps - 1",
        "claim: 1 claims the jar the finger touches (no motion), 0 probes",
    ],
}


def code(value: Any) -> str:
    return f"``{value!r}``" if isinstance(value, str) else f"``{value}``"


def reward_rows(settings: dict[str, Any]) -> list[list[str]]:
    """Each reward term: its info key, formula (the info table's doc), its weight setting
    and that weight in this id (a weight setting's key is the term's, or starts with it)."""
    rows = []
    for key, (_, doc) in STEP_INFO.items():
        if not key.startswith("reward_"):
            continue
        weight = next(s for s in DEFAULTS if s == key or s.startswith(key + "_"))
        rows.append([f"``{key}``", doc, f"``{weight}``", code(settings[weight])])
    return rows


def section(env: dict[str, Any], level: int = 2) -> str:
    """The section of one registered id (an entry of ``_core.registered_envs()``): its
    heading at ``level`` (``##`` by default), Gymnasium's headings one level below. Its
    links point at the page's ``Observation layout`` and ``Settings`` sections
    (``observation_layout`` and ``settings_section``)."""
    title, sub = "#" * level, "#" * (level + 1)
    settings = {**DEFAULTS, **env["settings"]}
    made = {mode: gym.make(env["id"], action_mode=mode).unwrapped for mode in ("wrist", "probe")}
    batch = made["wrist"]._batch
    facts = {**settings, "claim_threshold": batch.claim_threshold}
    presets = ", ".join(f"{k}={v!r}" for k, v in env["settings"].items())
    lines = [
        f"{title} `{env['id']}`",
        "",
        env["summary"][0].upper() + env["summary"][1:] + ".",
        "",
        "```python",
        f'env = gymnasium.make("{env["id"]}")',
        *([f"# its settings: {presets}"] if presets else []),
        "```",
        "",
        f"{sub} Description",
        "",
        env["description"],
        f"A cupboard {settings['cupboard_width']} m wide and {settings['cupboard_depth']} m "
        f"deep holds {settings['jar_count'][0]} to {settings['jar_count'][1]} jars.",
        "",
        f"{sub} Action Space",
        "",
    ]
    rows = []
    for mode, env_made in made.items():
        n = int(env_made.action_space.shape[0])
        entries = "; ".join(e.format(**facts) for e in ENTRIES[mode][:n])
        rows.append([f"``{mode!r}``", f"``{env_made.action_space}``", entries])
    lines += [markdown_table(["action_mode", "space", "entries"], rows), ""]
    lines += [f"{sub} Observation Space", ""]
    rows = []
    for map_mode in ("gpis", "occupancy", "none"):
        space = gym.make(env["id"], map=map_mode).observation_space
        rows.append([f"``{map_mode!r}``", f"``{space}``"])
    lines += [
        markdown_table(["map", "space"], rows),
        "",
        "The map's channels and the proprio entries: [Observation layout](#observation-layout).",
        "",
        f"{sub} Rewards",
        "",
        "The reward is the sum of these terms, each in ``info`` under its key:",
        "",
        markdown_table(["info key", "term", "weight setting", "weight"], reward_rows(settings)),
        "",
        f"{sub} Starting State",
        "",
        "A new layout drawn from the reset's seed, the depth camera's first look (a noisy "
        "horizontal slice at mid-jar height), the map started from it, and the hand at "
        f"hand_start {tuple(settings['hand_start'])} outside the opening.",
        "",
        f"{sub} Episode End",
        "",
        env["episode_end"] + f" max_steps = {settings['max_steps']}.",
        "",
        f"{sub} Arguments",
        "",
    ]
    if env["settings"]:
        rows = [[f"``{k}``", code(v), code(DEFAULTS[k])] for k, v in env["settings"].items()]
        lines += [
            "This id's settings over the defaults (every keyword argument of ``gym.make`` "
            "goes over them; the rest are in [Settings](#settings)):",
            "",
            markdown_table(["argument", "value", "default"], rows),
        ]
    else:
        lines += ["The defaults, every one in [Settings](#settings)."]
    lines += ["", f"{sub} Version History", "", env["history"], ""]
    for env_made in made.values():
        env_made.close()
    return "\n".join(lines)


def id_list(envs: list[dict[str, Any]], link: Callable[[str], str] | None = None) -> list[str]:
    """A list item per registered id: the id, linked to ``link(id)`` (by default its
    section's anchor on this page), and its summary."""
    target = link or (lambda env_id: f"#{anchor(env_id)}")
    return [f"- [`{env['id']}`]({target(env['id'])}): {env['summary']}" for env in envs]


def render() -> str:
    envs = _core.registered_envs()
    header = [
        "# Environments",
        "",
        "<!-- Written by `python scripts/environments_page.py` from the core's tables; do not "
        "edit by hand. -->",
        "",
        INTRO,
        "",
        *id_list(envs),
        "",
    ]
    sections = [section(env) for env in envs]
    return "\n".join([*header, *sections, observation_layout(), settings_section()])


def observation_layout(level: int = 2) -> str:
    """The ``Observation layout`` section, the same in every id: the map channels and the
    proprio entries (the core's observation layout)."""
    return "\n".join(
        [
            "#" * level + " Observation layout",
            "",
            "The same in every id. ``map`` channels:",
            "",
            map_channel_table(),
            "",
            "``proprio`` entries, each in [-1, 1]:",
            "",
            proprio_table(),
            "",
        ]
    )


def settings_section(level: int = 2) -> str:
    """The ``Settings`` section: every keyword argument with its type, default and range
    (the core's settings table)."""
    return "\n".join(
        [
            "#" * level + " Settings",
            "",
            "Every keyword argument, its type, default and range:",
            "",
            arguments_table(),
            "",
        ]
    )


def anchor(env_id: str) -> str:
    """GitHub's heading anchor of ``## `env_id` ``."""
    return "".join(c for c in env_id.lower() if c.isalnum() or c in "-_ ").replace(" ", "-")


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--check", action="store_true", help="exit 1 if the page is stale")
    args = parser.parse_args()
    page = render()
    if args.check:
        if not PAGE.is_file() or PAGE.read_text() != page:
            print(f"{PAGE} is out of date: run python scripts/environments_page.py")
            return 1
        return 0
    PAGE.write_text(page)
    return 0


if __name__ == "__main__":
    sys.exit(main())
