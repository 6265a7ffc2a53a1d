"""CLI: `intrusim mpm run CONFIG.toml` and `intrusim mpm resume RUN_DIR`."""

import csv
import json

import pytest
from typer.testing import CliRunner

from intrusim.cli import app

runner = CliRunner()

TINY = """
[domain]
size = [0.1, 0.1]
cells = [10, 10]
[bed]
rectangles = [{ x0 = 0.0, z0 = 0.0, x1 = 0.1, z1 = 0.05 }]
[time]
t_end = 0.02
[output]
record_every = 0.005
checkpoint_every = 0.01
"""


def _times(run_dir):
    return [float(r["time"]) for r in csv.DictReader((run_dir / "timeseries.csv").open())]


def test_run_writes_a_run_folder_and_resume_extends_it(tmp_path):
    cfg = tmp_path / "tiny.toml"
    cfg.write_text(TINY)
    out = tmp_path / "run"
    r = runner.invoke(app, ["mpm", "run", str(cfg), "--out", str(out)])
    assert r.exit_code == 0, r.output
    assert "done: t = 0.02 s" in r.output
    assert (out / "config.json").exists() and (out / "checkpoint.npz").exists()
    assert max(_times(out)) > 0.019
    r = runner.invoke(app, ["mpm", "resume", str(out), "--t-end", "0.03"])
    assert r.exit_code == 0, r.output
    assert "resuming" in r.output and max(_times(out)) > 0.029


def test_bad_config_fails_before_compute_with_the_field_named(tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text(TINY.replace("cells = [10, 10]", "cells = [10, 10]\nbogus = 3"))
    r = runner.invoke(app, ["mpm", "run", str(bad)])
    assert r.exit_code == 2 and "bogus" in r.output
    r = runner.invoke(app, ["mpm", "run", str(tmp_path / "missing.toml")])
    assert r.exit_code == 2 and "no such file" in r.output
    r = runner.invoke(app, ["mpm", "resume", str(tmp_path)])
    assert r.exit_code == 2 and "not a run folder" in r.output


def test_contact_band_reaches_the_solver_config_and_a_negative_one_is_refused():
    from intrusim.cli_mpm import _case
    from intrusim.scenarios.mpm_locomotion import mpm_config

    case = _case("wheel", True, None, None, None, contact_band=0.5)
    assert mpm_config(case.scenario, case.mpm, 30.0).contact_band_cells == 0.5
    assert mpm_config(case.scenario, _case("wheel", True, None, None, None).mpm, 30.0).contact_band_cells == 1.0
    r = runner.invoke(app, ["mpm", "steady", "--quick", "--contact-band", "-1"])
    assert r.exit_code == 2 and "contact_band must be >= 0" in r.output


def test_bed_length_keeps_the_cell_size_and_a_too_short_bed_is_refused():
    from intrusim.cli_mpm import _case

    full = _case("runner", False, None, None, None)
    short = _case("runner", False, None, None, None, cell_size=0.0025, length=1.0)
    assert full.mpm.domain[0] == 4.0 and short.mpm.domain == (1.0, full.mpm.domain[1])
    assert short.mpm.h == pytest.approx(0.0025) and short.mpm.cells == (400, round(full.mpm.domain[1] / 0.0025))
    r = runner.invoke(app, ["mpm", "steady", "--scenario", "runner", "--length", "0.1"])
    assert r.exit_code == 2 and "length must exceed" in r.output


def test_steady_marks_its_folder_finished_and_refuses_another_configuration_on_it(tmp_path):
    """`mpm steady --out` writes result.json (a sweep on that folder reuses the run); the same
    folder with another configuration is refused (exit 2) and the finished run is left as it was."""
    r = runner.invoke(app, ["mpm", "steady", "--quick", "--omega-rpm", "60", "--out", str(tmp_path), "--threads", "1"])
    assert r.exit_code == 0, r.output
    run_dir = tmp_path / "grousered_wheel_60rpm"
    assert (run_dir / "result.json").exists()
    before = {p.name: p.read_bytes() for p in run_dir.iterdir()}
    r = runner.invoke(app, ["mpm", "steady", "--quick", "--omega-rpm", "60", "--out", str(tmp_path), "--contact-band", "0"])
    assert r.exit_code == 2 and "another configuration (differs in contact_band_cells)" in r.output.replace("\n", " ")
    assert {p.name: p.read_bytes() for p in run_dir.iterdir()} == before
    # `mpm collect` gathers the finished run into the sweep CSV that reproduce/calibrate read
    from intrusim.analysis.sweep import SweepResult

    r = runner.invoke(app, ["mpm", "collect", str(tmp_path)])
    assert r.exit_code == 0, r.output
    res = SweepResult.from_csv(tmp_path / "grousered_wheel_mpm_sweep.csv")
    done = json.loads((run_dir / "result.json").read_text())
    assert res.omega_rpm.tolist() == [60.0] and res.column("velocity")[0] == pytest.approx(done["velocity"])
    r = runner.invoke(app, ["mpm", "collect", str(tmp_path / "empty")])
    assert r.exit_code == 2 and "needs finished run folders" in r.output
