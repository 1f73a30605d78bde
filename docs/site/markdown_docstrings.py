"""Sphinx extension: the API reference's entry of ``CupboardSearchEnv``, whose docstring is
Markdown (Gymnasium's env-doc sections and tables, also what ``help()`` shows), keeps the
docstring's first line and links to the page that renders the whole docstring with MyST
(``env_pages.py``'s class page). Autodoc would read it as reStructuredText; any other
docstring with a Markdown heading fails the build, so none is shown garbled.
"""

from __future__ import annotations

import re
from typing import Any

from sphinx.application import Sphinx
from sphinx.util import logging

import tactile_search
from docs.site.env_pages import CLASS_PAGE, PAGES_DOCNAME

LOGGER = logging.getLogger(__name__)
MARKDOWN_HEADING = re.compile(r"^#{1,6} ")


def point_to_the_class_page(
    app: Sphinx, what: str, name: str, obj: Any, options: Any, lines: list[str]
) -> None:
    """The ``autodoc-process-docstring`` event: rewrites ``lines`` in place."""
    if not any(MARKDOWN_HEADING.match(line) for line in lines):
        return
    if obj is not tactile_search.CupboardSearchEnv:
        LOGGER.warning(
            "the docstring of %s is Markdown (a '#' heading), which autodoc reads as "
            "reStructuredText: write it in reStructuredText",
            name,
            type="tactile_search",
            subtype="markdown_docstring",
        )
        return
    summary = lines[0]
    lines[:] = [
        summary,
        "",
        f"Its docstring (the spaces, rewards, episode end and every argument) is rendered on "
        f":doc:`/{PAGES_DOCNAME}/{CLASS_PAGE}`.",
        "",
    ]


def setup(app: Sphinx) -> dict[str, Any]:
    app.setup_extension("sphinx.ext.autodoc")
    app.connect("autodoc-process-docstring", point_to_the_class_page)
    return {"parallel_read_safe": True, "parallel_write_safe": True}
