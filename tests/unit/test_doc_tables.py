"""The marker helper the benchmarks write the docs' tables with (benchmarks/_doc_tables.py); runs no benchmark."""

import importlib.util
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
_spec = importlib.util.spec_from_file_location("_doc_tables", ROOT / "benchmarks" / "_doc_tables.py")
dt = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(dt)

DOC = """# Performance

## Forces

Prose before.

<!-- bench_forces: begin -->
| old | table |
|---|---|
| 1 | 2 |
<!-- bench_forces: end -->

Prose after.

<!-- bench_locomotion: begin -->
untouched
<!-- bench_locomotion: end -->
"""


def test_replaces_only_the_lines_between_its_markers():
    new = dt.replace_between(DOC, "bench_forces", ["| new | table |", "|---|---|", "| 3 | 4 |"])
    assert new == DOC.replace("| old | table |\n|---|---|\n| 1 | 2 |", "| new | table |\n|---|---|\n| 3 | 4 |")
    assert "Prose before.\n\n<!-- bench_forces: begin -->\n| new | table |" in new
    assert "| 3 | 4 |\n<!-- bench_forces: end -->\n\nProse after." in new
    assert "<!-- bench_locomotion: begin -->\nuntouched\n<!-- bench_locomotion: end -->\n" in new


def test_an_empty_table_leaves_the_markers_on_adjacent_lines():
    new = dt.replace_between(DOC, "bench_forces", [])
    assert "<!-- bench_forces: begin -->\n<!-- bench_forces: end -->" in new


def test_writing_twice_is_writing_once(tmp_path):
    path = tmp_path / "performance.md"
    path.write_text(DOC)
    lines = ["", "| a | b |", "|---|---|", "| 1 | 2 |", "", "Measured on ...", ""]
    dt.write_between(path, "bench_forces", lines)
    once = path.read_text()
    dt.write_between(path, "bench_forces", lines)
    assert path.read_text() == once
    assert dt.replace_between(once, "bench_forces", lines) == once
    assert once.count("<!-- bench_forces: begin -->") == 1 and once.count("| a | b |") == 1


@pytest.mark.parametrize(
    "text, why",
    [
        ("# Performance\n\nno markers here\n", "found 0 and 0"),
        ("<!-- bench_forces: begin -->\nonly the begin\n", "found 1 and 0"),
        ("only the end\n<!-- bench_forces: end -->\n", "found 0 and 1"),
        (DOC + DOC, "found 2 and 2"),
        ("<!-- bench_forces: end -->\nx\n<!-- bench_forces: begin -->\n", "comes before"),
    ],
)
def test_missing_or_misplaced_markers_are_refused_and_the_file_is_kept(tmp_path, text, why):
    path = tmp_path / "performance.md"
    path.write_text(text)
    with pytest.raises(dt.MarkerError, match=why):
        dt.write_between(path, "bench_forces", ["| a |"])
    assert path.read_text() == text


def test_a_missing_file_is_refused(tmp_path):
    with pytest.raises(dt.MarkerError, match="does not exist"):
        dt.write_between(tmp_path / "absent.md", "bench_forces", ["| a |"])
    assert not (tmp_path / "absent.md").exists()


def test_the_machine_line_names_the_cores_the_date_and_the_command():
    line = dt.machine_line([str(ROOT / "benchmarks" / "bench_forces.py"), "--write", "docs/performance.md"])
    assert line.startswith("Measured on ") and " cores (" in line
    assert "`python benchmarks/bench_forces.py --write docs/performance.md`" in line
    assert any(ch.isdigit() for ch in line.split(" on ")[-1])  # the date


def test_the_repository_docs_hold_each_benchmarks_markers_once():
    text = (ROOT / "docs" / "performance.md").read_text()
    for name in ("bench_forces", "bench_locomotion"):
        assert dt.replace_between(text, name, ["x"]).count("x\n<!-- " + name + ": end -->") == 1


def test_check_markers_refuses_before_anything_is_written(tmp_path):
    path = tmp_path / "performance.md"
    path.write_text(DOC)
    assert dt.check_markers(path, "bench_forces") == DOC
    with pytest.raises(dt.MarkerError, match="found 0 and 0"):
        dt.check_markers(path, "convergence table")
