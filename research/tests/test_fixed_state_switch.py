"""research/mpm_fixed_state.py switch: a free wheel held from its last checkpoint (coarse, 2 cm cells)."""

import argparse
import csv
import json

import numpy as np
import pytest

from intrusim.mpm.io import read_timeseries
from intrusim.scenarios import grousered_wheel_scenario
from intrusim.scenarios.mpm_locomotion import quick_settings, run_mpm_steady


@pytest.fixture(scope="module")
def free_run(tmp_path_factory):
    """A coarse free wheel on the treadmill, 0.8 s at 30 RPM, its checkpoint at the end."""
    out = tmp_path_factory.mktemp("free") / "run"
    # APIC (flip 0), the transfer these distances were set for: the held wheel (3x the free one's speed)
    # must pass the treadmill's trigger more than once
    s = quick_settings("wheel").validated_copy(t_max=0.8, settle_time=0.3, treadmill=(0.2, 0.17), flip=0.0)
    run_mpm_steady(grousered_wheel_scenario(), s, 30.0, out)
    return out


def _switch(mod, free, out, rpm, scale=1.0, duration=0.2):
    mod.switch(argparse.Namespace(free_run=str(free), rpm=rpm, vx_scale=scale, window=0.3, duration=duration,
                                  threads=1, out=str(out)))  # fmt: skip
    (folder,) = out.iterdir()
    ts = read_timeseries(folder / "timeseries.csv")
    rows = [{k: float(v[i]) for k, v in ts.items() if not np.isnan(v[i])} for i in range(len(ts["time"]))]
    return folder, rows


def test_the_held_wheel_keeps_its_height_and_the_speed_asked(load_example, free_run, tmp_path):
    """Held at 3x the free mean speed at 90 RPM: z frozen at the checkpoint's, vx exactly 3x the mean
    over the window, omega 90 RPM (the free run's sense), and x in the bed frame carries on from the
    free run across the treadmill's shifts; the free run's rows are kept before the switch."""
    mod = load_example("mpm_fixed_state")
    folder, rows = _switch(mod, free_run, tmp_path / "held", 90.0, scale=3.0)
    info = json.loads((folder / "fixed_state.json").read_text())
    t = np.array([r["time"] for r in rows])
    free_t = read_timeseries(free_run / "timeseries.csv")
    win = free_t["time"] > free_t["time"][-1] - 0.3 + 2e-9
    assert info["t_switch"] == pytest.approx(0.8, abs=2e-4) and info["vx_scale"] == 3.0  # a whole number of steps
    assert info["free_vx_mean"] == pytest.approx(float(np.mean(free_t["vx"][win])), rel=0.02)
    assert info["vx"] == pytest.approx(3.0 * info["free_vx_mean"], rel=1e-12) and info["vx"] > 0.1
    held = [r for r in rows if r["time"] > info["t_switch"] + 1e-9]
    assert 19 <= len(held) <= 20 and t[-1] > 0.98  # recorded every 0.01 s
    assert len(rows) - len(held) == len(free_t["time"])  # the free run's rows, then the held ones
    assert all(
        r["z"] == pytest.approx(info["z"], abs=1e-9) and r["vx"] == pytest.approx(info["vx"], rel=1e-6) for r in held
    )
    assert all(r["omega"] == pytest.approx(-90.0 * 2 * np.pi / 60, rel=1e-6) for r in held)
    th, xh = np.array([r["time"] for r in held]), np.array([r["x"] for r in held])
    assert xh[-1] - xh[0] > 0.15  # past the treadmill's trigger more than once (it shifts at 0.2 m)
    np.testing.assert_allclose(
        xh - xh[0], info["vx"] * (th - th[0]), rtol=0, atol=1e-6
    )  # bed frame, through the shifts
    loco = json.loads((folder / "locomotion.json").read_text())
    assert loco["omega_rpm"] == 90.0 and loco["held"]["from_run"] == str(free_run)


def test_the_first_held_row_averages_the_force_over_its_own_interval(load_example, free_run, tmp_path):
    """The switch falls between two records: the first held row's force is the mean over its whole
    interval, not the impulse since the free run's last record over the few steps since the switch
    (which blew it up by the ratio of the two: 66x here, 3-7x in the 2.5 mm runs)."""
    mod = load_example("mpm_fixed_state")
    _, rows = _switch(mod, free_run, tmp_path / "held", 30.0, duration=0.1)
    free_t = read_timeseries(free_run / "timeseries.csv")
    held = [r for r in rows if r["time"] > free_t["time"][-1] + 1e-9]
    scale = float(np.max(np.abs(free_t["fz"][-30:])))
    assert (
        abs(held[0]["fz"]) < 2.0 * scale and abs(held[0]["fx"]) < 2.0 * float(np.max(np.abs(free_t["fx"][-30:]))) + 5.0
    )


def test_a_finished_held_run_is_not_run_again(load_example, free_run, tmp_path, capsys):
    """The same command on a finished folder says so and keeps its rows and its recorded wall time."""
    mod = load_example("mpm_fixed_state")
    folder, rows = _switch(mod, free_run, tmp_path / "held", 30.0, duration=0.1)
    wall = json.loads((folder / "fixed_state.json").read_text())["wall_s"]
    _, again = _switch(mod, free_run, tmp_path / "held", 30.0, duration=0.1)
    assert "already held" in capsys.readouterr().out
    assert again == rows and json.loads((folder / "fixed_state.json").read_text())["wall_s"] == wall


def test_bad_input_is_refused_before_compute(load_example, free_run, tmp_path):
    """A folder without a free run's checkpoint, a non-positive omega or a window longer than the run."""
    mod = load_example("mpm_fixed_state")
    with pytest.raises(SystemExit, match="not a run folder"):
        _switch(mod, tmp_path, tmp_path / "held", 30.0)
    with pytest.raises(SystemExit, match="must be positive"):
        _switch(mod, free_run, tmp_path / "held", 0.0)
    with pytest.raises(SystemExit, match="longer than the run"):
        mod.held_from_free(free_run, 30.0, 1.0, 5.0, 0.1, tmp_path / "held")
    assert not (tmp_path / "held").exists()


def test_the_table_averages_whole_windows_after_the_switch(load_example, free_run, tmp_path):
    """``table --after-switch 0.05`` on a 0.2 s hold: four windows, each the mean of the held rows in
    (t_switch + k 0.05, t_switch + (k + 1) 0.05] (the last one short of its end by less than one
    record); a window past that is left out; S <= 0 refused."""
    mod = load_example("mpm_fixed_state")
    folder, rows = _switch(mod, free_run, tmp_path / "held", 30.0, duration=0.2)
    t_switch = json.loads((folder / "fixed_state.json").read_text())["t_switch"]
    fig = tmp_path / "fig" / "switch"
    mod.table(argparse.Namespace(folders=[str(tmp_path / "held")], window=0.1, after_switch=0.05, out=str(fig)))
    with (tmp_path / "fig" / "switch_after_switch.csv").open(newline="") as f:
        windows = [{k: float(v) for k, v in r.items()} for r in csv.DictReader(f)]
    assert [(w["t_start"], w["t_end"]) for w in windows] == [(0.0, 0.05), (0.05, 0.1), (0.1, 0.15), (0.15, 0.2)]
    for k, w in enumerate(windows):
        sel = [r for r in rows if t_switch + 0.05 * k + 1e-9 < r["time"] <= t_switch + 0.05 * (k + 1) + 1e-9]
        assert 4 <= len(sel) <= 6 and w["omega_rpm"] == 30.0
        assert w["fz"] == pytest.approx(np.mean([r["fz"] for r in sel]), rel=1e-12)
        assert w["fx"] == pytest.approx(np.mean([r["fx"] for r in sel]), rel=1e-12)
    assert (
        len(mod.after_switch_means(read_timeseries(folder / "timeseries.csv"), t_switch, 0.15)) == 1
    )  # 0.15-0.3 s is not held
    with pytest.raises(SystemExit, match="must be positive"):
        mod.table(argparse.Namespace(folders=[str(tmp_path / "held")], window=0.1, after_switch=0.0, out=str(fig)))
    with pytest.raises(SystemExit, match="none held a whole window"):
        mod.table(argparse.Namespace(folders=[str(tmp_path / "held")], window=0.1, after_switch=0.5, out=str(fig)))
