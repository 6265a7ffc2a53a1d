"""A calibrated model as a file (analysis/model_file.py): `intrusim calibrate` writes it, `steady` and
`sweep --model FILE` run it; `calibrate` on a wheel TOML makes its own MPM references."""

import json
from importlib import resources

import pytest
from cli_helpers import refused, run

from intrusim._checks import InputError
from intrusim.analysis.calibration import drft_steady_states, with_mpm_push, with_parameters
from intrusim.analysis.model_file import ModelFile, read_model, resolve_model, write_model
from intrusim.analysis.steady import run_steady
from intrusim.scenarios import grousered_wheel_scenario, load_scenario, small_wheel_scenario

TEN_GROUSERS = 'body = "wheel"\nname = "ten_grousers"\nlug_count = 10\n'


def _model(**fm) -> ModelFile:
    s = grousered_wheel_scenario()
    return ModelFile(force_model=s.force_model.validated_copy(**fm), calibrated_on=s.name)


def test_a_model_drives_another_body_with_its_own_push_and_geometry():
    m = _model(xi=0.9, lam=2.0, psi_slope=0.4, bulldozing=1.5)
    small = small_wheel_scenario()
    s = m.apply(small)
    assert s.force_model == m.force_model
    assert s.hub_diameter == small.hub_diameter and s.lug_count == small.lug_count and s.name == small.name
    assert s.external_fx == with_mpm_push(small).external_fx != with_mpm_push(grousered_wheel_scenario()).external_fx
    no_push = m.model_copy(update=dict(mpm_push=False)).apply(small)
    assert no_push.external_fx == small.external_fx == 0.0


def test_a_runner_keeps_no_structural_correction_as_calibrate_checks_it():
    """The rear-half correction is a wheel's: a model calibrated with it drives a runner without it
    (as `calibrate --check runner=...` compares it), and the runner then runs at 10 and 20 RPM, where
    the wheel's zone on the runner's flaps left Newton without a root (IntegratorError)."""
    from intrusim.scenarios import four_flap_runner_scenario

    m = _model(xi=0.545, lam=0.09, psi_slope=0.60, psi_offset=0.31, structural="wheel-rear-half-effective")
    runner = m.apply(four_flap_runner_scenario())
    assert runner.force_model.structural == "none"
    assert runner.force_model == m.force_model.validated_copy(structural="none")
    assert m.apply(small_wheel_scenario()).force_model.structural == "wheel-rear-half-effective"
    for rpm in (10.0, 20.0):
        st = run_steady(runner, m.kind, rpm)
        assert 0.0 < st.velocity and 0.0 < st.sinkage


def test_a_model_file_round_trips_and_keeps_its_table_beside_it(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "tables").mkdir()
    src = resources.files("intrusim.data") / "rft_li2013.toml"
    (tmp_path / "tables" / "t.toml").write_bytes(src.read_bytes())
    m = _model(xi=1.2, rft_coefficients="tables/t.toml")
    path = write_model(tmp_path / "models" / "m.model.json", m)
    assert json.loads(path.read_text())["force_model"]["rft_coefficients"] == "../tables/t.toml"
    back = read_model(path)
    assert back.force_model.xi == 1.2 and back.kind == "drft" and back.mpm_push
    assert (tmp_path / back.force_model.rft_coefficients).resolve() == (tmp_path / "tables" / "t.toml").resolve()


def test_resolve_model_takes_a_kind_or_a_model_file(tmp_path):
    s = grousered_wheel_scenario()
    assert resolve_model("rft", s) == ("rft", s)
    path = write_model(tmp_path / "m.model.json", _model(xi=0.7).model_copy(update=dict(kind="drft-inertial")))
    kind, t = resolve_model(str(path), s)
    assert kind == "drft-inertial" and t.force_model.xi == 0.7
    with pytest.raises(InputError, match="must be one of rft, drft-inertial, drft or a model file"):
        resolve_model("drtf", s)
    with pytest.raises(InputError, match="not found"):
        resolve_model(str(tmp_path / "none.json"), s)


@pytest.mark.parametrize(
    "text, words",
    [
        ("{not json", ["invalid JSON"]),
        ('{"calibration": {}}', ["no intrusim_model entry"]),
        ('{"intrusim_model": 1, "kind": "drft"}', ["force_model"]),
        ('{"intrusim_model": 1, "force_model": {"xi": -1}}', ["xi"]),
        ('{"intrusim_model": 2, "force_model": {}}', ["intrusim_model"]),
        ('{"intrusim_model": 1, "force_model": {}, "colour": "red"}', ["colour"]),
    ],
)
def test_a_bad_model_file_is_refused_naming_what_is_wrong(tmp_path, text, words):
    p = tmp_path / "bad.model.json"
    p.write_text(text)
    refused(run("steady", "--model", p), str(p), *words)


def test_steady_and_sweep_run_a_model_file_and_refuse_it_with_another_table(tmp_path):
    path = write_model(tmp_path / "m.model.json", _model(xi=0.9))
    r = run("steady", "--scenario", "small-wheel", "--model", path, "--omega-rpm", 30)
    assert r.exit_code == 0, r.output
    assert f"drft of {path}" in r.output
    expected = run_steady(_model(xi=0.9).apply(small_wheel_scenario()), "drft", 30.0)
    assert f"{expected.velocity:8.4f} | {expected.sinkage * 1e3:10.2f}" in r.output
    r = run("sweep", "--scenario", "small-wheel", "--model", path, "--omega-rpm", "30,60", "--no-parallel")
    assert r.exit_code == 0, r.output
    assert f"{expected.velocity:8.4f} | {expected.sinkage * 1e3:10.2f}" in r.output
    table = resources.files("intrusim.data") / "rft_li2013.toml"
    refused(run("steady", "--model", path, "--rft-coefficients", table), "--rft-coefficients", "model file")


def test_calibrate_refuses_run_options_with_a_given_mpm_table(tmp_path):
    ref = drft_steady_states(with_parameters(with_mpm_push(grousered_wheel_scenario()), {"xi": 0.8}), [20.0, 80.0])
    csv = ref.to_csv(tmp_path / "w.csv")
    refused(run("calibrate", "wheel", "--mpm", csv, "--quick"), "not with --mpm")
    refused(run("calibrate", "wheel", "--mpm", csv, "--name", "a/b"), "--name")
    # a given table: the model file is written, and steady runs it to the calibrated curve
    r = run("calibrate", "wheel", "--mpm", csv, "--params", "xi", "--starts", "1", "--out", tmp_path, "--name", "cal")
    assert r.exit_code == 0, r.output
    m = read_model(tmp_path / "cal.model.json")
    assert m.force_model.xi == pytest.approx(0.8, rel=0.02) and m.fit["reference"] == str(csv)


def test_calibrate_a_wheel_nobody_simulated_end_to_end(tmp_path, monkeypatch):
    """A wheel TOML that is not a shipped scenario: calibrate makes its (quick) MPM runs, fits xi,
    writes the model file; steady on that file gives the calibrated DRFT at each omega."""
    monkeypatch.chdir(tmp_path)
    (tmp_path / "my_wheel.toml").write_text(TEN_GROUSERS)
    args = ["calibrate", "my_wheel.toml", "--quick", "--mpm-omegas", "30,90", "--params", "xi", "--starts", "1"]
    r = run(*args, "--out", "out")
    assert r.exit_code == 0, r.output
    assert (tmp_path / "out" / "mpm-runs" / "ten_grousers_30rpm" / "result.json").is_file()  # under --out
    assert not (tmp_path / "runs").exists() and not list((tmp_path / "out").rglob(".lock"))
    assert json.loads((tmp_path / "out" / "calibration_my_wheel.body.json").read_text())["lug_count"] == 10
    report = json.loads((tmp_path / "out" / "calibration_my_wheel.json").read_text())
    cmp = report["calibration"]["comparison"]
    assert cmp["scenario"] == "ten_grousers" and cmp["omega_rpm"] == [30.0, 90.0]
    m = read_model(tmp_path / "out" / "calibration_my_wheel.model.json")
    assert m.calibrated_on == "ten_grousers" and m.fit["params"]["xi"] == report["calibration"]["values"]["xi"]
    for i, w in enumerate((30.0, 90.0)):
        st = run_steady(m.apply(load_scenario("my_wheel.toml")), m.kind, w)
        assert st.velocity == pytest.approx(cmp["velocity_model_m_s"][i], rel=1e-9)
        assert st.sinkage == pytest.approx(cmp["sinkage_model_m"][i], rel=1e-9)
    # the runs are reused: a second calibration on them (--runs) makes none
    results = sorted((tmp_path / "out" / "mpm-runs").rglob("result.json"))
    stamps = [p.stat().st_mtime_ns for p in results]
    r = run(*args, "--runs", "out/mpm-runs", "--out", "again")
    assert r.exit_code == 0, r.output
    assert len(results) == 2 and [p.stat().st_mtime_ns for p in results] == stamps
    assert (tmp_path / "again" / "calibration_my_wheel_mpm.csv").read_text() == (
        tmp_path / "out" / "calibration_my_wheel_mpm.csv"
    ).read_text()
