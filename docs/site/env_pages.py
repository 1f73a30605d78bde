"""Sphinx extension: writes the site's environment pages from the core before the build
reads its sources, into the folder ``environments`` beside this file (generated, not
committed):

- one page per registered id (``tactile_search.ENV_IDS``), in the shape of Gymnasium's env
  pages: its GIF (``docs/site/gifs.py``), then the sections ``scripts/environments_page.py``
  writes for ``docs/ENVIRONMENTS.md`` (Description, Action Space, Observation Space,
  Rewards, Starting State, Episode End, Arguments, Version History: the registry, each
  id's ``gymnasium.spec(id).kwargs`` over the defaults, the spaces of a made env, the info
  table), the observation layout and every setting with its default and range;
- the class page: ``CupboardSearchEnv``'s docstring (Markdown), the class every id makes;
- the index: the list of ids and the toctree.

A page is rewritten only when its text changes, so an incremental build reads only what
changed; pages of ids no longer registered are removed.
"""

from __future__ import annotations

import inspect
import os
from pathlib import Path
from typing import Any

import gymnasium as gym
from sphinx.application import Sphinx
from sphinx.util import logging

import tactile_search
from docs.site.gifs import caption, gif_path, shown_agent
from scripts.environments_page import (
    INTRO,
    id_list,
    observation_layout,
    section,
    settings_section,
)
from tactile_search import _core

LOGGER = logging.getLogger(__name__)
#: The folder of the generated pages, and its docname (the site's sources are ``docs/``).
PAGES = Path(__file__).resolve().parent / "environments"
PAGES_DOCNAME = "site/environments"
#: The page of the environment class's docstring (the API reference links to it).
CLASS_PAGE = "environment_class"


def page_name(env_id: str) -> str:
    """The page of ``env_id``: its name without the namespace (``CupboardSearch-v0``)."""
    return env_id.split("/")[-1]


def env_page(env: dict[str, Any]) -> str:
    """The page of one registered id (an entry of ``_core.registered_envs()``)."""
    title, body = section(env, level=1).split("\n", 1)
    gif = gif_path(env["id"])
    if gif.is_file():
        relative = Path(os.path.relpath(gif, PAGES)).as_posix()
        picture = [
            f"```{{figure}} {relative}",
            f":alt: {shown_agent(env['id'])} searching in {env['id']}",
            "",
            caption(env["id"], shown_agent(env["id"])),
            "```",
        ]
    else:
        LOGGER.warning(
            "no GIF for %s: %s is missing (python -m docs.site.gifs draws it)",
            env["id"],
            gif,
            type="tactile_search",
            subtype="gif",
        )
        picture = []
    return "\n".join(
        [
            title,
            "",
            *picture,
            body,
            observation_layout(level=2),
            settings_section(level=2),
            "## The environment class",
            "",
            f"Every id makes ``tactile_search.CupboardSearchEnv`` with its settings: "
            f"[its docstring]({CLASS_PAGE}.md) explains each part at the defaults.",
            "",
        ]
    )


def class_page() -> str:
    """``CupboardSearchEnv``'s docstring (written in Markdown) under a title."""
    doc = inspect.cleandoc(tactile_search.CupboardSearchEnv.__doc__ or "")
    return "\n".join(
        [
            "# The environment class",
            "",
            "``tactile_search.CupboardSearchEnv`` (``gymnasium.make`` of any registered id; "
            "``gymnasium.make_vec`` gives ``CupboardSearchVectorEnv``, the same episodes "
            "in one batch). Its docstring, at the default settings:",
            "",
            doc,
            "",
        ]
    )


def index_page(envs: list[dict[str, Any]]) -> str:
    names = [page_name(env["id"]) for env in envs]
    return "\n".join(
        [
            "# Environments",
            "",
            INTRO,
            "",
            *id_list(envs, lambda env_id: f"{page_name(env_id)}.md"),
            "",
            f"Every id is ``CupboardSearchEnv`` with its settings: [the class]({CLASS_PAGE}.md); "
            "[every id on one page](/ENVIRONMENTS.md), as in the repository.",
            "",
            "```{toctree}",
            ":hidden:",
            "",
            *names,
            CLASS_PAGE,
            "/ENVIRONMENTS",
            "```",
            "",
        ]
    )


def write_if_changed(path: Path, text: str) -> None:
    if not path.is_file() or path.read_text() != text:
        path.write_text(text)


def write_pages(app: Sphinx) -> None:
    """Writes the pages (the ``builder-inited`` event: before the sources are read)."""
    # Each id's settings as gymnasium applies them (its registration's kwargs).
    envs = [{**env, "settings": gym.spec(env["id"]).kwargs} for env in _core.registered_envs()]
    PAGES.mkdir(exist_ok=True)
    pages = {f"{page_name(env['id'])}.md": env_page(env) for env in envs}
    pages[f"{CLASS_PAGE}.md"] = class_page()
    pages["index.md"] = index_page(envs)
    for stale in set(p.name for p in PAGES.glob("*.md")) - set(pages):
        (PAGES / stale).unlink()
    for name, text in pages.items():
        write_if_changed(PAGES / name, text)


def setup(app: Sphinx) -> dict[str, Any]:
    app.connect("builder-inited", write_pages)
    return {"parallel_read_safe": True, "parallel_write_safe": True}
