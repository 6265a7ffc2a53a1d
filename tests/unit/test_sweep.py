"""Omega sweeps: bad points become error records, the rest is returned; Dask path."""

import numpy as np
import pytest

from intrusim._checks import InputError
from intrusim.analysis.sweep import sweep_omega
from intrusim.scenarios import get_scenario


@pytest.fixture(scope="module")
def wheel():
    s = get_scenario("wheel")
    s.run.average_revolutions = 1
    return s


def test_bad_points_become_error_records(wheel, tmp_path):
    res = sweep_omega(wheel, "rft", [30.0, -10.0, 0.0, float("nan"), 60.0], parallel=False, progress=False)
    ok = [r["ok"] for r in res.records]
    assert ok == [True, False, False, False, True]
    assert "omega_rpm must be > 0" in res.records[1]["error"] and "omega_rpm must be > 0" in res.records[2]["error"]
    assert "finite" in res.records[3]["error"]
    v = res.column("velocity")
    assert np.isfinite(v[[0, 4]]).all() and np.isnan(v[1:4]).all()
    assert "ERROR" in res.table()
    text = res.to_csv(tmp_path / "s.csv").read_text()
    assert text.count("\n") == 6


def test_integrator_failure_is_a_record_not_a_crash(wheel):
    bad = wheel.model_copy(deep=True)
    bad.run.dt_max = 1e-3
    bad.run.max_extensions = 0
    heavy = bad.model_copy(update={"mass_z": 1e5})  # the medium cannot carry it: sinks out of bounds
    res = sweep_omega(heavy, "rft", [30.0], parallel=False, progress=False)
    assert not res.records[0]["ok"] and "IntegratorError" in res.records[0]["error"]


def test_empty_or_unsupported(wheel):
    with pytest.raises(InputError, match="empty"):
        sweep_omega(wheel, "rft", [], parallel=False)
    with pytest.raises(InputError, match="supports"):
        sweep_omega(wheel.model_copy(update={"supported_models": ("rft",)}), "drft", [10.0], parallel=False)


def test_dask_matches_serial(wheel):
    pts = [20.0, -1.0, 50.0]
    ser = sweep_omega(wheel, "drft", pts, parallel=False, progress=False)
    par = sweep_omega(wheel, "drft", pts, parallel=True, n_workers=1, progress=False)  # 1 process: cheap start
    assert [r["ok"] for r in par.records] == [True, False, True]
    assert np.allclose(par.column("velocity")[[0, 2]], ser.column("velocity")[[0, 2]], rtol=1e-12)
