"""Sweep tables without running MPM (a fake run in its place): the CSV columns, each with its unit
in its name (docs/getting-started.md, "CSV files"), and the older files without, read the same."""

from __future__ import annotations

import csv
import math
import re
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

import intrusim.scenarios.mpm_locomotion as ml
from intrusim.analysis.calibration import load_reference
from intrusim.analysis.sweep import SweepResult
from intrusim.cli import app
from intrusim.params import RPM
from intrusim.scenarios import get_scenario

ROOT = Path(__file__).resolve().parents[2]
UNITS = ("_m", "_m_s", "_s", "_rad_s", "_rpm", "_N", "_N_per_m", "_per_s", "_kg_m3", "_m2", "_deg")


def documented_unitless() -> set[str]:
    """The column names the docs' CSV table lists as dimensionless, a flag or text."""
    doc = (ROOT / "docs" / "getting-started.md").read_text()
    table = doc[doc.index("## CSV files") :].split("\n\n## ")[0]
    names: set[str] = set()
    for line in table.splitlines():
        cells = [c.strip() for c in re.split(r"(?<!\\)\|", line.strip().strip("|"))]  # not at an escaped \|
        if len(cells) == 3 and cells[1] in ("1", "flag", "text"):
            names |= set(re.findall(r"`([a-z0-9_]+)`", cells[0]))
    return names


def assert_units(path: Path) -> list[str]:
    """Every column of the CSV at ``path`` names its unit or is a documented unitless one."""
    header = next(csv.reader(path.open()))
    unitless = documented_unitless()
    bare = [h for h in header if not h.endswith(UNITS) and h not in unitless]
    assert not bare, f"{path.name}: columns without a unit: {bare}"
    return header


def fake_mpm_run(scenario, settings, omega_rpm, out_dir=None, progress=None):
    """run_mpm_steady's place: reports four chunks 6 s of wall time apart, returns a steady state."""
    for k, t in enumerate((0.3, 0.6, 0.9, settings.t_max)):
        if progress is not None:
            progress({"t": t, "x": 0.1 * t, "z": 0.2, "vx": 0.1 + 0.01 * k, "wall": 6.0 * (k + 1)})
    return ml.MPMSteadyState(
        omega=omega_rpm * RPM, velocity=0.1, sinkage=0.02, slip=0.3, velocity_std=0.01, sinkage_std=0.001,
        drift=0.01, settled=True, surface_drop=0.005, surface_drop_std=0.001, window=(0.6, settings.t_max),
        radius=0.2, wall_time=24.0, steps=100, series={}, meta={"scenario": scenario.name},
    )  # fmt: skip


def test_demo_sweep_and_mpm_table_name_each_unit(tmp_path, monkeypatch):
    from intrusim.demo import run_demo
    from intrusim.figures.mpm import mpm_sweep_table

    demo = run_demo(tmp_path / "demo", omega_rpm=(30.0,), mpm_omega_rpm=None)
    assert assert_units(demo.csv_path) == ["model", "omega_rpm", "omega_rad_s", "velocity_m_s", "sinkage_m", "slip",
                                           "wall_time_s"]  # fmt: skip
    row = next(csv.DictReader(demo.csv_path.open()))
    assert float(row["omega_rad_s"]) == pytest.approx(-30.0 * RPM)  # rolling forward: clockwise
    assert 0.0 < float(row["sinkage_m"]) < 0.1  # metres, not mm

    out = tmp_path / "sweep.csv"
    r = CliRunner().invoke(app, ["sweep", "--model", "rft", "--omega-rpm", "30,0", "--no-parallel", "--csv", str(out)])
    assert r.exit_code == 1, r.output  # the 0 RPM point failed, and is a row
    header = assert_units(out)
    assert {"omega_rpm", "omega_rad_s", "velocity_m_s", "sinkage_m", "velocity_z_m_s"} <= set(header)
    rows = list(csv.DictReader(out.open()))
    assert float(rows[0]["omega_rad_s"]) == pytest.approx(-30.0 * RPM) and rows[1]["omega_rad_s"] == ""

    monkeypatch.setattr(ml, "run_mpm_steady", fake_mpm_run)
    table = tmp_path / "wheel_mpm.csv"
    mpm_sweep_table(get_scenario("wheel"), [30.0], True, tmp_path / "runs", [], table)
    header = assert_units(table)
    assert {"surface_drop_m", "wall_time_s", "window_start_s", "window_end_s", "steps"} <= set(header)
    assert load_reference(table).column("surface_drop")[0] == 0.005


def _same(a: SweepResult, b: SweepResult) -> None:
    """The same records; a standard column ``b`` has and ``a`` had not (omega_rad_s) is empty: NaN."""
    assert len(a.records) == len(b.records)
    for ra, rb in zip(a.records, b.records):
        assert set(ra) <= set(rb) and all(math.isnan(rb[k]) for k in set(rb) - set(ra))
        for k, v in ra.items():
            if isinstance(v, float) and math.isnan(v):
                assert math.isnan(rb[k]), k
            else:
                assert rb[k] == v, k


def committed_sweeps() -> list[Path]:
    """The sweep CSVs of the repository (docs/, research/): written before the units were in the names."""
    found = []
    for folder in ("docs", "research"):
        for path in sorted((ROOT / folder).rglob("*.csv")):
            with path.open() as f:
                if f.readline().startswith("omega_rpm,ok,"):
                    found.append(path)
    return found


def test_the_repository_holds_sweep_csvs_of_the_old_header():
    old = [p for p in committed_sweeps() if "velocity," in p.read_text().splitlines()[0]]
    assert len(old) >= 10, old


@pytest.mark.parametrize("committed", committed_sweeps(), ids=lambda p: str(p.relative_to(ROOT)))
def test_an_old_header_and_a_new_header_read_the_same(committed, tmp_path):
    old = SweepResult.from_csv(committed)  # written before the units were in the names
    new_path = old.to_csv(tmp_path / "new.csv")
    header = new_path.read_text().splitlines()[0]
    assert "velocity_m_s" in header and ",velocity," not in header and ",omega," not in header
    new = SweepResult.from_csv(new_path)
    _same(old, new)
    assert np.array_equal(new.column("velocity_m_s"), old.column("velocity"), equal_nan=True)
    assert (load_reference(new_path).column("sinkage") == load_reference(committed).column("sinkage")).all()


def test_omega_rad_s_has_the_packages_sign_and_reads_back_as_the_records_omega(tmp_path):
    old = tmp_path / "old.csv"
    old.write_text("omega_rpm,ok,velocity,sinkage,omega,wall_time,error\n30,True,0.2,0.01,3.14159,12.5,\n")
    new = tmp_path / "new.csv"
    new.write_text(
        "omega_rpm,ok,velocity_m_s,sinkage_m,omega_rad_s,wall_time_s,error\n30,True,0.2,0.01,-3.14159,12.5,\n"
    )
    a, b = SweepResult.from_csv(old), SweepResult.from_csv(new)
    _same(a, b)
    assert a.records[0]["omega"] == 3.14159 and b.column("omega_rad_s")[0] == -3.14159
    assert "omega_rad_s" in b.to_csv(tmp_path / "again.csv").read_text().splitlines()[0]
    assert b.to_csv(tmp_path / "again.csv").read_text().splitlines()[1].split(",")[1] == "-3.14159"


# ---------------------------------------------------------------- each run's progress, runs at once


def test_each_run_of_a_sweep_reports_its_time_speed_and_eta(tmp_path, monkeypatch, capsys):
    from intrusim.figures.mpm import mpm_sweep

    monkeypatch.setattr(ml, "run_mpm_steady", fake_mpm_run)
    res = mpm_sweep(get_scenario("wheel"), np.array([30.0, 60.0]), True, True, tmp_path, workers=1)
    assert [r["ok"] for r in res.records] == [True, True]
    err = capsys.readouterr().err
    for w in (30, 60):
        lines = [line for line in err.splitlines() if line.startswith(f"grousered_wheel {w} RPM: ")]
        assert lines[0].endswith(f"running to t = 1.2 s in {tmp_path / f'grousered_wheel_{w}rpm'}"), err
        # the first report at the mean rate (6 s of wall for 0.3 s), then at the rate since it (6 s / 0.3 s)
        assert lines[1] == f"grousered_wheel {w} RPM: t 0.30/1.20 s, v 0.100 m/s, wall 6 s, ETA 18 s", err
        assert lines[2] == f"grousered_wheel {w} RPM: t 0.60/1.20 s, v 0.110 m/s, wall 12 s, ETA 12 s", err
        assert lines[4].endswith("t 1.20/1.20 s, v 0.130 m/s, wall 24 s, ETA 0 s"), err
        assert "done (" in lines[5] and "v 0.1000 m/s, sinkage 20.00 mm" in lines[5], err
    assert "done (1 of 2)" in err and "done (2 of 2)" in err and "1 at once" in err
    assert "omega sweep" not in err  # no bar of the points: the runs' own lines

    capsys.readouterr()
    again = mpm_sweep(get_scenario("wheel"), np.array([30.0]), True, True, tmp_path, workers=1)
    err = capsys.readouterr().err  # a finished run is reused (the fake left no time series to read: a failed row)
    assert "grousered_wheel 30 RPM: finished before, reused" in err and "FAILED (1 of 1 done)" in err
    assert not again.records[0]["ok"] and "timeseries.csv" in again.records[0]["error"]


def test_a_run_reports_at_most_every_few_seconds_and_from_a_worker_process(capfd):
    import pickle

    from intrusim.analysis.sweep import RunProgress, dask_map

    p = RunProgress("my_wheel 30 RPM", 1.2, every=5.0)
    for t, wall in ((0.1, 1.0), (0.2, 2.0), (0.3, 7.0), (0.4, 9.0), (0.5, 12.5)):
        p({"t": t, "x": 0.0, "z": 0.0, "vx": 0.12, "wall": wall})
    lines = capfd.readouterr().err.splitlines()
    assert [line.split(",")[0] for line in lines] == ["my_wheel 30 RPM: t 0.10/1.20 s", "my_wheel 30 RPM: t 0.30/1.20 s",
                                                      "my_wheel 30 RPM: t 0.50/1.20 s"]  # fmt: skip
    assert lines[0].endswith("ETA 11 s") and lines[1].endswith("ETA 27 s")  # 1 s per 0.1 s; then 6 s per 0.2 s

    # in a worker process of a local cluster: the same lines, on this terminal
    q = pickle.loads(pickle.dumps(RunProgress("my_wheel 60 RPM", 1.2)))
    done = []
    dask_map(
        q, [({"t": 0.6, "vx": 0.2, "wall": 30.0},)], n_workers=1, progress=False, on_done=lambda i, r: done.append(i)
    )
    assert done == [0]
    assert "my_wheel 60 RPM: t 0.60/1.20 s, v 0.200 m/s, wall 30 s, ETA 30 s" in capfd.readouterr().err


def test_workers_is_the_number_of_runs_at_once(tmp_path, monkeypatch):
    import os

    from intrusim._checks import InputError
    from intrusim.figures import mpm as figmpm

    cores = os.cpu_count() or 1
    assert figmpm.run_count(None, True, 50) == cores and figmpm.run_count(None, True, 1) == 1
    assert (
        figmpm.run_count(3, True, 2) == 2 and figmpm.run_count(3, True, 9) == 3 and figmpm.run_count(4, False, 9) == 1
    )
    for bad in (0, -1, 1.5, True):
        with pytest.raises(InputError, match="workers"):
            figmpm.run_count(bad, True, 3)
    seen = {}

    def fake_sweep(case, kind, rpm, *, parallel, n_workers, progress):
        seen.update(parallel=parallel, n_workers=n_workers, threads=case.mpm.cpu_threads)
        return SweepResult(case.name, kind, None, [])

    monkeypatch.setattr(figmpm, "sweep_omega", fake_sweep)
    figmpm.mpm_sweep_table(get_scenario("wheel"), [10, 20, 30], True, tmp_path, [], tmp_path / "t.csv", workers=2)
    assert seen == {"parallel": True, "n_workers": 2, "threads": max(1, cores // 2)}
    with figmpm.running_workers(1):  # reproduce --workers 1
        figmpm.mpm_sweep(get_scenario("wheel"), np.array([10.0, 20.0]), True, True, tmp_path)
    assert seen["parallel"] is False and seen["n_workers"] == 1
    with pytest.raises(InputError, match="workers"):
        figmpm.mpm_sweep(get_scenario("wheel"), np.array([10.0]), True, True, tmp_path, workers=0)


def test_reproduce_and_sweep_refuse_a_bad_workers(tmp_path):
    import os

    many = (os.cpu_count() or 1) + 1
    runner = CliRunner()
    for args in (["reproduce", "fig3ab", "--quick", "--runs", str(tmp_path), "--out", str(tmp_path)],
                 ["sweep", "--model", "rft", "--omega-rpm", "30", "--no-parallel"]):  # fmt: skip
        r = runner.invoke(app, [*args, "--workers", "0"])
        assert r.exit_code == 2 and not list(tmp_path.glob("*.png")), r.output
        r = runner.invoke(app, [*args, "--workers", str(many)])
        assert r.exit_code == 2 and "cores" in r.output, r.output
    r = runner.invoke(
        app, ["reproduce", "fig3ab", "--quick", "--no-parallel", "--workers", "2", "--out", str(tmp_path)]
    )
    assert r.exit_code == 2 and "--no-parallel" in r.output, r.output
