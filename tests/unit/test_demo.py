"""intrusim.demo: the README's first command on a small case (two omegas, a short MPM point)."""

import csv
import math

import pytest

from intrusim._checks import InputError
from intrusim.demo import run_demo


def test_demo_writes_table_and_png(tmp_path):
    res = run_demo(tmp_path, omega_rpm=(10.0, 60.0), mpm_t_max=0.7)
    rows = list(csv.DictReader(res.csv_path.open()))
    assert [r["model"] for r in rows] == ["rft", "rft", "drft", "drft", "mpm"]
    assert res.png_path.stat().st_size > 0
    v = {(r["model"], float(r["omega_rpm"])): float(r["velocity_m_s"]) for r in rows}
    assert v["rft", 60.0] > v["rft", 10.0] > 0
    # DRFT's inertial and structural corrections slow the wheel at speed (paper, Fig 5A)
    assert v["drft", 60.0] < v["rft", 60.0]
    assert math.isfinite(v["mpm", 30.0]) and v["mpm", 30.0] > 0
    assert "drft" in res.table()


def test_demo_refuses_bad_omega():
    with pytest.raises(InputError, match="omega_rpm"):
        run_demo(None, omega_rpm=(10.0, -5.0), mpm_omega_rpm=None)
