"""CLI: `intrusim mpm run CONFIG.toml` and `intrusim mpm resume RUN_DIR`."""

import csv

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
