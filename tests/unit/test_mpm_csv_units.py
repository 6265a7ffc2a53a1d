"""The MPM run folder's timeseries.csv and the RFT map's alpha_map.csv name each column's unit
(docs/getting-started.md, "CSV files"); files written before, without, read to the same arrays."""

from __future__ import annotations

import csv
import json
import shutil
from pathlib import Path

import numpy as np
import pytest
from cli_helpers import block_config
from test_sweep_mpm import documented_unitless

from intrusim.errors import InputError
from intrusim.mpm import io as mpm_io
from intrusim.mpm.io import read_timeseries, timeseries_column, timeseries_key, write_csv, write_timeseries
from intrusim.mpm.rft_map import (
    ALPHA_MAP_UNITS,
    PlateMapCase,
    alpha_map_column,
    alpha_map_row,
    case_record,
    read_alpha_map,
)

ROOT = Path(__file__).resolve().parents[2]
UNITS = ("_s", "_m", "_rad", "_m_s", "_rad_s", "_N", "_N_m", "_J", "_kg", "_N_m3", "_kg_m3", "_Pa", "_cells")
OLD_RUN = ROOT / "research" / "outputs" / "gpu_h200"  # a run folder's files written before the units


def bare_columns(header: list[str]) -> list[str]:
    """The columns of ``header`` that neither end in a unit nor are a documented unitless name."""
    unitless = documented_unitless()
    return [h for h in header if not h.endswith(UNITS) and h not in unitless]


def _same(a: dict[str, np.ndarray], b: dict[str, np.ndarray]) -> None:
    assert list(a) == list(b)
    for k in a:
        if a[k].dtype == object:
            assert a[k].tolist() == b[k].tolist(), k
        else:
            np.testing.assert_array_equal(a[k], b[k], err_msg=k)


ROWS = [  # two bodies; the first row from before the front / rear split (no *_ahead)
    {"time": 0.0, "step": 0, "x": 0.1, "z": 0.2, "theta": 0.0, "vx": 0.0, "vz": 0.0, "omega": -0.0, "fx": 0.0,
     "fz": 0.0, "moment": 0.0, "b1_x": 0.3, "b1_fz": 0.0, "kinetic_energy": 0.0, "grain_mass": 26.8},
    {"time": 0.01, "step": 264, "x": 0.1001, "z": 0.199, "theta": -0.001, "vx": 0.0018, "vz": -0.09,
     "omega": -0.2, "fx": 0.19, "fz": 2.2, "moment": 0.0198, "fx_ahead": -0.17, "fz_ahead": 0.58,
     "moment_ahead": -0.012, "b1_x": 0.31, "b1_fz": 1.5, "kinetic_energy": 5.6e-05, "grain_mass": 26.8,
     "outflow_mass": 0.01},
]  # fmt: skip


def test_the_columns_name_their_units_and_map_back_to_the_rows_keys():
    assert [timeseries_column(k) for k in ("time", "step", "x", "theta", "vx", "omega", "fx", "moment")] == [
        "time_s", "step", "x_m", "theta_rad", "vx_m_s", "omega_rad_s", "fx_N", "moment_N_m"
    ]  # fmt: skip
    assert timeseries_column("moment_ahead") == "moment_ahead_N_m" and timeseries_column("b2_fz") == "b2_fz_N"
    for key in mpm_io.TIMESERIES_UNITS:
        for k in (key, f"b1_{key}"):
            assert timeseries_key(timeseries_column(k)) == k and timeseries_key(k) == k  # new and old names
    assert timeseries_key("bx") == "bx" and timeseries_key("b1_") == "b1_"  # not a body prefix


def test_an_old_and_a_new_timeseries_header_read_to_the_same_arrays(tmp_path):
    old, new = tmp_path / "old.csv", tmp_path / "new.csv"
    write_csv(old, ROWS)  # what the solver wrote before the units were in the names
    write_timeseries(new, ROWS)
    header = next(csv.reader(new.open()))
    assert header[:11] == ["time_s", "step", "x_m", "z_m", "theta_rad", "vx_m_s", "vz_m_s", "omega_rad_s", "fx_N",
                           "fz_N", "moment_N_m"]  # fmt: skip
    assert {"b1_x_m", "b1_fz_N", "fx_ahead_N", "moment_ahead_N_m", "kinetic_energy_J", "outflow_mass_kg"} <= set(header)
    assert not bare_columns(header)
    a, b = read_timeseries(old), read_timeseries(new)
    _same(a, b)
    assert np.isnan(a["fx_ahead"][0]) and a["fx_ahead"][1] == -0.17 and b["b1_fz"].tolist() == [0.0, 1.5]
    assert read_timeseries(tmp_path / "new.csv")["time"].tolist() == [0.0, 0.01]
    (tmp_path / "run").mkdir()
    shutil.copy(new, tmp_path / "run" / "timeseries.csv")
    _same(read_timeseries(tmp_path / "run"), b)  # the folder that holds it
    with pytest.raises(InputError, match="no such file"):
        read_timeseries(tmp_path / "none.csv")


def test_a_committed_old_run_folder_summarises_the_same_from_its_rewritten_header(tmp_path):
    """research/outputs/gpu_h200 (a 30 RPM wheel, written before the units): summarise_run reads it
    and the same rows under the new header to the same steady state."""
    from intrusim.scenarios import get_scenario
    from intrusim.scenarios.mpm_locomotion import MPMSettings, mpm_config, summarise_run

    assert next(csv.reader((OLD_RUN / "timeseries.csv").open()))[:3] == ["time", "step", "x"]
    info = json.loads((OLD_RUN / "locomotion.json").read_text())
    cfg = mpm_config(get_scenario("wheel"), MPMSettings.model_validate(info["settings"]), info["omega_rpm"])
    old_ts = read_timeseries(OLD_RUN / "timeseries.csv")
    states = []
    for name in ("old", "new"):
        run = tmp_path / name
        run.mkdir()
        (run / "config.json").write_text(json.dumps({"config": cfg.model_dump(mode="json")}))
        shutil.copy(OLD_RUN / "locomotion.json", run)
        if name == "old":
            shutil.copy(OLD_RUN / "timeseries.csv", run)
        else:
            n = len(old_ts["time"])
            write_timeseries(run / "timeseries.csv", [{k: float(v[i]) for k, v in old_ts.items()} for i in range(n)])
            assert next(csv.reader((run / "timeseries.csv").open()))[:3] == ["time_s", "step", "x_m"]
        states.append(summarise_run(run, t_end=3.0))
    a, b = states
    assert a.velocity == b.velocity > 0 and a.sinkage == b.sinkage > 0 and a.window == b.window
    for k in a.series:
        np.testing.assert_array_equal(a.series[k], b.series[k], err_msg=k)


def test_a_tiny_run_names_every_unit_and_resuming_an_old_header_folder_rewrites_it_whole(tmp_path):
    """A real MPM run with a body: every column of its timeseries.csv has a unit or is documented
    unitless. Its folder made old (the header without units, as a run of an earlier version left it)
    and resumed to a later end: the file is rewritten whole under the new header, the old rows read
    the same as before and the new ones follow, as in an uninterrupted run."""
    import tomllib

    from intrusim.mpm.config import MPMConfig
    from intrusim.mpm.solver import Solver

    def config(name: str, t_end: float) -> MPMConfig:
        cfg = MPMConfig.model_validate(tomllib.loads(block_config()))
        cfg.output.directory, cfg.time.t_end = str(tmp_path / name), t_end
        return cfg

    Solver(config("run", 0.02)).run()
    path = tmp_path / "run" / "timeseries.csv"
    header = next(csv.reader(path.open()))
    assert header[:3] == ["time_s", "step", "x_m"] and "fz_N" in header and "moment_ahead_N_m" in header
    assert not bare_columns(header), header
    first = read_timeseries(path)
    write_csv(path, [{k: float(v[i]) for k, v in first.items()} for i in range(len(first["time"]))])  # old header
    assert next(csv.reader(path.open()))[:3] == ["time", "step", "x"]
    _same(read_timeseries(path), first)

    resumed = Solver.resume(tmp_path / "run")
    resumed.run(0.03)
    whole = Solver(config("whole", 0.03))
    whole.run()
    text = path.read_text()
    assert text.splitlines()[0] == (tmp_path / "whole" / "timeseries.csv").read_text().splitlines()[0]
    assert ",time," not in "," + text.splitlines()[0] + "," and text.count("\n") == len(whole.rows) + 1
    after = read_timeseries(path)
    n = len(first["time"])
    for k in first:
        np.testing.assert_array_equal(after[k][:n], first[k], err_msg=k)
    np.testing.assert_allclose(after["time"], read_timeseries(tmp_path / "whole")["time"], rtol=0, atol=1e-12)
    np.testing.assert_allclose(after["fz"], read_timeseries(tmp_path / "whole")["fz"], rtol=1e-9, atol=1e-12)


# ---------------------------------------------------------------- alpha_map.csv


def _map_rows() -> list[dict]:
    rows = []
    for beta, gamma, az in ((0.0, 1.5707963267948966, 201121.7), (1.5707963267948966, 0.0, 1234.5)):
        rec = case_record(PlateMapCase(beta=beta, gamma=gamma, cell_size=0.005, plate_thickness=0.01))
        rows.append({**rec, "alpha_x": 12.5, "alpha_z": az, "alpha_x_std": 1.0, "alpha_z_std": 2.0,
                     "depth_mean": 0.0398, "steps": 1200})  # fmt: skip
    return rows


def _write(path: Path, rows: list[dict]) -> Path:
    with path.open("w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    return path


def test_an_old_and_a_new_alpha_map_header_read_to_the_same_arrays(tmp_path):
    rows = _map_rows()
    assert set(rows[0]) <= set(ALPHA_MAP_UNITS)  # every key of a plate's record has its unit
    old = _write(tmp_path / "old.csv", rows)
    new = _write(tmp_path / "new.csv", [alpha_map_row(r) for r in rows])
    header = next(csv.reader(new.open()))
    assert {"beta_rad", "gamma_rad", "depth_m", "alpha_x_N_m3", "alpha_z_N_m3", "speed_m_s", "rho_c_kg_m3",
            "youngs_modulus_Pa", "grid_offset_cells", "domain_m", "contact", "mu_s", "steps"} <= set(header)  # fmt: skip
    assert not bare_columns(header) and not bare_columns([alpha_map_column(k) for k in ALPHA_MAP_UNITS])
    a, b = read_alpha_map(old), read_alpha_map(new)
    _same(a, b)
    assert b["alpha_z"].tolist() == [201121.7, 1234.5] and b["contact"].tolist() == ["nodes", "nodes"]
    assert np.isnan(b["fluidity_diameter"]).all() and b["domain"][0] == "0.3x0.2"
    with pytest.raises(InputError, match="no such file"):
        read_alpha_map(tmp_path / "none.csv")


def test_the_example_appends_to_an_old_map_under_its_own_columns(tmp_path, monkeypatch):
    """examples/mpm_rft_map.py: a map written before the units reads (its cases count as done) and
    a new case is appended under the old columns; a new map gets the new ones."""
    import importlib.util

    spec = importlib.util.spec_from_file_location("mpm_rft_map", ROOT / "examples" / "mpm_rft_map.py")
    ex = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(ex)
    rows = _map_rows()
    keep = [k for k in ex.KEYS if k in rows[0]]
    old = _write(tmp_path / "old.csv", [{k: r[k] for k in keep} for r in rows[:1]])
    header, done = ex._existing(old)
    assert header == keep and done == {ex._key(rows[0]["beta"], rows[0]["gamma"])}
    new = _write(tmp_path / "new.csv", [alpha_map_row({k: r[k] for k in keep}) for r in rows[:1]])
    assert ex._existing(new) == ([alpha_map_column(k) for k in keep], done)
    assert not bare_columns(ex.FIELDS), ex.FIELDS
    _same(ex.read_map(old), ex.read_map(new))
    # a finished case is appended under the file's own columns, whichever they are
    rec = {**rows[1], "wall_s": 3.5}
    for path in (old, new):
        header, _ = ex._existing(path)
        with path.open("a", newline="") as f:
            csv.DictWriter(f, fieldnames=header, extrasaction="ignore").writerow({**rec, **alpha_map_row(rec)})
    _same(ex.read_map(old), ex.read_map(new))
    assert ex.read_map(new)["alpha_z"].tolist() == [201121.7, 1234.5]
