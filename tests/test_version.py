"""The version is typed once: ``tactile_search.__version__`` is the installed metadata's,
which maturin takes from ``Cargo.toml``'s workspace version, as the compiled core's is (a
stale build differs); ``CHANGELOG.md`` has a section for that version and for every
registered id."""

from __future__ import annotations

import re
from importlib.metadata import version
from pathlib import Path

import tactile_search
from tactile_search import _core

ROOT = Path(__file__).resolve().parents[1]


def changelog_headings() -> set[str]:
    text = (ROOT / "CHANGELOG.md").read_text()
    return {match.strip() for match in re.findall(r"^###\s+(.+)$", text, flags=re.MULTILINE)}


def test_the_version_is_the_metadatas_and_the_one_cargo_compiled_into_the_core() -> None:
    # The core's is env!("CARGO_PKG_VERSION"): Cargo.toml's when the extension was built.
    assert tactile_search.__version__ == version("tactile_search") == _core.__version__


def test_the_changelog_has_the_packages_version_and_every_registered_id() -> None:
    headings = changelog_headings()
    names = (tactile_search.__version__, *tactile_search.ENV_IDS)
    missing = [name for name in names if name not in headings]
    assert not missing, f"CHANGELOG.md has no '### NAME' section for {missing}"
