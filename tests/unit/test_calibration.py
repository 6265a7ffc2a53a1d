"""DRFT calibration on MPM (analysis/calibration.py): psi fits, parameter recovery, bad input, CLI."""

import csv
import json
import math
import re

import numpy as np
import pytest
from typer.testing import CliRunner

from intrusim.analysis.calibration import (
    FAILED_RESIDUAL,
    calibrate,
    compare,
    drft_steady_states,
    fit_psi_affine,
    fit_psi_linear,
    leave_one_out,
    load_reference,
    parameter_values,
    with_mpm_push,
    with_parameters,
)  # fmt: skip
from intrusim.analysis.steady import run_steady
from intrusim.analysis.sweep import SweepResult
from intrusim.cli import app
from intrusim.laws.drft import AffinePsi, identity_psi
from intrusim.scenarios import grousered_wheel_scenario, small_wheel_scenario

RPM = 2 * math.pi / 60


def _wheel(structural: str = "wheel-rear-half-effective"):
    """The Table S1 wheel with the paper's DRFT values and the given rear-half split."""
    s = grousered_wheel_scenario()
    return s.model_copy(update=dict(force_model=s.force_model.model_copy(update=dict(structural=structural))))


# --- psi from the rear surface drop ----------------------------------------------------------------
def test_psi_fits_recover_exact_laws():
    r, g = 0.106, 9.8
    w = np.array([10, 30, 60, 90]) * RPM
    x = r * w**2 / g
    assert fit_psi_linear(w, r * 0.52 * x, r, g) == pytest.approx(0.52, rel=1e-12)
    a, c = fit_psi_affine(w, r * (0.12 + 0.34 * x), r, g)
    assert (a, c) == pytest.approx((0.12, 0.34), rel=1e-10)
    assert fit_psi_linear(-w, r * 0.52 * x, r, g) == pytest.approx(0.52)  # the sign of omega does not matter


def test_psi_fits_reject_bad_input():
    w = np.array([1.0, 3.0, 6.0])
    with pytest.raises(ValueError, match="finite"):
        fit_psi_linear(w, [0.01, np.nan, 0.03], 0.1)
    with pytest.raises(ValueError, match="at least 2 distinct"):
        fit_psi_affine([3.0, 3.0], [0.01, 0.02], 0.1)
    with pytest.raises(ValueError, match="equal length"):
        fit_psi_linear(w, [0.01, 0.02], 0.1)
    with pytest.raises(ValueError, match="radius"):
        fit_psi_linear(w, [0.01, 0.02, 0.03], 0.0)


# --- the fitted free-surface law in the force model ------------------------------------------------
def test_psi_settings_reach_the_force_model_and_the_linear_law_is_compiled():
    s = _wheel("wheel-rear-half")
    assert s.build_model("drft").free_surface.psi is identity_psi  # the paper's law: unchanged path
    lin = with_parameters(s, {"psi": 0.5}).build_model("drft")
    assert lin.free_surface.psi == AffinePsi(0.5, 0.0) and lin.compiled_spec() is not None
    assert lin.free_surface.drop(6.0) == pytest.approx(0.5 * 0.106**2 * 36 / 9.8)
    aff = with_parameters(s, {"psi": 0.5, "psi_offset": 0.1}).build_model("drft")
    assert aff.compiled_spec() is not None  # an offset is compiled too (_traction.rear_surface_drop)
    assert aff.free_surface.drop(6.0) == pytest.approx(0.106 * (0.1 + 0.5 * 0.106 * 36 / 9.8))
    # the compiled linear and affine laws give the Python loop's steady state
    for params in ({"psi": 0.5}, {"psi": 0.5, "psi_offset": 0.1}):
        sc = with_parameters(s, params)
        fast, ref = run_steady(sc, "drft", 60.0), run_steady(sc, "drft", 60.0, compiled=False)
        assert fast.velocity == pytest.approx(ref.velocity, rel=1e-9) and fast.sinkage == pytest.approx(
            ref.sinkage, rel=1e-9
        )


def test_with_parameters_validates_and_copies():
    s = grousered_wheel_scenario()
    t = with_parameters(s, {"xi": 1.1, "lam": 2.0})
    assert parameter_values(t, ["xi", "lam", "psi"]) == {"xi": 1.1, "lam": 2.0, "psi": 1.0}
    assert s.force_model.xi == 0.35  # the original is untouched
    with pytest.raises(ValueError):
        with_parameters(s, {"xi": -1.0})
    with pytest.raises(ValueError, match="unknown DRFT parameter"):
        with_parameters(s, {"K": 1.0})


def test_mpm_push_is_the_runs_forward_force():
    assert with_mpm_push(grousered_wheel_scenario()).external_fx == pytest.approx(4.0)
    assert with_mpm_push(small_wheel_scenario()).external_fx == pytest.approx(0.5)


# --- recovery of known parameters from DRFT's own steady states -------------------------------------
@pytest.mark.parametrize("structural", ["wheel-rear-half-effective", "wheel-rear-half"])
def test_calibrate_recovers_known_xi_and_psi(structural):
    s = _wheel(structural)
    true = {"xi": 0.8, "psi": 0.6}
    ref = drft_steady_states(with_parameters(s, true), [20.0, 50.0, 80.0])
    res = calibrate(s, ref, ("xi", "psi"))  # starts from the paper's 0.35 and 1
    assert res.initial == {"xi": 0.35, "psi": 1.0}
    assert res.values["xi"] == pytest.approx(0.8, rel=0.02)
    assert res.values["psi"] == pytest.approx(0.6, rel=0.03)
    assert res.max_abs_rel_error < 0.005
    assert res.scenario.force_model.xi == res.values["xi"] and res.scenario.force_model.psi_slope == res.values["psi"]
    c = res.comparison
    assert len(c.rel_error_velocity) == 3 and len(c.residuals()) == 6
    assert c.max_abs_rel_error == max(np.max(np.abs(c.rel_error_velocity)), np.max(np.abs(c.rel_error_sinkage)))
    json.dumps(res.summary())  # JSON-ready


def test_calibrate_recovers_a_known_bulldozing_coefficient_and_leave_one_out_predicts_each_omega():
    s = with_mpm_push(_wheel("wheel-rear-half"))
    ref = drft_steady_states(with_parameters(s, {"bulldozing": 3.0}), [15.0, 30.0, 50.0])
    res = calibrate(s, ref, ("bulldozing",), starts=1)  # the paper has none (0): starts from Rankine's 1
    assert res.initial == {"bulldozing": 1.0}
    assert res.values["bulldozing"] == pytest.approx(3.0, rel=0.02)
    assert res.max_abs_rel_error < 0.01
    progress = []
    loo = leave_one_out(s, ref, ("bulldozing",), starts=1, progress=progress.append)
    assert len(progress) == 3 and "without 15 RPM" in progress[0]
    assert [v["bulldozing"] for v in loo.values] == pytest.approx([3.0] * 3, rel=0.03)
    assert list(loo.comparison.omega_rpm) == [15.0, 30.0, 50.0]
    assert loo.comparison.max_abs_rel_error < 0.02  # each omega predicted without it
    json.dumps(loo.summary())
    par = leave_one_out(s, ref, ("bulldozing",), starts=1, parallel=True, n_workers=2)  # a local Dask cluster
    assert par.values == loo.values
    assert np.array_equal(par.comparison.velocity_model, loo.comparison.velocity_model)
    assert np.array_equal(par.comparison.sinkage_model, loo.comparison.sinkage_model)
    with pytest.raises(ValueError, match="at least 3"):
        leave_one_out(s, _ref([10.0, 20.0], [0.05, 0.1], [0.04, 0.04]), ("bulldozing",))


def test_local_fits_on_dask_give_the_serial_result():
    s = with_mpm_push(_wheel("wheel-rear-half"))
    ref = drft_steady_states(with_parameters(s, {"bulldozing": 3.0}), [15.0, 50.0])
    ser = calibrate(s, ref, ("bulldozing",), starts=3, max_nfev=8)
    par = calibrate(s, ref, ("bulldozing",), starts=3, max_nfev=8, parallel=True, n_workers=2)
    assert par.values == ser.values and par.cost == ser.cost and par.nfev == ser.nfev
    assert par.meta == ser.meta and len(par.meta["local_fits"]) == 3
    assert np.array_equal(par.comparison.velocity_model, ser.comparison.velocity_model)


def test_paper_values_do_not_fit_a_stiffer_medium():
    s = _wheel()
    ref = drft_steady_states(with_parameters(s, {"xi": 0.8, "psi": 0.6}), [20.0, 80.0])
    c = compare(s, ref)
    assert c.max_abs_rel_error_sinkage > 0.3  # xi = 0.35 sinks far deeper than xi = 0.8


def test_failed_model_points_get_a_large_residual():
    c = compare(_wheel(), drft_steady_states(_wheel(), [20.0, 40.0]))
    broken = type(c)(c.name, c.omega_rpm, c.velocity_ref, c.sinkage_ref, np.array([np.nan, 1.0]), c.sinkage_model)
    assert broken.residuals()[0] == FAILED_RESIDUAL and math.isinf(broken.max_abs_rel_error_velocity)


# --- bad input ----------------------------------------------------------------------------------------
def _ref(rpm, v, s):
    recs = [{"omega_rpm": w, "ok": True, "velocity": a, "sinkage": b} for w, a, b in zip(rpm, v, s)]
    return SweepResult("grousered_wheel", "mpm", None, recs)


def test_calibrate_rejects_bad_input():
    s = _wheel()
    good = _ref([10.0, 30.0], [0.08, 0.2], [0.024, 0.027])
    with pytest.raises(ValueError, match="unknown DRFT parameter"):
        calibrate(s, good, ("xi", "kappa"))
    with pytest.raises(ValueError, match="distinct"):
        calibrate(s, good, ("xi", "xi"))
    with pytest.raises(ValueError, match="at least 2 omegas"):
        calibrate(s, _ref([10.0], [0.08], [0.024]), ("xi",))
    with pytest.raises(ValueError, match="NaN"):
        calibrate(s, _ref([10.0, 30.0], [0.08, math.nan], [0.024, 0.027]), ("xi",))
    with pytest.raises(ValueError, match="unknown"):
        calibrate(s, good, ("xi", "rho"))
    with pytest.raises(ValueError, match="low < high"):
        calibrate(s, good, ("xi",), bounds={"xi": (1.0, 0.5)})
    with pytest.raises(ValueError, match="not fitted"):
        calibrate(s, good, ("xi",), initial={"psi": 0.5})
    with pytest.raises(ValueError, match="non-zero"):
        calibrate(s, _ref([10.0, 30.0], [0.08, 0.2], [0.0, 0.027]), ("xi",))
    with pytest.raises(ValueError, match="starts"):
        calibrate(s, good, ("xi",), starts=0)


def test_calibrate_needs_as_many_residuals_as_parameters(monkeypatch):
    from intrusim.analysis import calibration

    # the four shipped parameters fit in the 4 residuals of 2 omegas: add a fifth
    monkeypatch.setitem(calibration.PARAMETERS, "rho", calibration.Parameter("rho", (100.0, 2000.0), "test only"))
    two = _ref([10.0, 30.0], [0.08, 0.2], [0.024, 0.027])
    with pytest.raises(ValueError, match="at least 5 residuals"):
        calibrate(_wheel(), two, ("xi", "psi", "psi_offset", "lam", "rho"))


def test_load_reference_keeps_finished_runs_sorted(tmp_path):
    recs = [
        {"omega_rpm": 90.0, "ok": True, "velocity": 0.33, "sinkage": 0.057, "surface_drop": 0.046},
        {"omega_rpm": 10.0, "ok": True, "velocity": 0.08, "sinkage": 0.024, "surface_drop": math.nan},
        {"omega_rpm": 50.0, "ok": False, "error": "IntegratorError: boom"},
    ]
    path = SweepResult("w", "mpm", None, recs).to_csv(tmp_path / "mpm.csv")
    ref = load_reference(path, "grousered_wheel")
    assert list(ref.omega_rpm) == [10.0, 90.0] and ref.scenario == "grousered_wheel"
    assert np.isnan(ref.column("surface_drop")[0]) and ref.column("velocity")[1] == 0.33
    with pytest.raises(ValueError, match="not found"):
        load_reference(tmp_path / "missing.csv")
    with pytest.raises(ValueError, match="settled"):  # no run says it settled
        load_reference(path, settled_only=True)


def test_load_reference_settled_only_drops_runs_still_digging_in(tmp_path):
    recs = [
        {"omega_rpm": 90.0, "ok": True, "velocity": 0.17, "sinkage": 0.10, "settled": False},
        {"omega_rpm": 10.0, "ok": True, "velocity": 0.06, "sinkage": 0.042, "settled": True},
        {"omega_rpm": 30.0, "ok": True, "velocity": 0.15, "sinkage": 0.045, "settled": True},
    ]
    path = SweepResult("w", "mpm", None, recs).to_csv(tmp_path / "mpm.csv")
    assert list(load_reference(path).omega_rpm) == [10.0, 30.0, 90.0]
    assert list(load_reference(path, settled_only=True).omega_rpm) == [10.0, 30.0]
    unsettled = SweepResult("w", "mpm", None, [dict(r, settled=False) for r in recs]).to_csv(tmp_path / "none.csv")
    with pytest.raises(ValueError, match="no finished \\(ok, settled\\) MPM run"):
        load_reference(unsettled, settled_only=True)


# --- command line -----------------------------------------------------------------------------------
def test_cli_calibrate_writes_json_csv_png(tmp_path):
    s = with_mpm_push(_wheel())
    ref = drft_steady_states(with_parameters(s, {"xi": 0.8, "psi": 0.6}), [20.0, 80.0])
    for r in ref.records:
        r["surface_drop"] = 0.106 * 0.5 * 0.106 * (r["omega_rpm"] * RPM) ** 2 / 9.8
    big = ref.to_csv(tmp_path / "wheel.csv")
    small = drft_steady_states(with_parameters(with_mpm_push(small_wheel_scenario()), {"xi": 0.8}), [30.0, 90.0])
    small_csv = small.to_csv(tmp_path / "small.csv")
    args = ["calibrate", "wheel", "--mpm", str(big), "--structural", "wheel-rear-half-effective", "--starts", "1",
            "--check", f"small_wheel={small_csv}", "--out", str(tmp_path / "out"), "--name", "cal"]  # fmt: skip
    r = CliRunner().invoke(app, args)
    assert r.exit_code == 0, r.output
    # the fitted values printed (their accuracy: the report's, below)
    assert (
        re.search(r"grousered_wheel: xi = 0\.\d{4}, psi = 0\.\d{4} \(", r.output) and "max |relative error|" in r.output
    )
    assert "check small_wheel (small_grousered_wheel, fitted values reused): 30 RPM v " in r.output
    out = tmp_path / "out"
    assert (out / "cal.png").stat().st_size > 1000
    for body in ("calibrated", "small_wheel"):  # one figure per body besides the whole
        assert (out / f"cal_{body}.png").stat().st_size > 1000
    small_rows = list(csv.DictReader((out / "cal_small_wheel_vs_mpm.csv").open()))
    assert {row["scenario"] for row in small_rows} == {"small_grousered_wheel"}
    assert {row["curve"] for row in small_rows} == {"DRFT before (small_wheel)", "DRFT calibrated (small_wheel)"}
    report = json.loads((out / "cal.json").read_text())
    assert report["calibration"]["values"]["xi"] == pytest.approx(0.8, rel=0.02)
    assert report["psi_from_surface_drop"]["linear_slope"] == pytest.approx(0.5)
    assert set(report["checks"]) == {"small_wheel"} and report["verdict"]["velocity_within_15pct"]
    rows = list(csv.DictReader((out / "cal_vs_mpm.csv").open()))
    assert {row["scenario"] for row in rows} == {"grousered_wheel", "small_grousered_wheel"}
    cal = [row for row in rows if row["curve"] == "DRFT calibrated" and row["scenario"] == "grousered_wheel"]
    assert [float(row["omega_rpm"]) for row in cal] == [20.0, 80.0]
    assert max(abs(float(row["rel_diff_velocity"])) for row in cal) < 0.005


def test_cli_calibrate_check_keeps_the_checked_scenarios_own_force_model(tmp_path):
    """A runner checked against a wheel's calibration keeps its lambda 4 and no structural
    correction; only the fitted values are put in (its MPM here: its own DRFT at the fitted xi)."""
    from intrusim.scenarios import four_flap_runner_scenario

    ref = drft_steady_states(with_parameters(with_mpm_push(_wheel("wheel-rear-half")), {"xi": 0.8}), [20.0, 80.0])
    runner = with_mpm_push(four_flap_runner_scenario())
    assert runner.force_model.lam == 4.0 and runner.force_model.structural == "none"
    runner_ref = drft_steady_states(with_parameters(runner, {"xi": 0.8}), [60.0, 150.0])
    args = ["calibrate", "wheel", "--mpm", str(ref.to_csv(tmp_path / "wheel.csv")), "--params", "xi", "--starts", "1",
            "--structural", "wheel-rear-half",  # the wheel's own, named: not put on the runner
            "--check", f"runner={runner_ref.to_csv(tmp_path / 'runner.csv')}", "--out", str(tmp_path), "--name", "cal"]  # fmt: skip
    r = CliRunner().invoke(app, args)
    assert r.exit_code == 0, r.output
    check = json.loads((tmp_path / "cal.json").read_text())["checks"]["runner"]["calibrated"]
    assert check["max_abs_rel_error_velocity"] < 0.005 and check["max_abs_rel_error_sinkage"] < 0.005


def test_cli_calibrate_leave_one_out(tmp_path):
    s = with_mpm_push(_wheel("wheel-rear-half"))
    ref = drft_steady_states(with_parameters(s, {"bulldozing": 2.0}), [15.0, 30.0, 50.0]).to_csv(tmp_path / "wheel.csv")
    args = ["calibrate", "wheel", "--mpm", str(ref), "--structural", "wheel-rear-half", "--params", "bulldozing", "--starts", "1",
            "--leave-one-out", "--out", str(tmp_path / "out"), "--name", "cal"]  # fmt: skip
    r = CliRunner().invoke(app, args)
    assert r.exit_code == 0, r.output
    assert "bulldozing = 2" in r.output and "fold 3/3: without 50 RPM" in r.output
    report = json.loads((tmp_path / "out" / "cal.json").read_text())
    assert report["command"]["leave_one_out"] is True
    held = report["leave_one_out"]["comparison"]
    assert held["omega_rpm"] == [15.0, 30.0, 50.0] and held["max_abs_rel_error_velocity"] < 0.02
    assert len(report["leave_one_out"]["fold_values"]) == 3


def test_cli_calibrate_params_none_runs_the_fixed_model_unfitted(tmp_path):
    """--params none --fix: the model with the given (measured) values against the MPM, nothing fitted;
    its own DRFT as the reference comes back within the integrator's reproducibility, on the checked body too."""
    s = with_mpm_push(_wheel("wheel-rear-half"))
    values = {"xi": 0.8, "lam": 2.6, "psi": 0.25, "psi_offset": 0.13}
    ref = drft_steady_states(with_parameters(s, values), [20.0, 80.0]).to_csv(tmp_path / "wheel.csv")
    small = drft_steady_states(with_parameters(with_mpm_push(small_wheel_scenario()), values), [30.0])
    args = ["calibrate", "wheel", "--mpm", str(ref), "--structural", "wheel-rear-half", "--params", "none",
            *[f"--fix={k}={v}" for k, v in values.items()], "--check", f"small-wheel={small.to_csv(tmp_path / 'small.csv')}",
            "--out", str(tmp_path / "out"), "--name", "m"]  # fmt: skip
    r = CliRunner().invoke(app, args)
    assert r.exit_code == 0, r.output
    assert "nothing fitted" in r.output
    report = json.loads((tmp_path / "out" / "m.json").read_text())
    assert report["command"]["fixed"] == values and report["calibration"]["values"] == {}
    assert report["calibration"]["max_abs_rel_error"] < 1e-9
    assert report["checks"]["small-wheel"]["calibrated"]["max_abs_rel_error_velocity"] < 1e-9
    model = json.loads((tmp_path / "out" / "m.model.json").read_text())["force_model"]
    assert {
        k: model[f] for k, f in (("xi", "xi"), ("lam", "lam"), ("psi", "psi_slope"), ("psi_offset", "psi_offset"))
    } == values
    # the same without --fix is another model: it misses
    r = CliRunner().invoke(app, args[: args.index("--params") + 2] + ["--out", str(tmp_path / "o2"), "--name", "m"])
    assert (
        r.exit_code == 0
        and json.loads((tmp_path / "o2" / "m.json").read_text())["calibration"]["max_abs_rel_error"] > 0.05
    )


@pytest.mark.parametrize(
    "extra, message",
    [
        (["--params", "none", "--leave-one-out"], "nothing is fitted"),
        (["--params", ","], "names no parameter"),
        (["--fix", "lam"], "NAME=VALUE"),
        (["--fix", "gamma=1"], "NAME=VALUE"),
        (["--fix", "lam=big"], "not a number"),
        (["--fix", "lam=nan"], "finite"),
        (["--fix", "lam=1", "--fix", "lam=2"], "given twice"),
        (["--params", "xi,lam", "--fix", "lam=2"], "also in --params"),
        (["--params", "none", "--fix", "psi=0.2", "--psi-from-dh", "affine"], "nor --fix them"),
        (["--params", "none", "--fix", "lam=-1"], "lam"),
    ],
)
def test_cli_calibrate_refuses_bad_params_and_fix(tmp_path, extra, message):
    ref = SweepResult(
        "w", "mpm", None, [{"omega_rpm": w, "ok": True, "velocity": 0.1, "sinkage": 0.05} for w in (30.0, 90.0)]
    )
    args = ["calibrate", "wheel", "--mpm", str(ref.to_csv(tmp_path / "w.csv")), "--out", str(tmp_path), *extra]
    r = CliRunner().invoke(app, args)
    assert r.exit_code == 2 and message in r.output, r.output
    assert not list(tmp_path.glob("*.json"))  # refused before anything is written


def test_cli_calibrate_bad_input_is_a_message(tmp_path):
    r = CliRunner().invoke(app, ["calibrate", "wheel", "--mpm", str(tmp_path / "none.csv")])
    assert r.exit_code == 2 and "not found" in r.output
    r = CliRunner().invoke(
        app, ["calibrate", "wheel", "--mpm", "x.csv", "--params", "xi,psi", "--psi-from-dh", "affine"]
    )
    assert r.exit_code == 2 and "do not fit psi" in r.output


def test_cli_calibrate_settled_only_without_settled_runs_is_a_message(tmp_path):
    recs = [{"omega_rpm": w, "ok": True, "velocity": 0.1, "sinkage": 0.05, "settled": False} for w in (30.0, 90.0)]
    path = SweepResult("w", "mpm", None, recs).to_csv(tmp_path / "mpm.csv")
    r = CliRunner().invoke(app, ["calibrate", "wheel", "--mpm", str(path), "--settled-only", "--out", str(tmp_path)])
    assert r.exit_code == 2 and "settled" in r.output and not list(tmp_path.glob("*.json"))


def test_a_single_omega_is_enough_to_compare_but_not_to_fit():
    s = with_mpm_push(_wheel("wheel-rear-half"))
    one = drft_steady_states(with_parameters(s, {"xi": 0.8}), [60.0])
    c = compare(with_parameters(s, {"xi": 0.8}), one)
    assert list(c.omega_rpm) == [60.0] and c.max_abs_rel_error_velocity < 1e-9
    with pytest.raises(ValueError, match="at least 2 omegas"):
        calibrate(s, one, ("xi",))


def test_cli_calibrate_checks_a_single_omega_and_refuses_a_bad_check_before_the_fit(tmp_path):
    s = with_mpm_push(_wheel("wheel-rear-half"))
    ref = drft_steady_states(with_parameters(s, {"xi": 0.8}), [20.0, 80.0]).to_csv(tmp_path / "wheel.csv")
    one = drft_steady_states(with_parameters(s, {"xi": 0.8}), [50.0]).to_csv(tmp_path / "one.csv")
    base = [
        "calibrate",
        "wheel",
        "--mpm",
        str(ref),
        "--params",
        "xi",
        "--starts",
        "1",
        "--structural",
        "wheel-rear-half",
    ]
    r = CliRunner().invoke(app, [*base, "--check", f"wheel={one}", "--out", str(tmp_path / "out"), "--name", "cal"])
    assert r.exit_code == 0, r.output
    assert "check wheel (grousered_wheel, fitted values reused): 50 RPM v " in r.output
    bad = SweepResult("w", "mpm", None, [{"omega_rpm": 50.0, "ok": True, "velocity": 0.3, "sinkage": 0.0}])
    r = CliRunner().invoke(
        app, [*base, "--check", f"wheel={bad.to_csv(tmp_path / 'bad.csv')}", "--out", str(tmp_path / "bad")]
    )
    assert r.exit_code == 2 and "--check wheel" in r.output and "non-zero" in r.output
    assert "xi = " not in r.output and not (tmp_path / "bad").exists()  # refused before the fit


def test_cli_calibrate_refuses_a_check_name_given_twice(tmp_path):
    """Two --check with one NAME would leave one comparison out of the output: refused before the fit."""
    s = with_mpm_push(_wheel("wheel-rear-half"))
    ref = drft_steady_states(with_parameters(s, {"xi": 0.8}), [20.0, 80.0]).to_csv(tmp_path / "wheel.csv")
    a = drft_steady_states(with_parameters(s, {"xi": 0.8}), [10.0]).to_csv(tmp_path / "a.csv")
    b = drft_steady_states(with_parameters(s, {"xi": 0.8}), [50.0]).to_csv(tmp_path / "b.csv")
    r = CliRunner().invoke(app, ["calibrate", "wheel", "--mpm", str(ref), "--params", "xi", "--starts", "1",
                                 "--check", f"wheel={a}", "--check", f"wheel={b}", "--out", str(tmp_path / "out")])  # fmt: skip
    assert r.exit_code == 2 and "--check wheel given twice" in r.output
    assert "xi = " not in r.output and not (tmp_path / "out").exists()
