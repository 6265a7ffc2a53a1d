"""intrusim.demo: the README's first command on a small case (two omegas, a short MPM point)."""

import csv
import json
import math
from pathlib import Path

import pytest

from intrusim._checks import InputError
from intrusim.analysis.model_file import read_model
from intrusim.demo import MODEL_ERRORS, OWN_WHEEL_PAGE, RECOMMENDED, recommended_model_path, run_demo

ROOT = Path(__file__).resolve().parents[2]


def test_demo_writes_table_and_png(tmp_path):
    res = run_demo(tmp_path, omega_rpm=(10.0, 60.0), mpm_t_max=0.7)
    rows = list(csv.DictReader(res.csv_path.open()))
    assert [r["model"] for r in rows] == ["rft", "rft", "drft", "drft", RECOMMENDED, RECOMMENDED, "mpm"]
    assert res.png_path.stat().st_size > 0
    v = {(r["model"], float(r["omega_rpm"])): float(r["velocity_m_s"]) for r in rows}
    s = {(r["model"], float(r["omega_rpm"])): float(r["sinkage_m"]) for r in rows}
    assert v["rft", 60.0] > v["rft", 10.0] > 0
    # DRFT's inertial and structural corrections slow the wheel at speed (paper, Fig 5A)
    assert v["drft", 60.0] < v["rft", 60.0]
    assert math.isfinite(v["mpm", 30.0]) and v["mpm", 30.0] > 0
    # the calibrated model: finite, and slower and deeper than the paper's DRFT at 60 RPM, as the MPM
    # references are (docs/results.md, "Blind prediction": the paper's DRFT +166 % in v there)
    for w in (10.0, 60.0):
        assert math.isfinite(v[RECOMMENDED, w]) and v[RECOMMENDED, w] > 0
        assert math.isfinite(s[RECOMMENDED, w]) and s[RECOMMENDED, w] > 0
    assert v[RECOMMENDED, 60.0] < v["drft", 60.0] and s[RECOMMENDED, 60.0] > s["drft", 60.0]
    assert "drft" in res.table() and RECOMMENDED in res.table()


def test_demo_notes_name_the_recommended_model_its_errors_and_the_page():
    res = run_demo(None, omega_rpm=(30.0,), mpm_omega_rpm=None)
    text = "\n".join(res.notes)
    assert f"Recommended model: {RECOMMENDED}" in text
    assert str(recommended_model_path()) in text
    assert OWN_WHEEL_PAGE in text and (ROOT / OWN_WHEEL_PAGE).is_file()
    for label, error in MODEL_ERRORS.items():
        assert f"  {label}: {error}" in text
    assert "not yet converged" in text
    # the calibrated row gets the MPM runs' 4 N push (its file's mpm_push), the others none
    assert "includes the MPM runs' constant 4 N push" in text and "rft and drft have 0 N" in text


def test_recommended_model_is_the_documented_blind_fit():
    """The shipped file is docs/results.md's "4 fitted" model (docs/figures/blind.model.json)."""
    path = recommended_model_path()
    assert path.is_file()
    shipped, documented = json.loads(path.read_text()), json.loads((ROOT / "docs/figures/blind.model.json").read_text())
    for key in ("kind", "force_model", "mpm_push", "calibrated_on"):
        assert shipped[key] == documented[key], key
    m = read_model(path)
    assert m.kind == "drft" and m.mpm_push
    fm = m.force_model
    assert (round(fm.xi, 3), round(fm.psi_offset, 3), round(fm.psi_slope, 3), fm.lam) == (0.662, 0.370, 0.595, 2.6)
    assert round(fm.zone_width, 3) == 0.139 and fm.structural == "wheel-rear-half-circle"
    # the errors the demo states are the fit's own record
    assert round(100 * m.fit["max_abs_rel_error_velocity"], 1) == 10.4
    assert round(100 * m.fit["max_abs_rel_error_sinkage"], 1) == 16.2
    assert "10.4 %" in MODEL_ERRORS[RECOMMENDED] and "16.2 %" in MODEL_ERRORS[RECOMMENDED]


def test_demo_refuses_bad_omega():
    with pytest.raises(InputError, match="omega_rpm"):
        run_demo(None, omega_rpm=(10.0, -5.0), mpm_omega_rpm=None)
