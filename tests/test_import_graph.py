"""The layers' arrows (docs/DESIGN.md §1): no import circle among the project's Python
modules, experiments import no benchmark, nothing patches ``sys.path``.

Imports are read with ``ast`` (every ``import`` and ``from ... import``, also those inside
functions: a circle through a function-level import is still two modules that each need the
other), not by importing anything.
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[1]
# Each top-level package and the folder its modules are found in.
PACKAGES = {
    "agents": REPO,
    "benchmarks": REPO,
    "experiments": REPO,
    "tactile_search": REPO / "python",
}


def module_files() -> dict[str, Path]:
    """Every module of the project's packages by dotted name (a package by its own name); a
    compiled module by its stub (``tactile_search._core``), which imports nothing of ours."""
    modules = {}
    for package, root in PACKAGES.items():
        for path in sorted([*(root / package).rglob("*.py"), *(root / package).rglob("*.pyi")]):
            parts = list(path.relative_to(root).with_suffix("").parts)
            if parts[-1] == "__init__":
                parts.pop()
            modules[".".join(parts)] = path
    return modules


def imported_modules(path: Path, name: str, known: set[str]) -> set[str]:
    """The project modules that the module ``name`` at ``path`` imports."""
    is_package = path.name == "__init__.py"
    found: set[str] = set()
    if path.suffix == ".pyi":
        return found
    for node in ast.walk(ast.parse(path.read_text(), str(path))):
        if isinstance(node, ast.Import):
            targets = [alias.name for alias in node.names]
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                anchor = name.split(".")
                anchor = anchor if is_package else anchor[:-1]
                anchor = anchor[: len(anchor) - (node.level - 1)]
                base = ".".join([*anchor, base] if base else anchor)
            # `from package import module` imports the module (its package's __init__ runs
            # first, as for any submodule: not an arrow of its own); `from module import
            # name` imports the module.
            targets = [
                f"{base}.{alias.name}" if f"{base}.{alias.name}" in known else base
                for alias in node.names
            ]
        else:
            continue
        for target in targets:
            while target and target not in known:
                target = target.rpartition(".")[0]
            if target and target != name:
                found.add(target)
    return found


def import_graph() -> dict[str, set[str]]:
    files = module_files()
    known = set(files)
    return {name: imported_modules(path, name, known) for name, path in files.items()}


def circles(graph: dict[str, set[str]]) -> list[list[str]]:
    """The strongly connected components of more than one module (Tarjan's algorithm)."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    found: list[list[str]] = []

    def visit(node: str) -> None:
        index[node] = low[node] = len(index)
        stack.append(node)
        on_stack.add(node)
        for successor in sorted(graph[node]):
            if successor not in index:
                visit(successor)
                low[node] = min(low[node], low[successor])
            elif successor in on_stack:
                low[node] = min(low[node], index[successor])
        if low[node] == index[node]:
            component = []
            while True:
                member = stack.pop()
                on_stack.discard(member)
                component.append(member)
                if member == node:
                    break
            if len(component) > 1:
                found.append(sorted(component))

    for node in sorted(graph):
        if node not in index:
            visit(node)
    return found


def test_the_circle_finder_finds_a_circle_through_three_modules() -> None:
    graph = {"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}}
    assert circles(graph) == [["a", "b", "c"]]
    assert circles({"a": {"b"}, "b": set()}) == []


def test_relative_and_package_imports_resolve_to_project_modules(tmp_path: Path) -> None:
    module = tmp_path / "m.py"
    module.write_text("from . import sibling\nfrom .sub import thing\nimport outside\n")
    known = {"pkg", "pkg.m", "pkg.sibling", "pkg.sub"}
    assert imported_modules(module, "pkg.m", known) == {"pkg.sibling", "pkg.sub"}
    module.write_text("from pkg import name_in_its_init\n")
    assert imported_modules(module, "pkg.m", known) == {"pkg"}


def test_no_import_circle_among_the_python_packages() -> None:
    graph = import_graph()
    assert "agents.sb3.training" in graph and "tactile_search.envs.cupboard_search" in graph
    assert circles(graph) == []


# The agents' commands: argparse over the subpackages, imported by nothing.
AGENT_COMMANDS = (
    "agents.train",
    "agents.evaluate",
    "agents.pipeline",
    "agents.comparison",
    "agents.probe_trace",
    "agents.rllib_ppo",
)


def layer_breach(importer: str, imported: str) -> str | None:
    """Why ``importer`` may not import ``imported`` (docs/DESIGN.md §1.1), or None."""

    def within(name: str, *packages: str) -> bool:
        return any(name == p or name.startswith(p + ".") for p in packages)

    if within(importer, "tactile_search") and not within(imported, "tactile_search"):
        return "the installed package imports nothing outside it"
    if within(importer, "experiments") and within(imported, "agents", "benchmarks"):
        return "experiments call the library, not the agents or a benchmark"
    if within(importer, "agents") and within(imported, "benchmarks", "experiments"):
        return "agents import no benchmark or experiment"
    if within(imported, *AGENT_COMMANDS):
        return "a command is imported by nothing"
    if within(importer, "agents.run_dir", "agents.rollout") and within(imported, "agents"):
        return "the two contracts stand on tactile_search alone"
    return None


def test_the_layer_rules_refuse_what_design_md_forbids() -> None:
    assert layer_breach("tactile_search.gpis", "agents.sb3") is not None
    assert layer_breach("agents.run_dir", "agents.sb3.recipes") is not None
    assert layer_breach("agents.grid.pipeline", "agents.train") is not None
    assert layer_breach("agents.sb3.training", "agents.run_dir") is None
    assert layer_breach("benchmarks.gpis_append", "experiments.paper.gpis_timing") is None


def test_every_import_follows_the_layers() -> None:
    breaches = sorted(
        f"{importer} -> {imported}: {why}"
        for importer, targets in import_graph().items()
        for imported in targets
        if (why := layer_breach(importer, imported)) is not None
    )
    assert breaches == []


def test_experiments_import_no_benchmark() -> None:
    graph = import_graph()
    offenders = {
        name: sorted(target for target in targets if target.startswith("benchmarks"))
        for name, targets in graph.items()
        if name.startswith("experiments")
    }
    assert {name: found for name, found in offenders.items() if found} == {}


@pytest.mark.parametrize("package", sorted(PACKAGES))
def test_nothing_patches_sys_path(package: str) -> None:
    patched = [
        str(path.relative_to(REPO))
        for path in sorted((PACKAGES[package] / package).rglob("*.py"))
        if "sys.path.insert" in path.read_text() or "sys.path.append" in path.read_text()
    ]
    assert patched == []
