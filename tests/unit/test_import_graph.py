"""The package's import graph has no cycle: every module of ``src/intrusim``, imports inside
functions and under ``TYPE_CHECKING`` included. The package ``intrusim`` itself is a node like any
other (its ``__init__`` names the public API, lazily), so no submodule may import from it: a
submodule imports the module that defines a name (``intrusim._version``, ``intrusim.errors``)."""

from __future__ import annotations

import ast
from pathlib import Path

SRC = Path(__file__).resolve().parents[2] / "src"
PACKAGE = SRC / "intrusim"


def _module_name(path: Path) -> str:
    parts = list(path.relative_to(SRC).with_suffix("").parts)
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def _imports(path: Path, modules: set[str]) -> set[str]:
    """The intrusim modules ``path`` imports, anywhere in the file. ``from a.b import c`` imports
    ``a.b`` (its __init__ runs) and, if ``c`` is a module, ``a.b.c``."""
    name = _module_name(path)
    package = name if path.name == "__init__.py" else name.rpartition(".")[0]
    found = set()
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.Import):
            targets = [a.name for a in node.names]
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                parts = package.split(".")
                base = ".".join(parts[: len(parts) - node.level + 1] + ([base] if base else []))
            targets = [f"{base}.{a.name}" for a in node.names] + [base]
        else:
            continue
        for t in targets:
            while t and t not in modules:  # a name defined in a module: the module
                t = t.rpartition(".")[0]
            if t and t != name:
                found.add(t)
    return found


def import_graph() -> dict[str, set[str]]:
    """module -> the intrusim modules it imports."""
    files = sorted(PACKAGE.rglob("*.py"))
    modules = {_module_name(p) for p in files}
    return {_module_name(p): _imports(p, modules) for p in files}


def find_cycle(graph: dict[str, set[str]]) -> list[str] | None:
    """One cycle of ``graph`` as [a, b, ..., a], or None (depth-first search, sorted order)."""
    state: dict[str, int] = {}  # 1: on the current path, 2: done

    def visit(m: str, path: list[str]) -> list[str] | None:
        state[m] = 1
        path.append(m)
        for t in sorted(graph.get(m, ())):
            if state.get(t) == 1:
                return path[path.index(t) :] + [t]
            if t not in state and (cycle := visit(t, path)):
                return cycle
        path.pop()
        state[m] = 2
        return None

    for m in sorted(graph):
        if m not in state and (cycle := visit(m, [])):
            return cycle
    return None


def test_find_cycle_finds_a_cycle_and_only_a_cycle():
    assert find_cycle({"a": {"b"}, "b": {"c"}, "c": set()}) is None
    assert find_cycle({"a": {"b"}, "b": {"c"}, "c": {"b"}}) == ["b", "c", "b"]


def test_the_graph_sees_relative_function_level_and_package_imports():
    graph = import_graph()
    assert "intrusim.mpm.backend" in graph["intrusim.mpm.grid"]  # from . import backend
    assert "intrusim.geometry" in graph["intrusim"]  # the public API, under TYPE_CHECKING
    assert len(graph) > 60


def test_the_package_has_no_import_cycle():
    cycle = find_cycle(import_graph())
    assert cycle is None, "import cycle: " + " -> ".join(cycle)


def test_private_taichi_apis_are_used_from_one_module():
    """taichi.lang, taichi.graph._graph, taichi._lib (Taichi's internals) are used in mpm/_taichi_private.py only,
    which refuses a Taichi outside the tested minor version."""
    import re

    private = re.compile(r"(from|import)\s+taichi\.(lang|graph\._|_lib)|\bti\.(lang|_lib)\b|\bti\.graph\._")
    users = sorted(
        str(p.relative_to(SRC))
        for p in SRC.rglob("*.py")
        if p.name != "_taichi_private.py" and private.search(p.read_text())
    )
    assert users == [], users
