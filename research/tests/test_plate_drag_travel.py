"""research/plate_drag_travel.py: the window means and the excess lambda (formulas), bad options
refused before any run, and one coarse run end to end."""

import importlib.util
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

SCRIPT = Path(__file__).resolve().parents[1] / "plate_drag_travel.py"
spec = importlib.util.spec_from_file_location("plate_drag_travel", SCRIPT)
pdt = importlib.util.module_from_spec(spec)
spec.loader.exec_module(pdt)


def test_window_means_average_each_window_and_leave_an_empty_one_nan():
    x = np.array([0.005, 0.015, 0.025, 0.035, 0.045])
    f = np.array([1.0, 3.0, 5.0, 7.0, 9.0])
    m = pdt.window_means(x, f, np.array([0.0, 0.02, 0.04, 0.1, 0.2]))
    assert m[:3] == pytest.approx([2.0, 6.0, 9.0])
    assert np.isnan(m[3])
    with pytest.raises(ValueError):
        pdt.window_means(x, f, np.array([0.02, 0.01]))


def test_excess_lambda_returns_the_lambda_of_a_pure_v2_excess():
    rho, area, lam = 900.0, 0.016, 1.1
    slow, fast = 0.04, 0.64
    f = lambda v: 17.4 + lam * rho * area * v**2  # noqa: E731
    assert pdt.excess_lambda(np.array([f(fast)]), np.array([f(slow)]), fast, slow)[0] == pytest.approx(lam)
    with pytest.raises(ValueError):
        pdt.excess_lambda(np.ones(1), np.ones(1), 0.04, 0.64)


@pytest.mark.parametrize("options, message", [(["--speeds", "0.04"], "--speeds"), (["--speeds", "0.04", "0.04"], "--speeds"),
                                              (["--windows", "0.02", "0.3"], "--windows"), (["--band", "-1"], "--band"),
                                              (["--flip", "2"], "--flip"), (["--cfl", "0"], "--cfl"),
                                              (["--shape", "cubic"], "--shape")])  # fmt: skip
def test_bad_options_are_refused_before_any_run(options, message, tmp_path):
    res = subprocess.run(
        [sys.executable, str(SCRIPT), *options, "--out", str(tmp_path)], capture_output=True, text=True, timeout=120
    )
    assert res.returncode == 2 and message in res.stderr
    assert not any(tmp_path.iterdir())


def test_a_coarse_run_writes_the_table_and_the_figure(tmp_path):
    res = subprocess.run([sys.executable, str(SCRIPT), "--speeds", "0.16", "0.64", "--travel", "0.04", "--windows", "0.02", "0.04",
                          "--cell-mm", "7.5", "--threads", "2", "--out", str(tmp_path)], capture_output=True, text=True, timeout=600)  # fmt: skip
    assert res.returncode == 0, res.stderr
    stem = tmp_path / "plate_drag_travel0.04m_band1_E1e+06_h7.5mm"  # a cell size with a dot: the name keeps it
    rows = Path(f"{stem}.csv").read_text().splitlines()
    assert rows[0] == "speed_m_s,quantity,0.02-0.04 m" and len(rows) == 4
    drag = [float(r.split(",")[2]) for r in rows[1:3]]
    assert 0 < drag[0] < drag[1]  # the faster plate meets more resistance
    assert Path(f"{stem}.png").stat().st_size > 0
