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
