"""The package's shape: no module imports research/, no import cycles outside mpm/ (imports inside
functions count), and the figure registry names a function for every figure."""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

SRC = Path(__file__).resolve().parents[2] / "src"
PACKAGE = SRC / "intrusim"


def _module_name(path: Path) -> str:
    parts = list(path.relative_to(SRC).with_suffix("").parts)
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def _imports(path: Path, modules: set[str]) -> set[str]:
    """The intrusim modules ``path`` imports, anywhere in the file (a package import counts as its __init__)."""
    name = _module_name(path)
    package = name if path.name == "__init__.py" else name.rpartition(".")[0]
    found = set()
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.Import):
            targets = [a.name for a in node.names]
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                base = ".".join(
                    package.split(".")[: len(package.split(".")) - node.level + 1] + ([base] if base else [])
                )
            targets = [f"{base}.{a.name}" for a in node.names] + [base]
        else:
            continue
        for t in targets:
            while t and t not in modules:
                t = t.rpartition(".")[0]
            if t and t != name:
                found.add(t)
    return found


def _graph() -> dict[str, set[str]]:
    files = sorted(PACKAGE.rglob("*.py"))
    modules = {_module_name(p) for p in files}
    return {_module_name(p): _imports(p, modules) for p in files}


def test_the_package_does_not_import_research():
    for path in PACKAGE.rglob("*.py"):
        tree = ast.parse(path.read_text())
        names = [a.name for n in ast.walk(tree) if isinstance(n, ast.Import) for a in n.names]
        names += [n.module or "" for n in ast.walk(tree) if isinstance(n, ast.ImportFrom)]
        assert not [m for m in names if m.split(".")[0] in ("research", "helpers")], path


def test_no_import_cycles_outside_mpm():
    graph = {
        m: {t for t in ts if not t.startswith("intrusim.mpm")}
        for m, ts in _graph().items()
        if not m.startswith("intrusim.mpm")
    }
    # a package's __init__ importing its own submodules is how a package exports names, not a cycle
    edges = {m: {t for t in ts if not (m.endswith("__init__") or t.startswith(m + "."))} for m, ts in graph.items()}
    seen: dict[str, int] = {}  # 1: on the current path, 2: done

    def visit(m: str, path: list[str]) -> None:
        seen[m] = 1
        for t in sorted(edges.get(m, ())):
            if seen.get(t) == 1:
                pytest.fail(
                    "import cycle: " + " -> ".join(path[path.index(t) :] + [m, t]) if t in path else f"{m} -> {t}"
                )
            if t not in seen:
                visit(t, path + [m])
        seen[m] = 2

    for m in sorted(edges):
        if m not in seen:
            visit(m, [])


def test_the_figure_registry_resolves_every_figure():
    from intrusim.figures import FIGURES, REGISTRY, figure

    assert set(FIGURES) == set(REGISTRY) and len(FIGURES) == 11
    for name in FIGURES:
        assert callable(FIGURES[name]) and FIGURES[name].__name__ == name.replace("-", "_")
    with pytest.raises(KeyError, match="unknown figure"):
        figure("fig99")
