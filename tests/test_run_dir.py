"""``agents/run_dir.py`` is the only code that knows what a run folder's files are called:
every other module of ``agents`` reaches them through its functions, so a renamed file is
renamed in one place, and no reader of a run folder drifts from its writer."""

from __future__ import annotations

import ast
import re
from pathlib import Path

import pytest

from agents import run_dir

AGENTS = Path(run_dir.__file__).parent
# File names, each found wherever it appears as a word of a string.
FILE_NAMES = (
    run_dir.CONFIG_FILE,
    run_dir.MODEL_FILE,
    run_dir.PROGRESS_FILE,
    run_dir.CHECKPOINT_PREFIX,
    run_dir.DEMONSTRATIONS_FILE,
    run_dir.TEACHER_DEMONSTRATIONS_FILE,
)
# Directory names that are also plain words: found as a whole string or beside a path
# separator. (``CLONE_DIR`` and ``ROUNDS_DIR`` are left out: "imitation" is a recipe key and
# "rounds" a config key, and ``agents.imitate`` writes its runs under ``runs/imitation``.)
DIRECTORY_NAMES = (run_dir.CHECKPOINT_DIR,)
FILE_NAME = re.compile(rf"(?<![\w.])({'|'.join(map(re.escape, FILE_NAMES))})(?!\w)")


def typed_names(text: str) -> list[str]:
    """The run folder's names ``text`` (a string of the code) types."""
    found = FILE_NAME.findall(text)
    for name in DIRECTORY_NAMES:
        if text == name or f"{name}/" in text or f"/{name}" in text:
            found.append(name)
    return found


def code_strings(tree: ast.AST) -> list[ast.Constant]:
    """The string constants of a module that are code: not docstrings nor other bare string
    statements (documentation, which may name the files)."""
    documentation = {
        id(node.value)
        for node in ast.walk(tree)
        if isinstance(node, ast.Expr) and isinstance(node.value, ast.Constant)
    }
    return [
        node
        for node in ast.walk(tree)
        if isinstance(node, ast.Constant)
        and isinstance(node.value, str)
        and id(node) not in documentation
    ]


def test_the_scan_finds_typed_names_and_not_words():
    assert typed_names(f"{run_dir.CONFIG_FILE}") == [run_dir.CONFIG_FILE]
    assert typed_names(f"a run directory with {run_dir.MODEL_FILE}") == [run_dir.MODEL_FILE]
    assert typed_names(f"{run_dir.CHECKPOINT_DIR}/") == [run_dir.CHECKPOINT_DIR]
    assert typed_names("none of the checkpoints loads") == []
    assert typed_names(f"x_{run_dir.DEMONSTRATIONS_FILE}") == []
    assert typed_names(run_dir.CHECKPOINT_DIR) == [run_dir.CHECKPOINT_DIR]


@pytest.mark.parametrize(
    "path",
    sorted(p for p in AGENTS.rglob("*.py") if p != Path(run_dir.__file__)),
    ids=lambda p: str(p.relative_to(AGENTS.parent)),
)
def test_no_module_but_run_dir_types_a_run_folder_name(path: Path):
    tree = ast.parse(path.read_text(), filename=str(path))
    typed = [
        f"line {node.lineno}: {name!r}"
        for node in code_strings(tree)
        for name in typed_names(node.value)
    ]
    assert not typed, (
        f"{path} types the run folder's names ({', '.join(typed)}): use agents.run_dir's "
        "functions (config_path, model_path, checkpoint_dir, ...) or its constants"
    )
