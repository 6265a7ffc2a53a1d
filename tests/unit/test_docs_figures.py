"""docs/figures holds what the documentation's pages show or name, nothing else: a study's outputs,
the numbers behind a figure included, live with the study in research/outputs/ (research/outputs/figures/
for the figures' CSVs and the calibration runs the pages sum up).

A file there must be named by a docs page, mkdocs.yml or the README: by its path under docs/figures
(``figures/blind_table_wheel.png``, ``docs/figures/blind.model.json``) or by its own name.
"""

from __future__ import annotations

from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
FIGURES = ROOT / "docs" / "figures"
NAMING = ("docs/*.md", "mkdocs.yml", "README.md")


def corpus() -> str:
    """The text of every page that may name a figure file."""
    return "\n".join(p.read_text(errors="replace") for g in NAMING for p in sorted(ROOT.glob(g)))


def figure_files(folder: Path = FIGURES) -> list[str]:
    """Every file under ``folder``, as a path relative to it ("a.png", "sub/b.csv")."""
    return sorted(p.relative_to(folder).as_posix() for p in folder.rglob("*") if p.is_file())


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


def unnamed(files: list[str], text: str) -> list[str]:
    """The files of ``files`` that ``text`` names neither by their path nor by their own name."""
    return [
        rel
        for rel in files
        if not (
            _names(text, rel, WORD + ".-", WORD + "-") or _names(text, rel.rpartition("/")[2], WORD + ".-/", WORD + "-")
        )
    ]


def test_every_file_in_docs_figures_is_named_by_a_docs_page():
    orphans = unnamed(figure_files(), corpus())
    assert not orphans, (
        f"docs/figures holds {len(orphans)} file(s) that no docs page, mkdocs.yml or README names: {orphans[:20]}; "
        "a study's output (a figure's numbers included) goes to research/outputs/ (research/outputs/README.md), "
        "a figure a page shows is linked from that page"
    )


def test_the_check_flags_every_file_no_page_names():
    files = ["fig9.png", "fig9.csv", "fig9_vs_mpm.csv", "fit.model.json", "fit.json", "runs/a_mpm_sweep.csv",
             "other/a_mpm_sweep.csv", "orphan.txt"]  # fmt: skip
    text = "![fig9](figures/fig9.png)\n`docs/figures/fit.model.json`\n--runs docs/figures/runs/a_mpm_sweep.csv\n"
    assert unnamed(files, text) == ["fig9.csv", "fig9_vs_mpm.csv", "fit.json", "other/a_mpm_sweep.csv", "orphan.txt"]
    assert unnamed(["fig9.png"], "figures/fig9.pngs") == ["fig9.png"]  # another name is not this one


def test_the_check_reads_the_tree_it_guards(tmp_path):
    (tmp_path / "sub").mkdir()
    for rel in ("a.png", "a.csv", "sub/x_mpm_sweep.csv"):
        (tmp_path / rel).write_text("")
    assert figure_files(tmp_path) == ["a.csv", "a.png", "sub/x_mpm_sweep.csv"]
    assert "figures/blind.model.json" in corpus()  # a docs page's name of a kept file
