"""Every repository path the docs, comments and docstrings name exists.

Scanned: ``README.md``, ``CONTRIBUTING.md`` and ``docs/*.md`` whole (code blocks too: a
command's paths must be true), and the comments and docstrings of every ``*.rs``, ``*.py``,
``*.yml`` and the ``Makefile`` (string literals in code are not prose and are not read).
Skipped: what is
generated or not ours (``.git``, ``.venv``, ``target``, ``runs``, ``results``, caches,
``docs/results/`` and ``docs/paper/``, written by ``make results`` and ``make paper``).

A token is a repository path when it holds a ``/`` and either starts with a top-level
folder (``env_core/``, ``python/``, ``agents/``, ...) or ``src/``, or ends with a file
extension of ours (``.rs``, ``.py``, ``.md``, ...); a bare file name is one when it ends
with a source extension (``.rs``, ``.py``, ``.pyi``, ``.md``, ``.yml``, ``.toml``: data files
named bare are mostly written at run time). URLs, absolute paths and templates (``<algo>``,
``{name}``) are not. How a path resolves:

- one that starts with a top-level folder: from the repository root, or from a folder
  above the citing file (in a file of ``env_core/src/``, ``tests/`` may be
  ``env_core/tests/``);
- a shortened one (``maps/gpis.rs``, ``envs/time_limit.py``, ``src/gpis/``, a bare
  ``probe.rs``): it must be the tail of an existing path, whole components
  (``maps/gpis.rs`` is the tail of ``env_core/src/episode/maps/gpis.rs``; a file moved to
  another folder is the tail of nothing);
- a ``*`` is a glob and must match something;
- paths under ``results/``, ``runs/`` and ``target/`` are written at run time (by the
  benchmarks, training and cargo), and so are the JSON files of ``docs/performance/`` (the
  benchmarks' output the performance page is rendered from; ``docs/PERFORMANCE.md`` names
  the file of a benchmark not run yet), and the documentation site's HTML under
  ``docs/_build/`` (``make docs``): they are allowed by rule.
"""

from __future__ import annotations

import ast
import io
import os
import re
import tokenize
from collections.abc import Iterator
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent
TOP_LEVEL = (
    "env_core",
    "python",
    "agents",
    "benchmarks",
    "experiments",
    "docs",
    "tests",
    "scripts",
)
EXTENSIONS = (".rs", ".py", ".pyi", ".md", ".yml", ".yaml", ".toml", ".json", ".png", ".gif",
              ".csv", ".npz", ".zip")  # fmt: skip
#: Written at run time, so not (or not yet) in the repository: allowed by rule.
GENERATED = ("results/", "runs/", "target/", "docs/performance/", "docs/_build/")
#: Folders neither scanned nor indexed: by name anywhere (not ours), and at the top level
#: (written at run time).
SKIP_DIRS = {".git", ".venv", "venv", "__pycache__", ".pytest_cache", ".ruff_cache",
             ".hypothesis", ".mypy_cache", "node_modules"}  # fmt: skip
SKIP_TOP = {"target", "runs", "results"}
#: Generated documentation, not scanned (it may cite what existed when it was written).
SKIP_SCAN = ("docs/results/", "docs/paper/")

SOURCE_EXTENSIONS = (".rs", ".py", ".pyi", ".md", ".yml", ".yaml", ".toml")
BARE_NAME = re.compile(r"[A-Za-z0-9_-]+\.[a-z]+")
URL = re.compile(r"[A-Za-z][A-Za-z0-9+.-]*://\S+")
TOKEN = re.compile(r"[A-Za-z0-9_.*<>{}$/-]+")


def candidates(text: str) -> Iterator[str]:
    """The tokens of one line of prose that name repository paths (see the module doc)."""
    for match in TOKEN.finditer(URL.sub(" ", text)):
        token = match.group().rstrip(".-")
        if any(c in token for c in "<>{}$"):
            continue
        if "/" not in token:
            if BARE_NAME.fullmatch(token) and token.endswith(SOURCE_EXTENSIONS):
                yield token
            continue
        if token.startswith(("/", ".", "~")) or "//" in token:
            continue  # absolute, relative to the working directory, or not a path
        first = token.split("/")[0]
        if first in (*TOP_LEVEL, "src") or token.endswith(EXTENSIONS):
            yield token


def python_prose(source: str) -> Iterator[tuple[int, str]]:
    """(line, text) of every comment and docstring of a Python source."""
    for tok in tokenize.generate_tokens(io.StringIO(source).readline):
        if tok.type == tokenize.COMMENT:
            yield tok.start[0], tok.string
    nodes = (ast.Module, ast.ClassDef, ast.FunctionDef, ast.AsyncFunctionDef)
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, nodes) and node.body:
            first = node.body[0]
            if (
                isinstance(first, ast.Expr)
                and isinstance(first.value, ast.Constant)
                and isinstance(first.value.value, str)
            ):
                for offset, line in enumerate(first.value.value.splitlines()):
                    yield first.lineno + offset, line


RUST_STRING = re.compile(r'r#*"|"(?:\\.|[^"\\])*"|\'(?:\\.|[^\'\\])\'')


def rust_prose(source: str) -> Iterator[tuple[int, str]]:
    """(line, text) of every ``//`` comment (``///`` and ``//!`` too) and ``/* */`` block of
    a Rust source; string literals are blanked first, so a ``//`` inside one is no comment."""
    in_block = False
    for number, line in enumerate(source.splitlines(), 1):
        if in_block:
            end = line.find("*/")
            yield number, line if end < 0 else line[:end]
            in_block = end < 0
            continue
        code = RUST_STRING.sub(lambda m: " " * len(m.group()), line)
        comment, block = code.find("//"), code.find("/*")
        if comment >= 0 and (block < 0 or comment < block):
            yield number, line[comment:]
        elif block >= 0:
            end = code.find("*/", block + 2)
            yield number, line[block : end if end >= 0 else None]
            in_block = end < 0


HASH_STRING = re.compile(r'"(?:\\.|[^"\\])*"|\'[^\']*\'')


def hash_prose(source: str) -> Iterator[tuple[int, str]]:
    """(line, text) of every ``#`` comment of a YAML file or a Makefile (quoted strings
    blanked first)."""
    for number, line in enumerate(source.splitlines(), 1):
        code = HASH_STRING.sub(lambda m: " " * len(m.group()), line)
        if "#" in code:
            yield number, line[code.index("#") :]


def markdown_prose(source: str) -> Iterator[tuple[int, str]]:
    yield from enumerate(source.splitlines(), 1)


def prose(path: Path) -> Iterator[tuple[int, str]]:
    """The prose lines of a file by its kind (none for other kinds)."""
    text = path.read_text(encoding="utf-8")
    if path.suffix == ".md":
        yield from markdown_prose(text)
    elif path.suffix == ".py":
        yield from python_prose(text)
    elif path.suffix == ".rs":
        yield from rust_prose(text)
    elif path.suffix in (".yml", ".yaml") or path.name == "Makefile":
        yield from hash_prose(text)


def repository_paths(root: Path) -> set[str]:
    """Every file and folder under ``root`` (relative, ``/``-separated; folders end in
    ``/``), without the folders of ``SKIP_DIRS``."""
    found: set[str] = set()
    for folder, dirs, files in os.walk(root):
        relative = Path(folder).relative_to(root).as_posix()
        prefix = "" if relative == "." else relative + "/"
        dirs[:] = [d for d in dirs if d not in SKIP_DIRS and not (not prefix and d in SKIP_TOP)]
        found.update(prefix + d + "/" for d in dirs)
        found.update(prefix + f for f in files)
    return found


def scanned_files(root: Path) -> list[Path]:
    """README.md, CONTRIBUTING.md, docs/*.md and every .rs, .py, .yml and Makefile outside
    the skipped folders."""
    pages = [root / "README.md", root / "CONTRIBUTING.md", *sorted((root / "docs").glob("*.md"))]
    files = [page for page in pages if page.exists()]
    for path in sorted(root.rglob("*")):
        relative = path.relative_to(root).as_posix()
        parts = Path(relative).parts[:-1]
        if set(parts) & SKIP_DIRS or parts[:1] in {(d,) for d in SKIP_TOP}:
            continue
        if relative.startswith(SKIP_SCAN):
            continue
        if path.is_file() and (
            path.suffix in (".rs", ".py", ".yml", ".yaml") or path.name == "Makefile"
        ):
            files.append(path)
    return [f for f in files if f.is_file()]


def resolves(token: str, citing: str, index: set[str], root: Path) -> bool:
    """Whether ``token``, cited in the file ``citing`` (relative to ``root``), names a
    path of ``index`` by the rules of the module docstring."""
    if token.startswith(GENERATED):
        return True
    parent = Path(citing).parent
    folders = [parent, *parent.parents]
    prefixes = ["" if f == Path(".") else f.as_posix() + "/" for f in folders]
    if "*" in token:
        return any(any((root / f).glob(token)) for f in folders) or any(
            Path(p.rstrip("/")).match(token) for p in index
        )
    wanted = token if token.endswith("/") else None
    names = [token] if wanted else [token, token + "/"]
    if token.split("/")[0] in TOP_LEVEL:
        return any(prefix + n in index for prefix in prefixes for n in names)
    tails = ["/" + n for n in names]
    return any(n in index for n in names) or any(p.endswith(t) for p in index for t in tails)


def missing_paths(root: Path = REPO) -> list[str]:
    """``file:line -> path`` for every cited path that does not resolve."""
    index = repository_paths(root)
    missing = []
    for path in scanned_files(root):
        citing = path.relative_to(root).as_posix()
        for number, line in prose(path):
            for token in candidates(line):
                if not resolves(token, citing, index, root):
                    missing.append(f"{citing}:{number} -> {token}")
    return missing


# ---- the extractor itself, so that the scan cannot pass by finding nothing ---------------
def test_the_extractor_finds_paths_and_tells_existing_from_missing(tmp_path: Path) -> None:
    (tmp_path / "agents").mkdir()
    (tmp_path / "agents" / "train.py").write_text('"""Trains."""\n')
    (tmp_path / "env_core" / "src" / "episode" / "maps" / "gpis").mkdir(parents=True)
    (tmp_path / "env_core" / "src" / "episode" / "maps" / "gpis" / "prior.rs").write_text("")
    (tmp_path / "README.md").write_text(
        "Train with `agents/train.py`; the old `agents/trainer.py` is gone.\n"
        "The prior: maps/gpis/prior.rs (see https://example.org/agents/x.py), not\n"
        "episode/prior.rs; runs write results/mine.json and runs/x/model.zip;\n"
        "`agents/hyperparams/<algo>.yml` is a template, 1/240 s a fraction, wrist/probe words.\n"
        "Bare names: train.py is one, gone.py is not; demo.npz and agents.train are not checked.\n"
    )
    lines = dict(markdown_prose((tmp_path / "README.md").read_text()))
    assert list(candidates(lines[1])) == ["agents/train.py", "agents/trainer.py"]
    assert list(candidates(lines[2])) == ["maps/gpis/prior.rs"]
    assert list(candidates(lines[3])) == [
        "episode/prior.rs",
        "results/mine.json",
        "runs/x/model.zip",
    ]
    assert list(candidates(lines[4])) == []
    assert list(candidates(lines[5])) == ["train.py", "gone.py"]
    assert missing_paths(tmp_path) == [
        "README.md:1 -> agents/trainer.py",
        "README.md:3 -> episode/prior.rs",
        "README.md:5 -> gone.py",
    ]


def test_only_comments_and_docstrings_of_code_are_read() -> None:
    python = (
        '"""Module: see agents/a.py."""\n'
        "x = 'agents/b.py'  # agents/c.py\n"
        "def f():\n"
        '    """agents/d.py"""\n'
        "    return 'agents/e.py'\n"
    )
    read = [t for _, text in python_prose(python) for t in candidates(text)]
    assert sorted(read) == ["agents/a.py", "agents/c.py", "agents/d.py"]
    rust = (
        "//! Module: env_core/src/a.rs\n"
        'let s = "agents/b.py"; // agents/c.py\n'
        'let url = "http://x"; /* agents/d.py */\n'
        "/* agents/e.py\n"
        "   agents/f.py */ let t = 1;\n"
    )
    read = [t for _, text in rust_prose(rust) for t in candidates(text)]
    assert read == ["env_core/src/a.rs", "agents/c.py", "agents/d.py", "agents/e.py", "agents/f.py"]
    yaml = "key: 'agents/b.py'  # agents/c.py\n"
    assert [t for _, text in hash_prose(yaml) for t in candidates(text)] == ["agents/c.py"]


def test_shortened_and_relative_paths_resolve_by_their_rules(tmp_path: Path) -> None:
    index = {"env_core/", "env_core/src/", "env_core/tests/", "env_core/tests/fuzz_gpis.rs"}
    index |= {"env_core/src/gpis/", "env_core/src/gpis/map.rs", "tests/", "tests/test_a.py"}
    citing = "env_core/src/gpis/map.rs"
    assert resolves("tests/fuzz_gpis.rs", citing, index, tmp_path)  # from a folder above
    assert not resolves("tests/fuzz_gpis.rs", "README.md", index, tmp_path)
    assert resolves("src/gpis/", "README.md", index, tmp_path)  # a tail, whole components
    assert resolves("gpis/map.rs", "docs/DESIGN.md", index, tmp_path)
    assert not resolves("pis/map.rs", "docs/DESIGN.md", index, tmp_path)
    assert not resolves("episode/map.rs", "docs/DESIGN.md", index, tmp_path)
    assert resolves("results/anything.json", "README.md", index, tmp_path)


# ---- the repository --------------------------------------------------------------------------
def test_every_path_named_in_the_docs_comments_and_docstrings_exists() -> None:
    missing = missing_paths()
    assert not missing, "paths named but not in the repository:\n" + "\n".join(missing)
