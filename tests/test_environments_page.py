"""``docs/ENVIRONMENTS.md`` is what ``scripts/environments_page.py`` writes from the core's
tables today: one section per registered id, each with Gymnasium's env-doc headings."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import tactile_search

ROOT = Path(__file__).resolve().parents[1]
HEADINGS = (
    "### Description",
    "### Action Space",
    "### Observation Space",
    "### Rewards",
    "### Starting State",
    "### Episode End",
    "### Arguments",
    "### Version History",
)


def test_the_committed_page_is_the_scripts_output() -> None:
    done = subprocess.run(
        [sys.executable, str(ROOT / "scripts" / "environments_page.py"), "--check"],
        capture_output=True, text=True, timeout=300, check=False,
    )  # fmt: skip
    assert done.returncode == 0, done.stdout + done.stderr


def test_every_registered_id_has_a_section_with_every_heading() -> None:
    page = (ROOT / "docs" / "ENVIRONMENTS.md").read_text()
    sections = page.split("\n## ")
    for env_id in tactile_search.ENV_IDS:
        section = next(s for s in sections if s.startswith(f"`{env_id}`"))
        positions = [section.index(heading) for heading in HEADINGS]
        assert positions == sorted(positions), env_id
