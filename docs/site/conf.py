"""Sphinx configuration of the documentation site (``make docs``: the HTML goes into the
folder ``_build/html`` under ``docs/``).

The source folder is ``docs/`` and this folder holds the configuration and the site's own
pages (``python -m sphinx -c docs/site docs OUT``): the pages ``docs/*.md`` are
read where they are, so their links to each other and their pictures resolve as on the
repository's web view, and nothing is copied. Run it from the repository root as a module
(``python -m sphinx``): the site's extensions are the modules ``docs.site.*`` (the rule of
``docs/DESIGN.md`` §1.1: nothing patches ``sys.path``).

Links to repository files that are not pages of the site (``docs/results/...``, source
files) go to ``repository_url`` when it is set (``-D repository_url=URL``, the web view of
the repository's tree at a commit) and are shown as paths otherwise (``repo_links.py``);
either way a link to a path that does not exist fails the build.
"""

from __future__ import annotations

import importlib.util
from pathlib import Path

from sphinx.application import Sphinx

import tactile_search

if importlib.util.find_spec("docs") is None or importlib.util.find_spec("docs.site") is None:
    raise RuntimeError(
        "the site's extensions (docs.site.*) are not importable: run Sphinx from the "
        "repository root as a module (make docs), e.g. "
        "python -m sphinx -c docs/site docs docs/_build/html"
    )

project = "tactile_search"
author = "the tactile_search authors"
release = tactile_search.__version__
version = release

extensions = [
    "myst_parser",
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.napoleon",
    "docs.site.env_pages",
    "docs.site.repo_links",
    "docs.site.markdown_docstrings",
]

# The sources: docs/*.md (the repository's pages, the leaderboard's when it exists) and the
# site's own pages here, with the generated ones (environments/, and api/: autosummary's
# page per module); not the Markdown written under docs/results/ and docs/paper/.
root_doc = "site/index"
include_patterns = ["*.md", "site/**.md", "site/api/*.rst"]
source_suffix = {".md": "markdown", ".rst": "restructuredtext"}
exclude_patterns = ["_build/**"]
# Absolute: the theme reads templates_path from this folder, autosummary from the sources'.
templates_path = [str(Path(__file__).resolve().parent / "_templates")]
# The site's root folder gets an index.html that forwards to the root page (site/index).
html_additional_pages = {"index": "redirect.html"}

html_theme = "furo"
html_title = f"tactile_search {release}"
html_show_sourcelink = False

# Headings get GitHub's anchors (``#4-the-episode``), so ``DESIGN.md#4-the-episode`` in
# a page resolves here as it does on the repository's web view, and is checked.
myst_heading_anchors = 6

# Every reference is checked (-n), but the Python objects of other libraries (numpy,
# gymnasium, torch, the standard library), which have no inventory here (the build reads
# nothing from the network), and the free text napoleon reads as a type ("#: The seed: ...").
# References to the package's own objects (``tactile_search.*``) are checked.
nitpicky = True
nitpick_ignore_regex = [(r"py:.*", r"(?!tactile_search\.).*")]

autosummary_generate = True
autodoc_member_order = "bysource"
autodoc_typehints = "description"
# Methods without a docstring of their own are not shown with gymnasium's (written for its
# own site's roles).
autodoc_inherit_docstrings = False
autodoc_default_options = {"members": True, "show-inheritance": True, "ignore-module-all": True}
# The networks need torch (the agents extra) and the Ray page's modules Ray and SB3: the
# site documents them without (the mocks stand in even where they are installed).
autodoc_mock_imports = ["torch", "stable_baselines3", "sb3_contrib", "ray", "yaml", "tqdm", "rich"]

# Links to repository files: their web view, e.g. https://github.com/OWNER/REPO/blob/COMMIT;
# empty shows them as paths (repo_links.py).
repository_url = ""

#: The leaderboard (written from the results' JSON by ``python -m
#: tactile_search.benchmark.leaderboard``) is a page of the site when it exists.
LEADERBOARD = Path(__file__).resolve().parents[1] / "LEADERBOARD.md"


def add_the_leaderboard(app: Sphinx, docname: str, source: list[str]) -> None:
    """The ``source-read`` event: the root page's toctree of the leaderboard, when it exists."""
    if docname == root_doc and LEADERBOARD.is_file():
        source[0] += "\n```{toctree}\n:caption: Leaderboard\n\n/LEADERBOARD\n```\n"


def setup(app: Sphinx) -> None:
    app.connect("source-read", add_the_leaderboard)
