"""The generated status table of docs/results.md: each model curve against MPM, from *_vs_mpm.csv."""

import csv

import pytest
from typer.testing import CliRunner

from intrusim.cli import app
from intrusim.figures.status import BEGIN, END, curve_agreement, status_table, write_status

FIELDS = ["curve", "scenario", "omega_rpm", "omega_over_omega0", "velocity_mpm_m_s", "sinkage_mpm_m",
          "rel_diff_velocity", "rel_diff_sinkage"]  # fmt: skip


def _write(path, rows):
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(FIELDS)
        for curve, omega, dv, ds in rows:
            w.writerow([curve, "grousered_wheel", omega, 0.0, 0.1, 0.02, dv, ds])


@pytest.fixture
def figures(tmp_path):
    _write(
        tmp_path / "fig5ab_vs_mpm.csv",
        [("DRFT", 10, 0.05, -0.10), ("DRFT", 30, -0.20, 0.01), ("DRFT", 90, 0.10, "nan"),
         ("RFT", 10, 0.01, 0.02), ("RFT", 30, 0.14, -0.15)],
    )  # fmt: skip
    return tmp_path


def test_each_curve_is_summed_up_from_its_rows(figures):
    rows = {c["curve"]: c for c in curve_agreement(figures / "fig5ab_vs_mpm.csv")}
    drft, rft = rows["DRFT"], rows["RFT"]
    assert drft["omegas"] == [10.0, 30.0, 90.0]
    assert drft["v_max"] == pytest.approx(0.20) and drft["v_median"] == pytest.approx(0.10)
    assert rft["v_median"] == pytest.approx(0.075)  # of two: their mean
    assert drft["sinkage_max"] == pytest.approx(0.10)  # the missing point is left out of the largest
    assert drft["within"] == 1  # 30 RPM is off in v, 90 RPM has no sinkage: only 10 RPM counts
    assert rft["within"] == 2  # 15 % is within
    assert curve_agreement(figures / "fig5ab_vs_mpm.csv", tolerance=0.1)[1]["within"] == 1


def test_the_table_names_missing_csvs_and_the_doc_block_is_replaced(figures, tmp_path):
    lines = status_table(figures)
    assert any(line.startswith("| fig5ab | DRFT | grousered_wheel | 10-90 (3) | 10 % / 20 % |") for line in lines)
    assert any("no `fig7bc_vs_mpm.csv`" in line for line in lines)
    doc = tmp_path / "results.md"
    doc.write_text(f"# R\n\nbefore\n{BEGIN}\nold table\n{END}\nafter\n")
    write_status(doc, figures)
    text = doc.read_text()
    assert "old table" not in text and text.startswith("# R\n\nbefore\n") and text.endswith(f"{END}\nafter\n")
    assert "| fig5ab | RFT |" in text
    write_status(doc, figures)
    assert doc.read_text() == text  # a second run changes nothing
    doc.write_text("no block here\n")
    with pytest.raises(ValueError, match="status table"):
        write_status(doc, figures)


def test_the_command_prints_writes_and_refuses_bad_paths(figures, tmp_path):
    runner = CliRunner()
    res = runner.invoke(app, ["status", "--figures", str(figures)])
    assert res.exit_code == 0 and "| fig5ab | DRFT |" in res.output
    doc = tmp_path / "r.md"
    doc.write_text(f"{BEGIN}\n{END}\n")
    assert runner.invoke(app, ["status", "--figures", str(figures), "--write", str(doc)]).exit_code == 0
    assert "| fig5ab | RFT |" in doc.read_text()
    for args in (["--figures", str(tmp_path / "none")], ["--figures", str(figures), "--write", str(tmp_path / "x.md")]):
        res = runner.invoke(app, ["status", *args])
        assert res.exit_code == 2 and "error:" in res.output
    doc.write_text("no block\n")
    res = runner.invoke(app, ["status", "--figures", str(figures), "--write", str(doc)])
    assert res.exit_code == 2 and "status table" in res.output
