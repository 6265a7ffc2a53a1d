"""CLI: steady, sweep and reproduce print tables / write files and fail with clear messages."""

import csv

from typer.testing import CliRunner

from intrusim.cli import app

runner = CliRunner()


def test_steady_table():
    r = runner.invoke(app, ["steady", "--scenario", "wheel", "--model", "rft", "--omega-rpm", "30"])
    assert r.exit_code == 0, r.output
    assert "v m/s" in r.output and "slip" in r.output


def test_steady_bad_input_is_a_message():
    r = runner.invoke(app, ["steady", "--omega-rpm", "-5"])
    assert r.exit_code == 2 and "omega_rpm must be > 0" in r.output
    r = runner.invoke(app, ["steady", "--model", "mpm-magic"])
    assert r.exit_code == 2 and "must be one of rft, drft-inertial, drft or a model file" in r.output


def test_sweep_keeps_good_points_and_reports_bad(tmp_path):
    out = tmp_path / "s.csv"
    r = runner.invoke(app, ["sweep", "--model", "rft", "--omega-rpm", "30,0,60", "--no-parallel", "--csv", str(out)])
    assert r.exit_code == 1  # one point failed
    assert "ERROR" in r.output and r.output.count("|") >= 12
    rows = list(csv.DictReader(out.open()))
    assert [row["ok"] for row in rows] == ["True", "False", "True"]


def test_reproduce_fig6a_quick(tmp_path):
    r = runner.invoke(app, ["reproduce", "fig6a", "--out", str(tmp_path), "--quick"])
    assert r.exit_code == 0, r.output
    assert (tmp_path / "fig6a.png").stat().st_size > 1000
    rows = list(csv.DictReader((tmp_path / "fig6a.csv").open()))
    assert len(rows) == 15 and abs(float(rows[0]["fit_lambda"]) - float(rows[0]["paper_lambda"])) < 1e-9


def test_reproduce_with_a_name_writes_that_stem_only(tmp_path):
    r = runner.invoke(app, ["reproduce", "fig6a", "--out", str(tmp_path), "--quick", "--name", "fig6a_coarse"])
    assert r.exit_code == 0, r.output
    assert sorted(p.name for p in tmp_path.iterdir()) == ["fig6a_coarse.csv", "fig6a_coarse.png"]
    assert str(tmp_path / "fig6a_coarse.csv") in r.output
    r = runner.invoke(app, ["reproduce", "fig6a", "--out", str(tmp_path), "--name", "../elsewhere"])
    assert r.exit_code == 2 and "plain file name" in r.output


def test_reproduce_mpm_takes_the_sweep_csv_of_a_runs_folder_without_run_folders(tmp_path):
    from intrusim.analysis.sweep import SweepResult

    rec = dict(slip=0.4, velocity_std=float("nan"), sinkage_std=float("nan"), drift=0.1, settled=True, error="")
    rows = [
        {**rec, "omega_rpm": 20.0, "ok": True, "velocity": 0.12, "sinkage": 0.041},
        {**rec, "omega_rpm": 45.0, "ok": True, "velocity": 0.20, "sinkage": 0.053},
        {**rec, "omega_rpm": 90.0, "ok": False, "velocity": 0.1, "sinkage": 0.04, "error": "not steady"},
    ]
    SweepResult("grousered_wheel", "mpm", None, rows).to_csv(tmp_path / "grousered_wheel_mpm_sweep.csv")
    r = runner.invoke(app, ["reproduce", "fig3ab", "--quick", "--runs", str(tmp_path), "--out", str(tmp_path / "f")])
    assert r.exit_code == 0, r.output
    got = list(csv.DictReader((tmp_path / "f" / "fig3ab.csv").open()))
    assert [(float(g["omega_rpm"]), float(g["velocity_m_s"])) for g in got] == [(20.0, 0.12), (45.0, 0.20)]
    assert not any(p.is_dir() for p in tmp_path.iterdir() if p.name != "f")  # no MPM run was started


def test_reproduce_unknown_figure():
    r = runner.invoke(app, ["reproduce", "fig99"])
    assert r.exit_code == 2 and "unknown figure" in r.output


def test_steady_with_an_rft_table(tmp_path):
    from intrusim.analysis.rft_fit import write_coefficients
    from intrusim.analysis.steady import run_steady
    from intrusim.laws.rft import LI2013
    from intrusim.scenarios import get_scenario

    table = write_coefficients(tmp_path / "t.json", 0.7 * LI2013)  # used as it is: the generic one with xi 0.7
    r = runner.invoke(app, ["steady", "--model", "rft", "--omega-rpm", "30", "--rft-coefficients", str(table)])
    assert r.exit_code == 0, r.output
    plain = runner.invoke(app, ["steady", "--model", "rft", "--omega-rpm", "30"])
    assert r.output.splitlines()[-1] != plain.output.splitlines()[-1]  # the table is used
    sc = get_scenario("wheel")
    sc.force_model.xi = 0.7
    st = run_steady(sc, "rft", 30.0, None)
    assert r.output.splitlines()[-1].split("|")[:2] == [f"{st.velocity:8.4f} ", f" {st.sinkage * 1e3:10.2f} "]
    bad = runner.invoke(app, ["steady", "--rft-coefficients", str(tmp_path / "none.json")])
    assert bad.exit_code == 2 and "not found" in bad.output
