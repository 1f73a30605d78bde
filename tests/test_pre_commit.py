"""The pre-commit hooks run the project's own lints: exactly the make targets ``make lint``
is made of, so the Makefile stays the one list of lints."""

from __future__ import annotations

import re
from pathlib import Path

import yaml

REPO = Path(__file__).resolve().parent.parent


def test_the_pre_commit_hooks_are_the_targets_of_make_lint() -> None:
    makefile = (REPO / "Makefile").read_text()
    lint = re.search(r"^lint:([^#\n]*)", makefile, flags=re.MULTILINE)
    assert lint is not None, "the Makefile has a lint target"
    targets = lint.group(1).split()
    config = yaml.safe_load((REPO / ".pre-commit-config.yaml").read_text())
    hooks = [hook for repo in config["repos"] for hook in repo["hooks"]]
    assert [hook["entry"] for hook in hooks] == [f"make {target}" for target in targets]
    for hook in hooks:
        assert hook["language"] == "system" and hook["pass_filenames"] is False
        # Each runs when a Rust source changes (the stub check reads the core too).
        assert re.compile(hook["files"]).search("env_core/src/lib.rs")
