"""docs/figures holds what the documentation shows or names, nothing else (research outputs go to
research/outputs/).

A file there must be named somewhere that uses it: a docs page, mkdocs.yml, the README, the package
(the figure registry of ``intrusim reproduce`` included), the tests, the benchmarks or the examples;
either by its path under docs/figures (``blind.model.json``, ``mpm_band0_settled/..._sweep.csv``,
``"mpm_band0_settled" / "..._sweep.csv"`` in Python) or as an output prefix
(``--out docs/figures/plate_node_entry``). A named file brings the files of the same run with it:
``NAME.png``, ``NAME.csv``, ``NAME.json``, ``NAME.model.json``, ``NAME_vs_mpm.csv`` (the plotted
numbers and settings stay with the figure), and a named MPM sweep CSV the other sweep CSVs of its
folder (a ``--runs`` folder).
"""

from __future__ import annotations

import re
from pathlib import Path

from intrusim.figures import REGISTRY

ROOT = Path(__file__).resolve().parents[2]
FIGURES = ROOT / "docs" / "figures"
NAMING = ("docs/*.md", "mkdocs.yml", "README.md", "src/intrusim/**/*.py", "tests/**/*.py", "benchmarks/**/*.py",
          "examples/**/*.py")  # fmt: skip


def corpus() -> str:
    """The text of every file that may name a figure file, Python path joins ``"a" / "b"`` read as ``a/b``."""
    me = Path(__file__).resolve()
    texts = [p.read_text(errors="replace") for g in NAMING for p in sorted(ROOT.glob(g)) if p.resolve() != me]
    return re.sub(r'"\s*/\s*"', "/", "\n".join(texts))


def figure_files(folder: Path = FIGURES) -> list[str]:
    """Every file under ``folder``, as a path relative to it ("a.png", "sub/b.csv")."""
    return sorted(p.relative_to(folder).as_posix() for p in folder.rglob("*") if p.is_file())


def run_of(rel: str) -> str:
    """The run a file belongs to: its folder and name up to the first dot, less ``_vs_mpm``; every MPM
    sweep CSV of a folder is one run (the folder is what ``--runs`` takes)."""
    folder, _, name = rel.rpartition("/")
    if "_mpm_sweep" in name:
        return f"{folder}/*_mpm_sweep"
    stem = name.split(".")[0]
    return f"{folder}/{stem.removesuffix('_vs_mpm')}"


def _names(text: str, name: str, before: str, after: str) -> bool:
    """Whether ``text`` holds ``name`` neither preceded by a character of ``before`` nor followed by one
    of ``after`` (str.find: a regex with look-arounds over the whole text takes seconds)."""
    i = text.find(name)
    while i >= 0:
        j = i + len(name)
        if (i == 0 or text[i - 1] not in before) and (j == len(text) or text[j] not in after):
            return True
        i = text.find(name, i + 1)
    return False


WORD = "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_"


def unnamed(files: list[str], text: str, registry: list[str]) -> list[str]:
    """The files of ``files`` that ``text`` does not name, alone or through a named file of their run."""
    named = set()
    for rel in files:
        folder, _, name = rel.rpartition("/")
        stem = f"{folder}/{name.split('.')[0]}".lstrip("/")
        if (
            _names(text, rel, WORD + ".-", WORD + "-")  # the file: `docs/figures/blind.model.json`
            or _names(text, f"figures/{stem}", "", WORD + ".-/")  # an output prefix: --out docs/figures/NAME
            or (not folder and stem in registry)  # intrusim reproduce NAME
        ):
            named.add(run_of(rel))
    return [rel for rel in files if run_of(rel) not in named]


def _registry() -> list[str]:
    return [name.replace("-", "_") for name in REGISTRY]


def test_every_file_in_docs_figures_is_named_by_the_docs_or_the_code():
    orphans = unnamed(figure_files(), corpus(), _registry())
    assert not orphans, (
        f"docs/figures holds {len(orphans)} file(s) that no docs page, mkdocs.yml, README, package code, test, "
        f"benchmark or example names: {orphans[:20]}; a research output goes to research/outputs/ "
        "(research/outputs/README.md), a figure a page shows is linked from that page"
    )


def test_the_check_flags_an_unnamed_file_and_keeps_a_named_figures_run():
    files = ["fig9.png", "fig9.csv", "fig9_vs_mpm.csv", "fig9_band0.png", "fig9_band0.csv", "fit.model.json",
             "fit.json", "fit.png", "plot.png", "plot.csv", "runs/a_mpm_sweep.csv", "runs/b_mpm_sweep.csv",
             "other/a_mpm_sweep.csv", "orphan.txt"]  # fmt: skip
    text = (
        "![fig9](figures/fig9.png)\n`docs/figures/fit.model.json`\n--out docs/figures/plot`\n"
        'ROOT / "docs" / "figures" / "runs/a_mpm_sweep.csv"\nthe orphan, fig9_band0 and other/ are not named'
    )
    assert unnamed(files, text, []) == ["fig9_band0.png", "fig9_band0.csv", "other/a_mpm_sweep.csv", "orphan.txt"]
    assert unnamed(["fig9.png", "fig9.csv"], "reproduce fig9", ["fig9"]) == []  # a registry figure is named
    assert unnamed(["fig9.png"], "figures/fig9.pngs", []) == ["fig9.png"]  # another name is not this one


def test_the_check_reads_the_tree_it_guards(tmp_path):
    (tmp_path / "sub").mkdir()
    for rel in ("a.png", "a.csv", "sub/x_mpm_sweep.csv"):
        (tmp_path / rel).write_text("")
    assert figure_files(tmp_path) == ["a.csv", "a.png", "sub/x_mpm_sweep.csv"]
    assert "figures/blind.model.json" in corpus()  # a docs page's name of a kept file
    assert '"mpm_small_1p25mm/small_grousered_wheel_mpm_sweep.csv"' in corpus()  # a test's Path join
