"""Sphinx extension: links from a page to repository files and folders that are not pages of
the site (``docs/results/ablations_speed/``, ``results/planner_probe/probe_grid.md``, a
figure's PNG).

MyST turns a Markdown link to a path into a reference to a page, a download of a file, or a
reference it cannot resolve (a folder). While the page is read (before Sphinx collects its
downloads and MyST resolves its references), each such link whose path exists in the
repository (relative to the page's source, as on the repository's web
view) becomes a link to ``repository_url`` + its path from the repository's root, or, with
no ``repository_url``, the path itself as code. A path that exists nowhere is left to MyST,
which warns (``myst.xref_missing``): with ``-W`` the build fails on a broken link.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

from docutils import nodes
from sphinx import addnodes
from sphinx.application import Sphinx
from sphinx.transforms import SphinxTransform

#: The repository's root: links resolve only to paths inside it.
REPOSITORY = Path(__file__).resolve().parents[2]


def repository_path(target: str, citing_folder: Path) -> str | None:
    """``target`` (a link's path, anchor dropped) from the folder of the page that cites it,
    as a path from the repository's root (a folder ends in ``/``), or None if it is not an
    existing path inside the repository."""
    path_part = target.split("#", 1)[0]
    if not path_part or "://" in path_part:
        return None
    path = (citing_folder / path_part).resolve()
    if not path.exists() or not path.is_relative_to(REPOSITORY):
        return None
    relative = path.relative_to(REPOSITORY).as_posix()
    return relative + "/" if path.is_dir() else relative


class RepositoryLinks(SphinxTransform):
    """Replaces the links to repository paths that are not pages (see the module doc)."""

    default_priority = 500

    def apply(self, **kwargs: Any) -> None:
        links = [
            node
            for node in self.document.findall(nodes.Element)
            if isinstance(node, addnodes.pending_xref | addnodes.download_reference)
            and node.get("reftype") == "myst"
        ]
        for node in links:
            relative = self.unresolved_path(node)
            if relative is not None:
                node.replace_self(self.repository_link(relative, node))

    def unresolved_path(self, node: nodes.Element) -> str | None:
        """The repository path of a link MyST would not resolve to a page: a download, a
        path that is no page, or a page left out of the site (``include_patterns``)."""
        citing_folder = Path(self.env.doc2path(node["refdoc"])).parent
        if isinstance(node, addnodes.download_reference):
            return repository_path(node["reftarget"], citing_folder)
        if node.get("refdomain") == "doc":
            if node["reftarget"] in self.env.found_docs:
                return None
            source = Path(self.env.doc2path(node["reftarget"]))
            return repository_path(str(source), citing_folder)
        return repository_path(node["reftarget"], citing_folder)

    def repository_link(self, relative: str, node: nodes.Element) -> nodes.Node:
        url = self.config.repository_url
        text = node.astext()
        if url:
            link = nodes.reference("", "", internal=False, refuri=f"{url.rstrip('/')}/{relative}")
            link += (
                nodes.literal(text, text)
                if text.strip("`/") in relative
                else nodes.inline(text, text)
            )
            return link
        if text.strip("`/") in relative:
            return nodes.literal(relative, relative)
        shown = nodes.inline()
        shown += [nodes.Text(f"{text} ("), nodes.literal(relative, relative), nodes.Text(")")]
        return shown


def setup(app: Sphinx) -> dict[str, Any]:
    app.add_config_value("repository_url", "", "html", types=frozenset({str}))
    app.add_transform(RepositoryLinks)
    return {"parallel_read_safe": True, "parallel_write_safe": True}
