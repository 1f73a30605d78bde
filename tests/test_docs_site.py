"""The documentation site (``make docs``, ``docs/site/``) builds with every warning an error
and every reference checked (``-W -n``: a broken link between pages, to a heading or to a
repository file fails it), with a page per registered id showing its GIF; and a link to a
path that exists nowhere does fail a build. Skipped where Sphinx is not installed (the
``docs`` extra)."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

pytest.importorskip("sphinx")
pytest.importorskip("myst_parser")
pytest.importorskip("furo")

import tactile_search
from docs.site.repo_links import REPOSITORY, repository_path

ROOT = Path(__file__).resolve().parents[1]


def sphinx_build(config: Path, sources: Path, out: Path) -> subprocess.CompletedProcess[str]:
    """``make docs``'s command (run from the repository root, as a module), into ``out``."""
    return subprocess.run(
        [sys.executable, "-m", "sphinx", "-W", "--keep-going", "-n", "-q",
         "-c", str(config), str(sources), str(out)],
        cwd=ROOT, capture_output=True, text=True, timeout=1800, check=False,
    )  # fmt: skip


def test_the_site_builds_with_warnings_as_errors_with_a_page_per_registered_id(
    tmp_path: Path,
) -> None:
    out = tmp_path / "html"
    done = sphinx_build(ROOT / "docs" / "site", ROOT / "docs", out)
    assert done.returncode == 0, done.stdout[-4000:] + done.stderr[-8000:]
    for env_id in tactile_search.ENV_IDS:
        name = env_id.split("/")[-1]
        page = out / "site" / "environments" / f"{name}.html"
        assert page.is_file(), f"no page for {env_id}"
        html = page.read_text()
        assert env_id in html
        assert f'src="../../_images/{name}.gif"' in html, f"the page of {env_id} shows no GIF"
        assert (out / "_images" / f"{name}.gif").is_file()
    assert (out / "index.html").is_file()
    assert (out / "site" / "api" / "tactile_search.benchmark.html").is_file()


def test_a_link_to_a_path_that_exists_nowhere_fails_the_build(tmp_path: Path) -> None:
    sources = tmp_path / "src"
    sources.mkdir()
    (sources / "conf.py").write_text(
        'extensions = ["myst_parser", "docs.site.repo_links"]\nmyst_heading_anchors = 6\n'
    )
    page = "# Title\n\n[here](#title), [there](notes/gone.md) and [a folder](gone/).\n"
    (sources / "index.md").write_text(page)
    done = sphinx_build(sources, sources, tmp_path / "html")
    assert done.returncode != 0
    assert "notes/gone.md" in done.stderr and "gone/" in done.stderr
    assert "#title" not in done.stderr  # the heading's anchor resolves

    (sources / "index.md").write_text("# Title\n\n[here](#title).\n")
    assert sphinx_build(sources, sources, tmp_path / "html2").returncode == 0


def test_links_to_repository_paths_resolve_from_the_citing_page_inside_the_repository() -> None:
    docs = REPOSITORY / "docs"
    assert repository_path("results/ablations_speed/", docs) == "docs/results/ablations_speed/"
    assert repository_path("../agents/train.py#L1", docs) == "agents/train.py"
    assert repository_path("results/no_such_folder/", docs) is None
    assert repository_path("../../../etc/passwd", docs) is None  # outside the repository
    assert repository_path("https://example.org/agents/train.py", docs) is None
