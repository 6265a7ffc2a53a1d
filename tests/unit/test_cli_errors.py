"""Bad input and faults (issue 53): each is refused before compute with exit 2 and one line naming
the field and the value, or fails with exit 1 and a diagnosis (run folder kept), never a traceback,
a hang or NaN in the output. One test (or case) per numbered finding of the issue."""

import csv
import errno
import math
import os
import shutil
import warnings

import numpy as np
import pytest
from cli_helpers import block_config
from cli_helpers import refused as _refused
from cli_helpers import run as _run
from typer.testing import CliRunner

runner = CliRunner()

TINY = """
[domain]
size = [0.1, 0.1]
cells = [10, 10]
[bed]
rectangles = [{ x0 = 0.0, z0 = 0.0, x1 = 0.1, z1 = 0.05 }]
[time]
t_end = 0.02
[output]
record_every = 0.005
checkpoint_every = 0.01
[backend]
cpu_threads = 1
"""

BODY = block_config(t_end=0.01, z=0.065)  # a coupled block just above the bed


def _toml(tmp_path, text, name="c.toml"):
    path = tmp_path / name
    path.write_text(text)
    return path


def _replace(text, old, new):
    assert old in text, old
    return text.replace(old, new)


# ---------------------------------------------------------------- 1. hangs


def test_1_frames_every_negative_is_refused_not_looped_for_ever(tmp_path):
    _refused(_run("mpm", "steady", "--quick", "--out", tmp_path, "--set", "frames_every=-1"), "frames_every", "-1")
    _refused(_run("mpm", "steady", "--quick", "--out", tmp_path, "--set", "frames_every=0"), "frames_every")


def test_1_sweep_workers_below_one_or_above_the_cores_are_refused(tmp_path):
    _refused(_run("mpm", "sweep", "--quick", "--out", tmp_path, "--workers", "-1"), "--workers", "-1")
    _refused(_run("mpm", "sweep", "--quick", "--out", tmp_path, "--workers", "0"), "--workers")
    many = (os.cpu_count() or 1) + 1
    _refused(_run("mpm", "sweep", "--quick", "--out", tmp_path, "--workers", many), "--workers", str(many), "cores")
    _refused(
        _run("calibrate", "wheel", "--mpm", tmp_path / "x.csv", "--workers", many), "--workers", str(many), "cores"
    )


@pytest.mark.parametrize(
    "old,new",
    [
        ("omega = -1.0", "omega = 1e30"),  # dt ~ 1e-31 s
        ("t_end = 0.01", "t_end = 0.01\ncfl = 1e-12"),
        ("t_end = 0.01", "t_end = 0.01\ndt = 1e-15"),
    ],
)
def test_1_a_run_of_too_many_steps_is_refused_before_compute(tmp_path, old, new):
    line = _refused(_run("mpm", "run", _toml(tmp_path, _replace(BODY, old, new))), "time.max_steps", "steps")
    assert "--max-steps" in line


def test_1_the_step_limit_can_be_raised(tmp_path):
    cfg = _toml(tmp_path, _replace(TINY, "t_end = 0.02", "t_end = 0.02\nmax_steps = 100"))
    _refused(_run("mpm", "run", cfg), "time.max_steps = 100")
    r = _run("mpm", "run", cfg, "--max-steps", "1000")
    assert r.exit_code == 0, r.output


# ---------------------------------------------------------------- 2. NaN and inf


@pytest.mark.parametrize(
    "old,new,field",
    [
        ("width = 0.1", "width = inf", "intruders.0.width"),
        ("mass_z = 1.0", "mass_z = inf", "intruders.0.motion.mass_z"),
        ("omega = -1.0", "omega = nan", "intruders.0.motion.omega"),
        ("x = 0.1", "x = nan", "intruders.0.x"),
        ("mass_z = 1.0", "mass_z = 1.0\nexternal_force = [nan, 0.0]", "intruders.0.motion.external_force"),
        ("[0.02, 0.01], [-0.02", "[0.02, nan], [-0.02", "intruders.0.vertices"),
    ],
)
def test_2_nan_and_inf_in_a_body_are_refused_naming_the_field(tmp_path, old, new, field):
    _refused(_run("mpm", "run", _toml(tmp_path, _replace(BODY, old, new)), "--out", tmp_path / "run"), field)
    assert not (tmp_path / "run" / "timeseries.csv").exists()


def _light_body_on_the_bed() -> str:
    """BODY at 1e-6 kg/m, its lower face on the bed's surface (z = 0.05 m), so the contact acts at once."""
    return _replace(
        _replace(BODY, "mass_x = 1.0\nmass_z = 1.0", "mass_x = 1e-6\nmass_z = 1e-6"), "z = 0.065", "z = 0.06"
    )


def test_2_a_body_too_light_to_stay_in_the_box_stops_the_run_with_a_diagnosis(tmp_path):
    text = _light_body_on_the_bed()
    r = _run("mpm", "run", _toml(tmp_path, text), "--out", tmp_path / "run")
    assert r.exit_code == 1, r.output
    assert "Traceback" not in r.output and "body" in r.output
    assert (tmp_path / "run" / "checkpoint_failure.npz").exists()
    rows = (
        list(csv.DictReader((tmp_path / "run" / "timeseries.csv").open()))
        if (tmp_path / "run" / "timeseries.csv").exists()
        else []
    )
    assert all(math.isfinite(float(v)) for row in rows for v in row.values() if v)


def test_2_the_body_guard_sees_a_body_that_leaves_the_box():
    from types import SimpleNamespace

    from intrusim.mpm.diagnostics import body_report
    from intrusim.mpm.intruder import IntruderState

    square = SimpleNamespace(vertices=[[-0.01, -0.01], [0.01, -0.01], [0.01, 0.01], [-0.01, 0.01]])

    def body(**kw):
        return SimpleNamespace(state=IntruderState(**{"x": 0.1, "z": 0.05, "theta": 0.0, **kw}), contact=square)  # noqa: E731

    assert body_report([body()], 0.2, 0.1, 1e-4, 0.01) is None
    assert "left the box" in body_report([body(z=-575.0)], 0.2, 0.1, 1e-4, 0.01)  # mass 1e-6 ended there
    assert "NaN/inf" in body_report([body(vx=math.nan)], 0.2, 0.1, 1e-4, 0.01)
    assert "CFL" in body_report([body(vz=1e3)], 0.2, 0.1, 1e-4, 0.01)


# ---------------------------------------------------------------- 3. geometry


@pytest.mark.parametrize(
    "old,new,words",
    [
        ("z = 0.065", "z = 0.2", ("intruders.0.vertices", "above the top")),
        ("x = 0.1", "x = 0.5", ("intruders.0.vertices", "side wall")),
        ("z = 0.065", "z = 0.0", ("intruders.0.vertices", "floor")),
        (
            "[[-0.02, -0.01], [0.02, -0.01], [0.02, 0.01], [-0.02, 0.01]]",
            "[[-0.02, -0.01], [0.02, 0.01], [0.02, -0.01], [-0.02, 0.005]]",
            ("intruders.0.vertices", "not a simple polygon"),
        ),
        (
            "[[-0.02, -0.01], [0.02, -0.01], [0.02, 0.01], [-0.02, 0.01]]",
            "[[-0.02, -0.01], [0.0, 0.0], [0.02, 0.01]]",
            ("intruders.0.vertices", "zero area"),
        ),
        (
            "[[-0.02, -0.01], [0.02, -0.01], [0.02, 0.01], [-0.02, 0.01]]",
            "[[0.01, 0.01], [0.01, 0.01], [0.01, 0.01]]",
            ("intruders.0.vertices", "zero area"),
        ),
        (
            "[[intruders]]",
            "[[obstacles]]\nvertices = [[0.0, 0.0], [0.01, 0.0], [0.01, nan]]\n[[intruders]]",
            ("obstacles.0.vertices",),
        ),
        (
            "[[intruders]]",
            "[[obstacles]]\nvertices = [[0.15, 0.0], [0.25, 0.0], [0.25, 0.02]]\n[[intruders]]",
            ("obstacles.0.vertices", "side wall"),
        ),
        (
            "rectangles",
            "polygons = [[[0.0, 0.0], [0.5, 0.0], [0.5, 0.05]]]\nrectangles",
            ("bed.polygons.0", "side wall"),
        ),
    ],
)
def test_3_bad_geometry_is_refused_naming_the_polygon(tmp_path, old, new, words):
    _refused(_run("mpm", "run", _toml(tmp_path, _replace(BODY, old, new))), *words)


def test_3_an_infinite_contact_band_is_refused():
    _refused(_run("mpm", "steady", "--quick", "--set", "contact_band=inf"), "contact_band", "inf")
    _refused(_run("mpm", "steady", "--quick", "--set", "contact_band=nan"), "contact_band")


# ---------------------------------------------------------------- 4. run folders


def test_4_a_checkpoint_is_never_written_from_a_broken_state(tmp_path):
    from intrusim.mpm import io as mpm_io
    from intrusim.mpm.config import MPMConfig
    from intrusim.mpm.diagnostics import SimulationError
    from intrusim.mpm.solver import Solver

    with pytest.raises(SimulationError, match="NaN/inf in x"):
        mpm_io.save_checkpoint(tmp_path / "c.npz", {"x": np.array([[0.0, math.nan]])}, {"step_count": 1})
    assert not (tmp_path / "c.npz").exists() and not list(tmp_path.glob("*.tmp"))
    cfg = MPMConfig.model_validate(
        {**__import__("tomllib").loads(TINY), "output": {"directory": str(tmp_path / "run"), "record_every": 0.005}}
    )
    s = Solver(cfg)
    s.run(t_end=0.005)
    d = s.particles.to_numpy()
    d["v"][3] = math.nan
    s.particles.load(d)
    with pytest.raises(SimulationError):
        s.checkpoint_run_folder()
    assert not (tmp_path / "run" / "checkpoint.npz").exists()
    with pytest.raises(SimulationError, match="NaN"):  # the guard keeps the broken state apart, for the diagnosis
        s.check_guards()
    assert (tmp_path / "run" / "checkpoint_failure.npz").exists()


def test_4_resume_refuses_an_mpm_steady_folder_and_leaves_its_result(tmp_path):
    out = tmp_path / "run"
    assert _run("mpm", "run", _toml(tmp_path, TINY), "--out", out).exit_code == 0
    (out / "locomotion.json").write_text("{}")
    (out / "result.json").write_text('{"velocity": 1.0}')
    before = {p.name: p.read_bytes() for p in out.iterdir() if p.is_file()}
    _refused(_run("mpm", "resume", out, "--t-end", "0.03"), "mpm steady", "--set t_max")
    assert {p.name: p.read_bytes() for p in out.iterdir() if p.is_file()} == before


def test_4_a_checkpoint_of_another_configuration_is_not_loaded(tmp_path):
    a, b = tmp_path / "a", tmp_path / "b"
    assert _run("mpm", "run", _toml(tmp_path, TINY), "--out", a).exit_code == 0
    other = _replace(TINY, "[time]", "[material]\nmu_s = 0.3\n[time]")  # same dt, other grains
    assert _run("mpm", "run", _toml(tmp_path, other, "b.toml"), "--out", b).exit_code == 0
    shutil.copy(a / "checkpoint.npz", b / "checkpoint.npz")
    _refused(_run("mpm", "resume", b), "checkpoint of another configuration", "material.mu_s")


def test_4_a_scenario_name_cannot_write_outside_out(tmp_path):
    toml = _toml(tmp_path, 'body = "wheel"\nname = "../../escaped"\n', "w.toml")
    out = tmp_path / "a" / "b"
    _refused(_run("mpm", "steady", "--scenario", toml, "--quick", "--out", out), "not a plain file name")
    _refused(_run("mpm", "sweep", "--scenario", toml, "--quick", "--serial", "--out", out), "not a plain file name")
    assert not list(tmp_path.rglob("escaped*"))


def test_4_two_runs_on_one_folder_the_second_is_refused(tmp_path):
    from intrusim.mpm.io import run_lock

    out = tmp_path / "run"
    with run_lock(out):
        _refused(_run("mpm", "run", _toml(tmp_path, TINY), "--out", out), "in use by another run")
    assert _run("mpm", "run", _toml(tmp_path, TINY), "--out", out).exit_code == 0


def test_4_files_get_ordinary_modes_and_no_partial_file_is_left_by_a_full_disk(tmp_path, monkeypatch):
    from intrusim.mpm import io as mpm_io

    old = os.umask(0o022)
    try:
        mpm_io.atomic_write_bytes(tmp_path / "a.json", b"{}")
        assert (tmp_path / "a.json").stat().st_mode & 0o777 == 0o644
    finally:
        os.umask(old)

    import meshio

    def full_disk(path, *args, **kwargs):
        with open(path, "wb") as fh:
            fh.write(b"<VTKFile half")
        raise OSError(errno.ENOSPC, "No space left on device")

    monkeypatch.setattr(meshio, "write", full_disk)
    with pytest.raises(OSError):
        mpm_io.write_vtk(tmp_path / "p.vtu", {"x": np.zeros((3, 2)), "v": np.zeros((3, 2))})
    assert not (tmp_path / "p.vtu").exists() and not list(tmp_path.glob("*.tmp"))


def test_4_a_full_disk_during_a_run_is_one_line_and_exit_1(tmp_path, monkeypatch):
    from intrusim.mpm import io as mpm_io

    def full_disk(*args, **kwargs):
        raise OSError(errno.ENOSPC, "No space left on device")

    monkeypatch.setattr(mpm_io, "write_csv", full_disk)
    r = _run("mpm", "run", _toml(tmp_path, TINY), "--out", tmp_path / "run")
    assert r.exit_code == 1 and "No space left on device" in r.output and "Traceback" not in r.output


# ---------------------------------------------------------------- 5. one-line errors, exit codes


@pytest.mark.parametrize(
    "old,new,field",
    [
        ("[time]", "[material]\nyoungs_modulus = inf\n[time]", "material.youngs_modulus"),
        ("t_end = 0.01", "t_end = inf", "time.t_end"),
        ("omega = -1.0", "omega = inf", "intruders.0.motion.omega"),
        ("record_every = 0.0025", "record_every = inf", "output.record_every"),
        ("record_every = 0.0025", "record_every = 0.0025\nsnapshot_every = inf", "output.snapshot_every"),
        ("t_end = 0.01", "t_end = 0.01\nv_max_expected = inf", "time.v_max_expected"),
        ("t_end = 0.01", "t_end = true", "t_end"),
    ],
)
def test_5_bad_numbers_in_a_file_are_one_line_and_exit_2(tmp_path, old, new, field):
    _refused(_run("mpm", "run", _toml(tmp_path, _replace(BODY, old, new))), field)


@pytest.mark.parametrize(
    "args,words",
    [
        (["sweep", "--omega-rpm", "10:90:0", "--no-parallel"], ("omega range",)),
        (["sweep", "--omega-rpm", "10:20:1e-9", "--no-parallel"], ("omega range", "points")),
        (["forces", "--slip", "nan"], ("--slip", "nan")),
        (["forces", "--sinkage-mm", "5,inf"], ("--sinkage-mm",)),
        (["mpm", "collect", ".", "--from", "nan"], ("--from", "nan")),
        (["mpm", "steady", "--quick", "--set", "cell_size=1e-9"], ("domain.cells", "cells")),
    ],
)
def test_5_bad_flags_are_one_line_and_exit_2(args, words):
    _refused(_run(*args), *words)


@pytest.fixture(scope="module")
def finished_run(tmp_path_factory):
    folder = tmp_path_factory.mktemp("finished")
    (folder / "tiny.toml").write_text(TINY)
    r = _run("mpm", "run", folder / "tiny.toml", "--out", folder / "run")
    assert r.exit_code == 0, r.output
    return folder / "run"


@pytest.mark.parametrize("t_end", ["nan", "-1", "inf", "0"])
def test_5_resume_with_a_bad_end_time_is_refused(finished_run, t_end):
    _refused(_run("mpm", "resume", finished_run, "--t-end", t_end), "--t-end", t_end)


def test_5_corrupt_run_folders_and_config_files_are_one_line_and_exit_2(tmp_path, finished_run):
    bad = tmp_path / "bad"
    shutil.copytree(finished_run, bad)
    (bad / "checkpoint.npz").write_bytes(b"PK\x03\x04 not a zip")
    _refused(_run("mpm", "resume", bad), "not a readable checkpoint")
    (bad / "config.json").write_text('{"config": {')
    _refused(_run("mpm", "resume", bad), "unreadable input")
    _refused(_run("mpm", "run", tmp_path), "is not a file")
    (tmp_path / "binary.toml").write_bytes(bytes(range(256)))
    _refused(_run("mpm", "run", tmp_path / "binary.toml"), "not a text (TOML) file")
    (tmp_path / "a_file").write_text("x")
    _refused(_run("mpm", "run", _toml(tmp_path, TINY), "--out", tmp_path / "a_file"), "a_file")
    _refused(_run("mpm", "steady", "--quick", "--out", tmp_path / "a_file"), "a_file")


@pytest.mark.skipif(os.geteuid() == 0, reason="root writes into read-only folders")
def test_5_a_read_only_folder_is_one_line_and_exit_2(tmp_path):
    ro = tmp_path / "ro"
    ro.mkdir()
    ro.chmod(0o555)
    try:
        _refused(_run("mpm", "run", _toml(tmp_path, TINY), "--out", ro / "run"), "ermission")
    finally:
        ro.chmod(0o755)


def test_5_calibrate_refuses_duplicate_omegas_before_the_fit(tmp_path):
    csv_path = tmp_path / "mpm.csv"
    csv_path.write_text("omega_rpm,ok,velocity,sinkage\n30,True,0.3,0.01\n30,True,0.31,0.011\n60,True,0.5,0.02\n")
    _refused(_run("calibrate", "wheel", "--mpm", csv_path, "--out", tmp_path), "omega_rpm 30", "more than once")


def test_5_debug_shows_the_traceback_and_an_internal_error_is_one_line(monkeypatch):
    import intrusim.cli as cli

    def broken(*args, **kwargs):
        raise KeyError("a bug")

    monkeypatch.setattr(cli, "make_force_model", broken)
    r = _run("forces")
    assert r.exit_code == 1 and "internal error KeyError" in r.output and "--debug" in r.output
    r = _run("--debug", "forces")
    assert isinstance(r.exception, KeyError)


def test_5_version():
    from intrusim import __version__

    r = _run("--version")
    assert r.exit_code == 0 and r.output.strip() == f"intrusim {__version__}"


# ---------------------------------------------------------------- 6. sweeps


def test_6_mpm_sweep_exits_1_when_its_points_failed(tmp_path, monkeypatch):
    # omegas no run can take are refused before any point runs (exit 2, no CSV) ...
    _refused(_run("mpm", "sweep", "--quick", "--serial", "--omega-rpm", "-10,-20", "--out", tmp_path), "omega_rpm")
    assert not (tmp_path / "grousered_wheel_mpm_sweep.csv").exists()
    # ... points that fail as they run (here: a guard stops each run) are failed rows, exit 1
    import intrusim.scenarios.mpm_locomotion as loco
    from intrusim.mpm.diagnostics import SimulationError

    def stopped(*args, **kwargs):
        raise SimulationError("a guard stopped the run")

    monkeypatch.setattr(loco, "run_mpm_steady", stopped)
    r = _run("mpm", "sweep", "--quick", "--serial", "--omega-rpm", "10,20", "--out", tmp_path)
    assert r.exit_code == 1, r.output
    assert "2 of 2 points failed" in r.output and (tmp_path / "grousered_wheel_mpm_sweep.csv").exists()


def test_6_a_programming_error_is_raised_not_made_a_data_row():
    from intrusim.analysis.sweep import sweep_point
    from intrusim.errors import InputError

    class Scenario:
        def __init__(self, err):
            self.err = err

        def run_steady(self, kind, omega_rpm, lam):
            raise self.err

    rec = sweep_point(Scenario(InputError("omega_rpm must be > 0")), "mpm", 10.0, None)
    assert rec["ok"] is False and "omega_rpm must be > 0" in rec["error"]
    with pytest.raises(AttributeError):
        sweep_point(Scenario(AttributeError("'NoneType' object has no attribute 'x'")), "mpm", 10.0, None)


def test_6_stale_temporary_files_of_a_killed_writer_are_removed(tmp_path):
    from intrusim.mpm.io import run_lock

    run = tmp_path / "run"
    (run / "snapshots").mkdir(parents=True)
    for stale in (run / "checkpoint.npz.abc.tmp", run / "snapshots" / "particles_00000010.vtu.x.tmp"):
        stale.write_bytes(b"partial")
    with run_lock(run):
        assert not list(run.rglob("*.tmp"))


# ---------------------------------------------------------------- 7. progress


def test_7_the_progress_bar_ends_cleanly_and_an_error_has_its_own_line(tmp_path):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        r = _run("mpm", "run", _toml(tmp_path, TINY), "--out", tmp_path / "run")
    assert r.exit_code == 0, r.output
    assert not [w for w in caught if "clamping frac" in str(w.message)]
    assert "-00:00" not in r.output and "0.020/0.020 s" in r.output
    text = _light_body_on_the_bed()
    r = _run("mpm", "run", _toml(tmp_path, text))
    assert r.exit_code == 1
    assert any(
        line.startswith("error: body escape") or line.startswith("error: body CFL") or line.startswith("error: NaN")
        for line in r.output.splitlines()
    ), r.output
