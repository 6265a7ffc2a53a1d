"""The package's shape: no module imports research/, and the figure registry names a function for
every figure (no import cycle: test_import_graph.py)."""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

SRC = Path(__file__).resolve().parents[2] / "src"
PACKAGE = SRC / "intrusim"


def test_the_package_does_not_import_research():
    for path in PACKAGE.rglob("*.py"):
        tree = ast.parse(path.read_text())
        names = [a.name for n in ast.walk(tree) if isinstance(n, ast.Import) for a in n.names]
        names += [n.module or "" for n in ast.walk(tree) if isinstance(n, ast.ImportFrom)]
        assert not [m for m in names if m.split(".")[0] in ("research", "helpers")], path


def test_the_figure_registry_resolves_every_figure():
    from intrusim.figures import FIGURES, REGISTRY, figure

    assert set(FIGURES) == set(REGISTRY) and len(FIGURES) == 12
    for name in FIGURES:
        assert callable(FIGURES[name]) and FIGURES[name].__name__ == name.replace("-", "_")
    with pytest.raises(KeyError, match="unknown figure"):
        figure("fig99")
