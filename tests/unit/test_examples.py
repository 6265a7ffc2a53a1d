"""Smoke tests of the user examples in examples/: each runs on tiny settings and gives sane output."""

from __future__ import annotations

import importlib.util
import math
import tomllib
from pathlib import Path

import pytest

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


def _load(name: str):
    spec = importlib.util.spec_from_file_location(f"example_{name}", EXAMPLES / f"{name}.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def test_forces_of_my_shape(tmp_path):
    rows = _load("forces_of_my_shape").main(["--depths-mm", "10,40", "--out", str(tmp_path)])
    assert (tmp_path / "forces.csv").exists()
    rft = [r for r in rows if r["model"] == "rft"]
    assert rft[1]["fz_N"] > rft[0]["fz_N"] > 0  # deeper: more lift
    assert all(r["fx_N"] < 0 for r in rft)  # drag opposes the forward motion
    inertial = [r for r in rows if r["model"] == "drft-inertial"]
    assert all(abs(d["fx_N"]) >= abs(r["fx_N"]) for d, r in zip(inertial, rft))


def test_drft_sweep(tmp_path):
    png = _load("drft_sweep").main(["--omega-rpm", "50", "--out", str(tmp_path)])
    assert png.stat().st_size > 0
    text = (tmp_path / "sweep_drft.csv").read_text()
    assert "50" in text and "velocity" in text


def test_mpm_quick_wheel():
    summary = _load("mpm_quick_wheel").main(["--t-max", "0.7"])
    assert math.isfinite(summary["velocity"]) and summary["velocity"] > 0
    assert 0 < summary["sinkage"] < 0.1


def test_mpm_run_from_toml(tmp_path):
    from intrusim.mpm.config import MPMConfig
    from intrusim.mpm.solver import Solver

    data = tomllib.loads((EXAMPLES / "mpm_column_collapse.toml").read_text())
    data["time"]["t_end"] = 0.02
    data.setdefault("backend", {})["cpu_threads"] = 1
    data.setdefault("output", {})["directory"] = str(tmp_path / "collapse")
    solver = Solver(MPMConfig.model_validate(data))
    solver.run()
    assert solver.t == pytest.approx(0.02, abs=2e-3)


def test_calibrate_drft():
    summary = _load("calibrate_drft").main(["--params", "xi", "--max-nfev", "3"])
    assert summary["params"] == ["xi"]
    assert math.isfinite(summary["max_abs_rel_error"])


def test_mpm_rft_map(tmp_path):
    import subprocess
    import sys

    args = [
        "run",
        "--out",
        str(tmp_path),
        "--betas",
        "0",
        "--gammas",
        "-90",
        "--cell-mm",
        "10",
        "--thickness-mm",
        "20",
        "--plate-mm",
        "20",
        "--bed-mm",
        "150",
        "--domain-mm",
        "300x200",
        "--workers",
        "1",
    ]
    res = subprocess.run(
        [sys.executable, str(EXAMPLES / "mpm_rft_map.py"), *args], capture_output=True, text=True, timeout=300
    )
    assert res.returncode == 0, res.stdout + res.stderr
    header, row = (tmp_path / "alpha_map.csv").read_text().splitlines()
    alpha_z = float(row.split(",")[header.split(",").index("alpha_z_N_m3")])
    assert 1e3 < abs(alpha_z) < 1e6  # N/m^3: of the order of poppy seeds' 0.1-1 N/cm^3
    assert row.split(",")[header.split(",").index("contact")] == "nodes"  # the MPM's default contact
    bad = subprocess.run([sys.executable, str(EXAMPLES / "mpm_rft_map.py"), *args[:3], "--contact", "nodse"],
                         capture_output=True, text=True, timeout=300)  # fmt: skip
    assert bad.returncode == 2 and "contact must be one of nodes, surface, band" in bad.stderr
