"""A user's own wheel through ``intrusim calibrate --quick``, as a new user meets it: the box sizes
itself, every failure and warning reaches the terminal, everything lands under --out, nothing is
left behind, and bad output folders or boxes are refused before any compute."""

import csv
import json
import math
from types import SimpleNamespace

import numpy as np
import pytest
from cli_helpers import MY_WHEEL, run

ARGS = ["calibrate", "my_wheel.toml", "--quick", "--params", "xi", "--starts", "1"]


@pytest.fixture
def scratch(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "my_wheel.toml").write_text(MY_WHEEL)
    return tmp_path


def test_a_users_wheel_calibrates_end_to_end_with_everything_under_out(scratch):
    r = run(*ARGS, "--mpm-omegas", "30,60", "--out", "cal")
    assert r.exit_code == 0, r.output
    out = r.output
    assert "wheel 'my_wheel': hub_diameter = 0.2 m" in out  # the effective body, named after its file
    assert "box grown to 1 x 0.62 m" in out  # radius 0.115 m: the quick box (0.5 m high) could not hold it
    assert "warning: my_wheel: cells of 20 mm are coarser than a fifth" in out
    assert "constant forward push, 2.09 N" in out  # the push DRFT is given is said (4 N x 12 / 23)
    assert "verdict: " in out and "v MPM m/s" in out
    rows = list(csv.DictReader(open(scratch / "cal" / "calibration_my_wheel_mpm.csv")))
    assert [float(r["omega_rpm"]) for r in rows] == [30.0, 60.0]
    loose = [r for r in rows if r["settled"] in ("False", "0", "0.0")]
    short = [r for r in loose if r["outcome"] == "too short"]  # 1.2 s: not two revolutions at 30 RPM
    assert ("were too short to judge" in out) == bool(short)  # unsettled runs in the fit are said, by outcome
    assert ("did not settle" in out) == bool(len(loose) > len(short))
    body = json.loads((scratch / "cal" / "calibration_my_wheel.body.json").read_text())
    assert body["name"] == "my_wheel" and body["length_scale"] == pytest.approx(0.23) and body["radius"] == 0.115
    assert body["external_fx"] == 0.0 and body["external_fx_as_run"] == pytest.approx(
        4.0 * 12.0 / 23.0
    )  # the push, said
    assert sorted(p.name for p in (scratch / "cal" / "mpm-runs").iterdir()) == ["my_wheel_30rpm", "my_wheel_60rpm"]
    assert not list(scratch.rglob(".lock")) and not (scratch / "runs").exists() and not (scratch / "figures").exists()


@pytest.mark.parametrize("out", ["/proc/intrusim_out", "my_wheel.toml/sub"])
def test_an_output_folder_that_cannot_be_written_is_refused_before_any_run(scratch, out):
    r = run(*ARGS, "--mpm-omegas", "30,60", "--out", out)
    assert r.exit_code == 2 and "--out" in r.output and ("not writable" in r.output or "is a file" in r.output)
    assert "MPM runs not finished" not in r.output and sorted(p.name for p in scratch.iterdir()) == ["my_wheel.toml"]


def test_a_read_only_output_folder_is_refused_before_any_run(scratch):
    import os

    ro = scratch / "ro"
    ro.mkdir()
    ro.chmod(0o555)
    try:
        if os.access(ro, os.W_OK):
            pytest.skip("this user (root) writes into read-only folders: /proc above stands in for it")
        r = run(*ARGS, "--mpm-omegas", "30,60", "--out", "ro/cal")
        assert r.exit_code == 2 and "not writable" in r.output and not any(ro.iterdir())
    finally:
        ro.chmod(0o755)


def test_a_box_set_by_hand_too_small_for_the_wheel_is_refused_naming_its_height(scratch):
    r = run(*ARGS, "--mpm-omegas", "30,60", "--out", "cal", "--set", "domain=[1.0, 0.5]", "--set", "cell_size=0.02")
    assert r.exit_code == 2 and "does not fit under the box's top: its height 0.5 m" in r.output
    assert "start_x" not in r.output.splitlines()[-1]  # the limit is the height (the wrong fix was named before)
    assert sorted(p.name for p in scratch.iterdir()) == ["my_wheel.toml"]  # nothing run, nothing written


def test_each_failed_run_says_its_reason_and_fix_on_the_terminal(scratch):
    # a 0.4 m bed: the wheel reaches the wall before the averaging window opens
    r = run(*ARGS, "--mpm-omegas", "30,60", "--out", "cal", "--set", "length=0.4")
    assert r.exit_code == 2, r.output
    assert (
        "warning: my_wheel at 30 RPM failed: " in r.output
        and "at 60 RPM failed" in r.output
        and "before the averaging window" in r.output
    )
    assert "(fix: a longer bed" in r.output and "no MPM run of my_wheel finished" in r.output
    assert not list(scratch.rglob(".lock"))


def _result(values, bounds, jac, cost=1e-3, local=()):
    from intrusim.analysis.calibration import CalibrationResult

    cmp = SimpleNamespace(max_abs_rel_error_velocity=0.05, max_abs_rel_error_sinkage=0.2)
    return CalibrationResult(
        scenario=None, params=tuple(values), values=values, initial=values, bounds=bounds, comparison=cmp, cost=cost,
        nfev=1, success=True, message="", meta={"local_fits": list(local)}, jacobian=np.asarray(jac, float),
    )  # fmt: skip


def test_std_errors_are_the_gauss_newton_ones_and_a_flat_direction_is_unidentified():
    j = np.array([[1.0, 0.0], [0.0, 2.0], [0.0, 0.0], [1.0, 0.0]])  # 4 residuals, 2 parameters
    res = _result({"xi": 0.5, "psi": 1.0}, {"xi": (0.05, 3.0), "psi": (0.0, 5.0)}, j, cost=0.5)
    se = res.std_errors()
    s2 = 2 * 0.5 / (4 - 2)
    assert se["xi"] == pytest.approx(math.sqrt(s2 / 2.0)) and se["psi"] == pytest.approx(math.sqrt(s2 / 4.0))
    flat = _result(
        {"xi": 0.5, "psi": 1.0}, {"xi": (0.05, 3.0), "psi": (0.0, 5.0)}, [[1.0, 2.0], [2.0, 4.0], [0.5, 1.0]]
    )
    assert flat.std_errors() == {"xi": math.inf, "psi": math.inf}  # only xi + 2 psi is seen by the data
    exact = _result({"xi": 0.5, "psi": 1.0}, {"xi": (0.05, 3.0), "psi": (0.0, 5.0)}, [[1.0, 0.0], [0.0, 2.0]], cost=0.0)
    assert exact.std_errors() == {"xi": math.inf, "psi": math.inf}  # 2 residuals, 2 parameters: no error to tell


def test_a_parameter_fitted_near_zero_is_judged_against_its_range():
    from intrusim.analysis.calibration_job import _fit_warnings

    res = _result({"psi_offset": 1e-3}, {"psi_offset": (-1.0, 1.0)}, [[10.0], [20.0], [5.0]], cost=1e-4)
    said, warned = [], []
    _fit_warnings(res, said.append, warned.append)
    assert not any("not identified" in w for w in warned)  # s.e. 4e-4 against a range of 2
    assert any("psi_offset = 0.001 +- " in s for s in said)


def test_the_fit_says_its_verdict_a_bound_and_a_parameter_the_data_do_not_fix():
    from intrusim.analysis.calibration_job import _fit_warnings

    local = [{"values": {"xi": 0.5, "psi": v}, "cost": c} for v, c in ((4.62, 1e-3), (3.0, 1.02e-3), (4.9, 1.01e-3))]
    res = _result({"xi": 0.5, "psi": 4.99}, {"xi": (0.05, 3.0), "psi": (0.0, 5.0)}, [[1.0, 0.0], [0.0, 0.0], [1.0, 0.0]],
                  local=local)  # fmt: skip
    said, warned = [], []
    _fit_warnings(res, said.append, warned.append)
    assert any("NOT within 15% of the MPM" in s and "sinkage 20.0%" in s for s in said)
    assert any("misses the 15% target" in w for w in warned)
    assert any("psi = 4.99 is at a bound of its range [0, 5]" in w for w in warned)
    assert any("psi = 4.99 is not identified by the data" in w and "psi = 3-4.9" in w for w in warned)
    assert not any(w.startswith("xi") for w in warned)  # xi is identified
    assert any("xi = 0.5 +- " in s and "psi = 4.99 (not identified)" in s for s in said)


def test_sweep_writes_its_csv_and_the_effective_body_into_a_new_folder(scratch):
    r = run("sweep", "--scenario", "my_wheel.toml", "--omega-rpm", "30,60", "--workers", "1", "--csv", "out/s.csv")
    assert r.exit_code == 0, r.output
    body = json.loads((scratch / "out" / "s.body.json").read_text())
    assert body["name"] == "my_wheel" and body["lug_count"] == 12 and "hub_diameter" not in body["defaulted"]
    header = (scratch / "out" / "s.csv").read_text().splitlines()[0].split(",")
    assert header[:5] == ["omega_rpm", "omega_rad_s", "ok", "velocity_m_s", "sinkage_m"]


@pytest.mark.parametrize(
    "args",
    [["sweep", "--scenario", "my_wheel.toml", "--omega-rpm", "30", "--csv", "/proc/intrusim/s.csv"],
     ["mpm", "sweep", "--scenario", "my_wheel.toml", "--quick", "--omega-rpm", "30", "--out", "/proc/intrusim"],
     ["mpm", "steady", "--scenario", "my_wheel.toml", "--quick", "--omega-rpm", "30", "--out", "/proc/intrusim"]],
)  # fmt: skip
def test_every_command_refuses_an_unwritable_output_before_compute(scratch, args):
    r = run(*args)
    assert r.exit_code == 2 and "is not writable" in r.output and "v m/s" not in r.output
    assert sorted(p.name for p in scratch.iterdir()) == ["my_wheel.toml"]
