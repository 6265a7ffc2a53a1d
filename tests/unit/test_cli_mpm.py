"""CLI: `intrusim mpm run CONFIG.toml` and `intrusim mpm resume RUN_DIR`."""

import json
import re

import numpy as np
import pytest
from cli_helpers import tiny_config
from typer.testing import CliRunner

from intrusim.cli import app
from intrusim.mpm.io import read_timeseries

runner = CliRunner()

TINY = tiny_config(0.02)


def _times(run_dir):
    return read_timeseries(run_dir / "timeseries.csv")["time"].tolist()


def test_run_writes_a_run_folder_and_resume_extends_it(tmp_path):
    cfg = tmp_path / "tiny.toml"
    cfg.write_text(TINY)
    out = tmp_path / "run"
    r = runner.invoke(app, ["mpm", "run", str(cfg), "--out", str(out)])
    assert r.exit_code == 0, r.output
    assert "done: t = 0.02 s" in r.output
    assert (out / "config.json").exists() and (out / "checkpoint.npz").exists()
    assert max(_times(out)) > 0.019
    r = runner.invoke(app, ["mpm", "resume", str(out), "--t-end", "0.03"])
    assert r.exit_code == 0, r.output
    assert "resuming" in r.output and max(_times(out)) > 0.029


def test_run_on_its_own_folder_goes_on_a_later_end_extends_it_and_another_config_is_refused(tmp_path):
    """`mpm run` on a folder of the same configuration continues from its checkpoint (the end state
    of a finished run); a later t_end extends it to that time, as one uninterrupted run would; a
    folder of another configuration is refused (exit 2) with its files left as they were."""
    cfg = tmp_path / "tiny.toml"
    cfg.write_text(TINY)
    out = tmp_path / "run"
    assert runner.invoke(app, ["mpm", "run", str(cfg), "--out", str(out)]).exit_code == 0
    longer = tmp_path / "longer.toml"
    longer.write_text(TINY.replace("t_end = 0.02", "t_end = 0.035"))
    r = runner.invoke(app, ["mpm", "run", str(longer), "--out", str(out)])
    assert r.exit_code == 0, r.output
    assert "continuing" in r.output and "t = 0.02 s" in r.output  # from the end of the first run
    whole = tmp_path / "whole"
    assert runner.invoke(app, ["mpm", "run", str(longer), "--out", str(whole)]).exit_code == 0
    assert _times(out) == _times(whole)
    extended, uninterrupted = read_timeseries(out), read_timeseries(whole)
    for key in ("kinetic_energy", "grain_mass"):
        assert extended[key].tolist() == uninterrupted[key].tolist()
    assert json.loads((out / "config.json").read_text())["config"]["time"]["t_end"] == 0.035
    before = {q.name: q.read_bytes() for q in out.iterdir() if q.is_file()}
    for text, key in (
        (TINY.replace("cells = [10, 10]", "cells = [20, 20]"), "domain.cells"),
        (TINY.replace("t_end = 0.02", "t_end = 0.01"), "time.t_end"),
    ):
        other = tmp_path / "other.toml"
        other.write_text(text)
        r = runner.invoke(app, ["mpm", "run", str(other), "--out", str(out)])
        assert r.exit_code == 2 and f"differs in {key}" in r.output, r.output
    assert "not cut short" in r.output
    assert {q.name: q.read_bytes() for q in out.iterdir() if q.is_file()} == before


def test_resume_writes_to_the_folder_it_is_given_after_a_move(tmp_path):
    cfg = tmp_path / "tiny.toml"
    cfg.write_text(TINY)
    first = tmp_path / "first"
    assert runner.invoke(app, ["mpm", "run", str(cfg), "--out", str(first)]).exit_code == 0
    moved = tmp_path / "moved"
    first.rename(moved)
    r = runner.invoke(app, ["mpm", "resume", str(moved), "--t-end", "0.03"])
    assert r.exit_code == 0, r.output
    assert not first.exists() and max(_times(moved)) > 0.029


def test_bad_config_fails_before_compute_with_the_field_named(tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text(TINY.replace("cells = [10, 10]", "cells = [10, 10]\nbogus = 3"))
    r = runner.invoke(app, ["mpm", "run", str(bad)])
    assert r.exit_code == 2 and "bogus" in r.output
    r = runner.invoke(app, ["mpm", "run", str(tmp_path / "missing.toml")])
    assert r.exit_code == 2 and "no such file" in r.output
    r = runner.invoke(app, ["mpm", "resume", str(tmp_path)])
    assert r.exit_code == 2 and "not a run folder" in r.output


def _quick(*sets, scenario="wheel", quick=True):
    from intrusim.cli_mpm import _case

    return _case(scenario, quick, None, None, list(sets))


def _set(*sets):
    return [a for s in sets for a in ("--set", s)]


def test_contact_band_reaches_the_solver_config_and_a_negative_one_is_refused():
    from intrusim.scenarios.mpm_locomotion import mpm_config

    case = _quick("contact_band=0.5")
    assert mpm_config(case.scenario, case.mpm, 30.0).contact_band_cells == 0.5
    assert mpm_config(case.scenario, _quick().mpm, 30.0).contact_band_cells == 1.0
    r = runner.invoke(app, ["mpm", "steady", "--quick", *_set("contact_band=-1")])
    assert r.exit_code == 2 and "contact_band must be >= 0" in r.output


def test_flip_reaches_the_solver_config_and_a_share_outside_0_1_is_refused():
    from intrusim.scenarios.mpm_locomotion import mpm_config

    case = _quick("flip=1.0")
    assert mpm_config(case.scenario, case.mpm, 30.0).transfer.flip == 1.0
    assert mpm_config(case.scenario, _quick().mpm, 30.0).transfer.flip is None  # the default
    for cmd in ("steady", "sweep"):
        r = runner.invoke(app, ["mpm", cmd, "--quick", *_set("flip=1.5")])
        assert r.exit_code == 2 and "flip: Input should be less than or equal to 1 (got 1.5)" in r.output


def test_shape_reaches_the_solver_config_and_an_unknown_one_is_refused():
    from intrusim.scenarios.mpm_locomotion import mpm_config

    case = _quick("flip=1", "shape=linear")
    assert mpm_config(case.scenario, case.mpm, 30.0).transfer.shape == "linear"
    assert mpm_config(case.scenario, _quick().mpm, 30.0).transfer.shape == "quadratic"
    for cmd in ("steady", "sweep"):
        r = runner.invoke(app, ["mpm", cmd, "--quick", *_set("shape=cubic")])
        assert r.exit_code == 2 and "shape: Input should be 'quadratic' or 'linear' (got 'cubic')" in r.output


def test_drop_escaped_reaches_the_solver_config():
    from intrusim.scenarios.mpm_locomotion import mpm_config

    case = _quick("drop_escaped=true")
    assert mpm_config(case.scenario, case.mpm, 30.0).output.escaped == "drop"
    assert mpm_config(case.scenario, _quick().mpm, 30.0).output.escaped == "stop"


def test_bed_length_keeps_the_cell_size_and_a_too_short_bed_is_refused():
    full = _quick(scenario="runner", quick=False)
    short = _quick("cell_size=0.0025", "length=1.0", scenario="runner", quick=False)
    assert full.mpm.domain[0] == 4.0 and short.mpm.domain == (1.0, full.mpm.domain[1])
    assert short.mpm.h == pytest.approx(0.0025) and short.mpm.cells == (400, round(full.mpm.domain[1] / 0.0025))
    # the same case with the keys in the other order
    assert _quick("length=1.0", "cell_size=0.0025", scenario="runner", quick=False).mpm == short.mpm
    r = runner.invoke(app, ["mpm", "steady", "--scenario", "runner", *_set("length=0.1")])
    assert r.exit_code == 2 and "length must exceed" in r.output


def test_t_max_reaches_the_run_settings_and_one_inside_the_settling_time_is_refused():
    assert _quick("t_max=3.0").mpm.t_max == 3.0
    r = runner.invoke(app, ["mpm", "steady", "--quick", *_set("t_max=0.5")])
    assert r.exit_code == 2 and "t_max must exceed ramp_time + settle_time" in r.output


def test_mu_i_and_fluidity_reach_the_material_and_bad_diameters_are_refused():
    from intrusim.scenarios.mpm_locomotion import mpm_config

    case = _quick("mu_i_diameter=2e-3")
    material = mpm_config(case.scenario, case.mpm, 30.0).material
    assert material.mu_i.grain_diameter == 2e-3 and material.mu_i.grain_density == 1100.0
    assert mpm_config(case.scenario, _quick().mpm, 30.0).material.mu_i is None
    assert _quick("mu_i.grain_diameter=2e-3").mpm == case.mpm  # the dotted key of the field itself
    r = runner.invoke(app, ["mpm", "steady", "--quick", *_set("mu_i_diameter=0")])
    assert r.exit_code == 2 and "mu_i_diameter must be > 0" in r.output
    case = _quick("fluidity_diameter=1e-3")
    assert mpm_config(case.scenario, case.mpm, 30.0).material.fluidity.grain_diameter == 1e-3
    r = runner.invoke(app, ["mpm", "steady", "--quick", *_set("fluidity_diameter=-1")])
    assert r.exit_code == 2 and "fluidity_diameter must be > 0" in r.output
    r = runner.invoke(app, ["mpm", "steady", "--quick", *_set("fluidity_diameter=1e-3", "mu_i_diameter=1e-3")])
    assert r.exit_code == 2 and "not both" in r.output


def test_treadmill_reaches_the_run_settings_and_a_bad_one_is_refused_before_compute(tmp_path):
    assert _quick("treadmill=[0.5, 0.35]").mpm.treadmill == (0.5, 0.35)
    assert _quick().mpm.treadmill is None
    for bad, reason in (
        ("0.5", "treadmill: Input should be a valid tuple"),
        ("[0.5]", "treadmill.1: Field required"),
        ("0.5,x", "treadmill: Input should be a valid tuple"),
        ("[0.35, 0.5]", "x_target < x_trigger"),
        ("[0.1, 0.05]", "ahead of start_x"),
    ):
        r = runner.invoke(app, ["mpm", "steady", "--quick", *_set(f"treadmill={bad}"), "--out", str(tmp_path / "t")])
        assert r.exit_code == 2 and reason in r.output, (bad, r.output)
    assert not any((tmp_path / "t").rglob("*.csv"))  # nothing ran
    # a 0.6 m bed stops the wheel at t = 1.09 s (its front 8 cm from the wall, centre at 0.41 m);
    # on the treadmill it runs to t_max and travels past the bed's end (measured with the contact
    # "surface": with "nodes" the 2 cm cells barely resolve the grousers and the wheel slips more)
    sets = _set("length=0.6", "t_max=1.6", "treadmill=[0.3, 0.2]", "contact=surface")
    r = runner.invoke(app, ["mpm", "steady", "--quick", *sets])
    assert r.exit_code == 0, r.output
    assert "over t = 0.60-1.59 s" in r.output  # the quick run drifts: "NOT settled: averages over ..."
    assert float(re.findall(r"  x = ([0-9.]+) m ", r.output)[-1]) > 0.45


def test_steady_marks_its_folder_finished_and_refuses_another_configuration_on_it(tmp_path):
    """`mpm steady --out` writes result.json (a sweep on that folder reuses the run); the same
    folder with another configuration is refused (exit 2) and the finished run is left as it was."""
    r = runner.invoke(app, ["mpm", "steady", "--quick", "--omega-rpm", "60", "--out", str(tmp_path), "--threads", "1"])
    assert r.exit_code == 0, r.output
    run_dir = tmp_path / "grousered_wheel_60rpm"
    assert (run_dir / "result.json").exists()
    before = {p.name: p.read_bytes() for p in run_dir.iterdir()}
    r = runner.invoke(
        app, ["mpm", "steady", "--quick", "--omega-rpm", "60", "--out", str(tmp_path), "--set", "contact_band=0"]
    )
    assert r.exit_code == 2 and "another configuration (differs in contact, contact_band_cells)" in r.output.replace(
        "\n", " "
    )
    assert {p.name: p.read_bytes() for p in run_dir.iterdir()} == before
    # `mpm collect` gathers the finished run into the sweep CSV that reproduce/calibrate read
    from intrusim.analysis.sweep import SweepResult

    r = runner.invoke(app, ["mpm", "collect", str(tmp_path)])
    assert r.exit_code == 0, r.output
    res = SweepResult.from_csv(tmp_path / "grousered_wheel_mpm_sweep.csv")
    done = json.loads((run_dir / "result.json").read_text())
    assert res.omega_rpm.tolist() == [60.0] and res.column("velocity")[0] == pytest.approx(done["velocity"])
    from intrusim.scenarios.mpm_settings import read_record

    recorded = json.loads((run_dir / "locomotion.json").read_text())["settings"]
    assert read_record(tmp_path / "grousered_wheel_mpm_sweep.csv") == {60.0: recorded}  # what reproduce checks
    assert res.column("window_start")[0] == pytest.approx(done["window"][0])
    # a later window (a run that settled late): averages from --from on, dh from the run's own per-chunk drops
    late = tmp_path / "late.csv"
    r = runner.invoke(app, ["mpm", "collect", str(tmp_path), "--from", "0.9", "--out", str(late)])
    assert r.exit_code == 0, r.output
    rec = SweepResult.from_csv(late).records[0]
    ts = read_timeseries(run_dir / "timeseries.csv")
    vx = ts["vx"][ts["time"] > 0.9].tolist()
    assert rec["window_start"] > 0.9 and rec["velocity"] == pytest.approx(sum(vx) / len(vx), rel=1e-12)
    drops = [
        d for t, d in json.loads((run_dir / "progress.json").read_text())["drops"] if t > 0.9 and d == d
    ]  # measured ones
    assert rec["surface_drop"] == pytest.approx(sum(drops) / len(drops), rel=1e-12)
    # --last: each run over its own last seconds (here the same window as --from 0.9)
    r = runner.invoke(
        app, ["mpm", "collect", str(tmp_path), "--last", str(done["window"][1] - 0.9), "--out", str(late)]
    )
    assert r.exit_code == 0, r.output
    assert SweepResult.from_csv(late).records[0]["velocity"] == pytest.approx(rec["velocity"], rel=1e-12)
    for bad in (["--last", "0"], ["--last", "0.2", "--from", "0.9"]):
        r = runner.invoke(app, ["mpm", "collect", str(tmp_path), *bad, "--out", str(late)])
        assert r.exit_code == 2 and "--last must be > 0" in r.output
    r = runner.invoke(app, ["mpm", "collect", str(tmp_path), "--from", "5", "--out", str(late)])
    assert r.exit_code == 2 and "before the averaging window starts" in r.output
    r = runner.invoke(app, ["mpm", "collect", str(tmp_path / "empty")])
    assert r.exit_code == 2 and "needs finished run folders" in r.output


def test_a_scenario_toml_runs_in_mpm_as_in_drft(tmp_path):
    """`mpm steady --scenario FILE.toml` runs the user's own wheel (here half the weight), the file
    `intrusim steady` takes; a missing file is refused before any compute."""
    toml = tmp_path / "light.toml"
    toml.write_text('body = "wheel"\nname = "light_wheel"\nmass_z = 3.15\n')
    r = runner.invoke(
        app,
        [
            "mpm",
            "steady",
            "--scenario",
            str(toml),
            "--quick",
            "--omega-rpm",
            "30",
            "--out",
            str(tmp_path / "runs"),
            "--threads",
            "1",
        ],
    )
    assert r.exit_code == 0, r.output
    info = json.loads((tmp_path / "runs" / "light_wheel_30rpm" / "locomotion.json").read_text())
    assert info["scenario"]["mass_z"] == 3.15 and info["body"] == "wheel"
    r = runner.invoke(app, ["mpm", "steady", "--scenario", str(tmp_path / "missing.toml"), "--quick"])
    assert r.exit_code == 2 and "not found" in r.output
    r = runner.invoke(app, ["mpm", "steady", "--scenario", "tractor", "--quick"])
    assert r.exit_code == 2 and "or a .toml file" in r.output


def test_a_folder_written_before_a_setting_existed_goes_on_when_the_setting_is_its_default(tmp_path):
    """A run folder from an earlier version lacks the settings added since (here
    backend.deterministic_sums): it is read with their defaults, as loading it does, so the same
    configuration goes on from its checkpoint; a non-default value of that setting is a difference."""
    cfg = tmp_path / "tiny.toml"
    cfg.write_text(TINY)
    out = tmp_path / "run"
    assert runner.invoke(app, ["mpm", "run", str(cfg), "--out", str(out)]).exit_code == 0
    written = json.loads((out / "config.json").read_text())
    del written["config"]["backend"]["deterministic_sums"]
    (out / "config.json").write_text(json.dumps(written))
    longer = tmp_path / "longer.toml"
    longer.write_text(TINY.replace("t_end = 0.02", "t_end = 0.03"))
    r = runner.invoke(app, ["mpm", "run", str(longer), "--out", str(out)])
    assert r.exit_code == 0 and "continuing" in r.output, r.output
    other = tmp_path / "other.toml"
    other.write_text(TINY.replace("t_end = 0.02", "t_end = 0.04") + "[backend]\ndeterministic_sums = false\n")
    r = runner.invoke(app, ["mpm", "run", str(other), "--out", str(out)])
    assert r.exit_code == 2 and "differs in backend.deterministic_sums" in r.output, r.output


def test_the_summary_line_calls_a_drifting_window_an_average_not_a_steady_state():
    """A run that did not pass the settle test (v and sinkage within 1 % over its last two
    revolutions) is reported as "NOT settled" with what it is still doing (still sinking at X mm/s)
    and the way to extend it, never as a steady state."""
    from intrusim.cli_mpm import steady_line
    from intrusim.scenarios.mpm_locomotion import steady_from_series

    t = np.linspace(0.0, 6.0, 601)  # omega 3 rad/s: revolutions of 2.09 s, two of them after 0.65 s
    outline = np.array([[0.1, 0.0], [0.0, 0.1], [-0.1, 0.0], [0.0, -0.1]])
    base = {"time": t, "x": 0.2 * t, "theta": -3.0 * t, "vz": 0 * t, "omega": -3.0 + 0 * t}
    base.update(fx=0 * t, fz=0 * t, moment=0 * t)
    flat = steady_from_series({**base, "z": 0.36 + 0 * t, "vx": 0.2 + 0 * t}, outline, 0.3, 0.65, False, [])
    sinking = steady_from_series({**base, "z": 0.36 - 0.01 * t, "vx": 0.25 - 0.04 * t}, outline, 0.3, 0.65, False, [])
    short = steady_from_series({**base, "z": 0.36 + 0 * t, "vx": 0.2 + 0 * t}, outline, 0.3, 2.0, False, [])
    for st in (flat, sinking, short):
        st.meta["particles"] = 10
    assert flat.settled and flat.outcome == "settled"
    assert steady_line(flat).startswith("steady state over t = 0.66-6.00 s (settled: v and sinkage moved 0.00%")
    assert ": v = 0.2000 m/s" in steady_line(flat)
    assert not short.settled and short.outcome == "too short"  # 4 s after 2 s: not two revolutions
    assert steady_line(short).startswith("NOT settled (too short to judge")
    assert not sinking.settled and sinking.outcome == "sinking"
    line = steady_line(sinking)
    assert line.startswith("NOT settled (still sinking at 9.97 mm/s") and "steady state" not in line
    assert sinking.settling.sinkage_rate == pytest.approx(0.01, rel=0.01)  # the centre drops 10 mm/s
    assert "--set t_max=T" in line and "--set settle_time=S" in line and "averages over t = 0.66-6.00 s" in line
    assert "cell_size" not in line  # a state without its cell size names no finer one
    sinking.meta["cell_size"] = 0.005
    assert "halve the cells, --set cell_size=0.0025" in steady_line(sinking)
    assert "this wheel did not settle" not in steady_line(sinking)  # a body nothing was measured for
    sinking.meta["scenario"] = "grousered_wheel"  # the Table S1 wheel: what docs/convergence.md measured
    assert "at 30 RPM this wheel did not settle in 8 s at 5 mm cells" in steady_line(sinking)
