"""Coarse MPM locomotion in CI (2 cm cells, ~1 s runs): the signs of the paper's trends.

Full-resolution numbers (5 mm cells, the paper's set-up) are produced by `intrusim mpm sweep`
and recorded in docs/results.md; these tests only check the direction of each effect.
"""

import math

import numpy as np
import pytest

from intrusim._checks import InputError
from intrusim.analysis.sweep import sweep_omega
from intrusim.scenarios import four_flap_runner_scenario, grousered_wheel_scenario
from intrusim.scenarios.mpm_locomotion import MPMLocomotion, mpm_config, quick_settings, run_mpm_steady, write_result


@pytest.fixture(scope="module")
def wheel_runs():
    sc = grousered_wheel_scenario()
    s = quick_settings("wheel").model_copy(update=dict(contact="band"))  # the trends as measured with the band
    return {rpm: run_mpm_steady(sc, s, rpm) for rpm in (10.0, 50.0)}


def test_wheel_slips_more_and_sinks_more_as_omega_grows(wheel_runs):
    slow, fast = wheel_runs[10.0], wheel_runs[50.0]
    assert fast.velocity > slow.velocity > 0
    assert fast.slip > slow.slip + 0.05  # v/(r omega) falls (Fig 3A plateau)
    assert fast.sinkage > slow.sinkage  # sinkage grows with omega (Fig 3B)
    for st in (slow, fast):
        assert 0 < st.sinkage < st.radius
        assert st.window[0] >= 0.6 - 1e-9 and st.window[1] > st.window[0] + 0.3


def test_wheel_rear_surface_drop_grows_with_omega(wheel_runs):
    slow, fast = wheel_runs[10.0], wheel_runs[50.0]
    assert math.isfinite(slow.surface_drop) and math.isfinite(fast.surface_drop)
    assert fast.surface_drop > slow.surface_drop  # Fig 5C


def test_with_the_paper_groups_transfer_the_wheel_keeps_the_trends():
    """FLIP on linear shape functions (the paper's group's mpm-2d): faster, more slip, deeper and a
    deeper rear drop from 10 to 50 RPM, as with the default transfer (docs/results.md)."""
    sc = grousered_wheel_scenario()
    s = quick_settings("wheel").validated_copy(flip=1.0, shape="linear", contact="band")
    slow, fast = (run_mpm_steady(sc, s, rpm) for rpm in (10.0, 50.0))
    assert fast.velocity > slow.velocity > 0
    assert fast.slip > slow.slip + 0.05
    assert fast.sinkage > slow.sinkage
    assert fast.surface_drop > slow.surface_drop


def test_runner_rises_as_omega_grows():
    sc = four_flap_runner_scenario()
    s = quick_settings("runner").model_copy(update=dict(contact="band"))  # measured with the band (2 cm cells)
    slow, fast = (run_mpm_steady(sc, s, rpm) for rpm in (30.0, 90.0))
    assert fast.velocity > 2 * slow.velocity
    assert fast.sinkage < slow.sinkage  # elevation with spin (Fig 7C)


def test_sweep_dispatches_to_mpm_and_survives_a_bad_point():
    s = quick_settings("wheel").model_copy(update=dict(t_max=0.6, settle_time=0.3))
    case = MPMLocomotion(scenario=grousered_wheel_scenario(), mpm=s)
    res = sweep_omega(case, "mpm", [20.0, -5.0], parallel=False, progress=False)
    good, bad = res.records
    assert good["ok"] and good["velocity"] > 0
    assert not bad["ok"] and "omega_rpm" in bad["error"]


def test_bad_mpm_cases_fail_before_compute():
    sc = grousered_wheel_scenario()
    with pytest.raises(InputError, match="omega_rpm"):
        mpm_config(sc, quick_settings("wheel"), 0.0)
    with pytest.raises(InputError, match="does not fit"):
        mpm_config(sc, quick_settings("wheel").model_copy(update=dict(start_x=0.05)), 30.0)
    with pytest.raises(InputError, match="MPMLocomotion runs the 'mpm' model"):
        MPMLocomotion(scenario=sc, mpm=quick_settings("wheel")).run_steady("drft", 30.0)
    with pytest.raises(InputError, match="start_depth"):
        mpm_config(sc, quick_settings("wheel").model_copy(update=dict(start_depth=0.3)), 30.0)


def test_embedded_start_places_the_wheel_below_the_surface_without_grains_inside():
    """start_depth puts the lowest point of the true outline that far below the bed surface; the
    bed leaves out the grains in the wheel's place, so the bed holds less mass than without."""
    from intrusim.geometry import posed_polygon
    from intrusim.mpm.solver import Solver

    sc = grousered_wheel_scenario()
    base = quick_settings("wheel").model_copy(update=dict(cpu_threads=1))
    masses, lows = [], []
    for depth in (0.0, 0.04):
        cfg = mpm_config(sc, base.model_copy(update=dict(start_depth=depth)), 30.0)
        body = cfg.intruders[0]
        lows.append(float(posed_polygon(np.asarray(body.vertices), body.x, body.z, body.theta)[:, 1].min()))
        masses.append(float(Solver(cfg).particles.to_numpy()["mass"].sum()))
    assert lows[0] == pytest.approx(base.bed_depth + 0.5 * base.h)
    assert lows[1] == pytest.approx(base.bed_depth - 0.04)
    assert masses[1] < masses[0] * 0.995  # the wheel's submerged area, about 1 % of a 1 m bed


def test_run_description_is_written_whole_or_not_at_all(tmp_path, monkeypatch):
    """locomotion.json (what ``mpm collect`` reads to rebuild a run's scenario) goes through the
    atomic writer: a write whose final rename fails leaves no file and no temporary."""
    import intrusim.mpm.io as mpm_io

    real_replace = mpm_io.os.replace

    def failing_replace(src, dst):
        if str(dst).endswith("locomotion.json"):
            raise OSError("disk full")
        return real_replace(src, dst)

    monkeypatch.setattr(mpm_io.os, "replace", failing_replace)
    with pytest.raises(OSError, match="disk full"):
        run_mpm_steady(grousered_wheel_scenario(), quick_settings("wheel"), 30.0, tmp_path / "run")
    assert not (tmp_path / "run" / "locomotion.json").exists()
    assert not list((tmp_path / "run").glob("locomotion.json*"))


class _Killed(Exception):
    pass


def _killed_and_resumed(sc, s, folder):
    """Run 30 RPM in ``folder``, kill it just after 0.62 s (after its 0.5 s checkpoint), start it
    again on the same folder: the resumed steady state and the progress records it sent."""

    def kill(p):
        if p["t"] > 0.62:
            raise _Killed

    with pytest.raises(_Killed):
        run_mpm_steady(sc, s, 30.0, folder, progress=kill)
    seen = []
    return run_mpm_steady(sc, s, 30.0, folder, progress=seen.append), seen


def test_killed_run_resumes_from_its_checkpoint_and_matches_the_uninterrupted_run(tmp_path):
    """A locomotion run stopped after its checkpoint (t = 0.5 s) and started again on the same
    folder continues from the checkpoint: same steps, steady state and rear surface drop."""
    sc = grousered_wheel_scenario()
    s = quick_settings("wheel").model_copy(update=dict(t_max=0.8, settle_time=0.3))  # window from 0.4 s
    full = run_mpm_steady(sc, s, 30.0, tmp_path / "full")
    resumed, seen = _killed_and_resumed(sc, s, tmp_path / "killed")
    assert seen[0]["t"] == pytest.approx(0.55, abs=1e-3)  # went on from the checkpoint at 0.5 s, not from 0
    assert resumed.steps == full.steps
    for key in ("velocity", "sinkage", "slip", "surface_drop", "surface_drop_std"):
        assert getattr(resumed, key) == pytest.approx(getattr(full, key), rel=1e-6, abs=1e-9), key
    assert len(resumed.meta["fields"]) == len(full.meta["fields"]) == s.keep_fields
    # another configuration on the same folder is refused, naming the difference, and the run's
    # files are left as they were (it used to delete the checkpoint and overwrite the time series)
    before = {p.name: p.read_bytes() for p in (tmp_path / "killed").iterdir()}
    for other in (s.model_copy(update=dict(t_max=0.6)), s.model_copy(update=dict(contact_band_cells=0.0))):
        with pytest.raises(InputError, match="another configuration.*differs in (time.t_end|contact_band_cells)"):
            run_mpm_steady(sc, other, 30.0, tmp_path / "killed")
    assert {p.name: p.read_bytes() for p in (tmp_path / "killed").iterdir()} == before
    # as is a finished run of another configuration that a sweep would otherwise reuse
    write_result(tmp_path / "killed", resumed)
    case = MPMLocomotion(scenario=sc, mpm=s.model_copy(update=dict(t_max=0.6)), out_root=str(tmp_path))
    (tmp_path / "killed").rename(case.run_dir(30.0))
    with pytest.raises(InputError, match="another configuration"):
        case.run_steady("mpm", 30.0)
    # the same configuration in a moved folder, on another thread count, is the same run: reused
    same = MPMLocomotion(scenario=sc, mpm=s.model_copy(update=dict(cpu_threads=1)), out_root=str(tmp_path))
    assert same.run_steady("mpm", 30.0).velocity == pytest.approx(resumed.velocity, rel=1e-6)


def test_a_killed_free_wheel_with_the_nonlocal_law_resumes_on_the_uninterrupted_track(tmp_path):
    """The free wheel with the nonlocal fluidity (docs/results.md item 10): its checkpoint carries
    the grid's fluidity, so a run killed after it resumes to the uninterrupted run's numbers, and
    the law is the one configured (at these 2 cm cells it moves v by 2 % against the paper's law)."""
    from intrusim.mpm.config import FluidityConfig

    sc = grousered_wheel_scenario()
    s = quick_settings("wheel").model_copy(
        update=dict(
            t_max=0.8,
            settle_time=0.3,
            contact="band",
            contact_band_cells=0.0,
            fluidity=FluidityConfig(grain_diameter=6e-3),
        )
    )
    full = run_mpm_steady(sc, s, 30.0, tmp_path / "full")
    resumed, seen = _killed_and_resumed(sc, s, tmp_path / "killed")
    assert seen[0]["t"] == pytest.approx(0.55, abs=1e-3)  # from the checkpoint at 0.5 s
    assert resumed.steps == full.steps
    for key in ("velocity", "sinkage", "slip"):
        assert getattr(resumed, key) == pytest.approx(getattr(full, key), rel=1e-6, abs=1e-9), key
    paper = run_mpm_steady(sc, s.model_copy(update=dict(fluidity=None)), 30.0)
    assert abs(full.velocity - paper.velocity) > 0.01 * paper.velocity


def test_finished_run_with_a_later_t_max_goes_on_from_its_end_and_matches_a_run_that_long(tmp_path, capsys):
    """A run not settled by t_max can be made longer: the same case with a later t_max on its
    folder goes on from the end state (not from t = 0) and gives the numbers of a run made that
    long from the start; the longer run then stands in the folder, and the shorter one is refused."""
    sc = grousered_wheel_scenario()
    s = quick_settings("wheel").model_copy(update=dict(t_max=0.8, settle_time=0.3))  # window from 0.4 s
    full = run_mpm_steady(sc, s, 30.0, tmp_path / "full")
    short = MPMLocomotion(scenario=sc, mpm=s.model_copy(update=dict(t_max=0.6)), out_root=str(tmp_path / "ext"))
    first = short.run_steady("mpm", 30.0)
    assert first.window[1] == pytest.approx(0.6, abs=0.011)  # the last record (every 0.01 s)
    capsys.readouterr()
    longer = MPMLocomotion(scenario=sc, mpm=s, out_root=str(tmp_path / "ext"))
    extended = longer.run_steady("mpm", 30.0)
    assert "resumed at t = 0.600 s" in capsys.readouterr().err
    assert extended.steps == full.steps
    for key in ("velocity", "sinkage", "slip", "surface_drop", "surface_drop_std"):
        assert getattr(extended, key) == pytest.approx(getattr(full, key), rel=1e-6, abs=1e-9), key
    assert longer.run_steady("mpm", 30.0).velocity == pytest.approx(extended.velocity, rel=1e-12)  # reused
    with pytest.raises(InputError, match="not cut short"):
        short.run_steady("mpm", 30.0)


def test_a_killed_treadmill_run_resumes_on_the_uninterrupted_track(tmp_path):
    """With the moving window the number of points changes at every shift: a run killed after its
    0.5 s checkpoint resumes from it (new point count, offset and all) to the uninterrupted run's
    numbers, the time series' x included."""
    sc = grousered_wheel_scenario()
    s = quick_settings("wheel").validated_copy(t_max=0.8, settle_time=0.3, treadmill=(0.2, 0.17))
    full = run_mpm_steady(sc, s, 30.0, tmp_path / "full")
    assert full.meta["x_offset"] >= 0.04  # the scene moved back at least twice (2 cm cells)
    resumed, seen = _killed_and_resumed(sc, s, tmp_path / "killed")
    assert seen[0]["t"] == pytest.approx(0.55, abs=1e-3)  # from the checkpoint at 0.5 s
    assert resumed.steps == full.steps and resumed.meta["x_offset"] == pytest.approx(full.meta["x_offset"])
    for key in ("velocity", "sinkage", "slip", "surface_drop"):
        assert getattr(resumed, key) == pytest.approx(getattr(full, key), rel=1e-6, abs=1e-9), key
    np.testing.assert_allclose(resumed.series["x"], full.series["x"], rtol=0, atol=1e-9)


def test_the_treadmill_in_a_1_m_box_gives_the_2_m_box_wheel():
    """The moving window stands in for a longer bed: the coarse wheel kept between 0.35 and 0.5 m
    of a 1 m box (the scene moved back 0.4 m or more by 2.4 s) moves as in a 2 m box, window by
    window (measured: v within 1.1 %, sinkage within 0.2 mm in its three 0.6 s windows)."""
    sc = grousered_wheel_scenario()
    # APIC and the band contact: the run these figures were measured on
    base = quick_settings("wheel").validated_copy(t_max=2.4, flip=0.0, contact="band")
    long_box = run_mpm_steady(sc, base.validated_copy(domain=(2.0, 0.5), cells=(100, 25)), 30.0)
    tread = run_mpm_steady(sc, base.validated_copy(treadmill=(0.5, 0.35)), 30.0)
    assert long_box.meta["x_offset"] == 0.0 and tread.meta["x_offset"] >= 0.4
    assert tread.series["x"][-1] == pytest.approx(long_box.series["x"][-1], abs=0.01)  # bed frame
    t = tread.series["time"]
    for a, b in ((0.6, 1.2), (1.2, 1.8), (1.8, 2.4)):
        m = (t > a) & (t <= b)
        for run in (tread, long_box):
            assert np.array_equal(run.series["time"][m], t[m])
        v = [run.series["vx"][m].mean() for run in (tread, long_box)]
        sk = [run.series["sinkage"][m].mean() for run in (tread, long_box)]
        assert v[0] == pytest.approx(v[1], rel=0.02), (a, b)
        assert sk[0] == pytest.approx(sk[1], abs=5e-4), (a, b)


def test_a_treadmill_outside_the_box_is_refused_before_compute(tmp_path):
    s = quick_settings("wheel")
    for bad, match in (
        ((0.3, 0.35), "x_target < x_trigger"),
        ((0.95, 0.5), "x_target < x_trigger"),
        ((0.15, 0.1), "ahead of start_x"),
        ((0.5, 0.49), "at least one cell"),
    ):
        with pytest.raises(ValueError, match=match):
            s.validated_copy(treadmill=bad)
    for bad, match in (
        ((0.85, 0.5), "wall margin"),  # the wheel's front would pass it
        ((0.3, 0.11), "touch the left wall"),
    ):  # radius 0.106 m, 2 cm cells
        with pytest.raises(InputError, match=match):
            run_mpm_steady(grousered_wheel_scenario(), s.validated_copy(treadmill=bad), 30.0, tmp_path / "run")
        assert not (tmp_path / "run").exists()


@pytest.mark.slow
def test_half_size_wheel_in_its_similar_setup_falls_on_the_large_wheels_curve():
    """Fig S1 in the MPM: the half-size wheel (every length x 1/2) in the set-up made similar
    (``mpm_scale`` 0.5: cells and box x 1/2, times x 1/sqrt 2) at the same omega / omega_0 gives
    the large wheel's v / sqrt(g l) and sinkage / l (coarse: 2 and 1 cm cells, under 1.2 s)."""
    from intrusim.scenarios.locomotor import small_wheel_scenario

    big, small = grousered_wheel_scenario(), small_wheel_scenario()
    rpm = 45.0
    out = {}
    for sc, w in ((big, rpm), (small, rpm * math.sqrt(2.0))):  # omega sqrt(l / g) kept
        st = run_mpm_steady(sc, quick_settings(sc.body, sc.mpm_scale), w)
        out[sc.name] = (st.velocity / math.sqrt(sc.gravity * sc.length_scale), st.sinkage / sc.length_scale)
    (vb, sb), (vs, ss) = out[big.name], out[small.name]
    assert vs == pytest.approx(vb, rel=0.05) and ss == pytest.approx(sb, rel=0.05), (
        out
    )  # +0.7 %, -2.6 % (x 1 cells: -6 %, +25 %)


def test_the_wheel_bears_on_the_grains_in_front_of_its_lowest_point(tmp_path):
    """The MPM wheel's load around its rim (analysis.contact_load, figure wheel-load) lies in front of
    its lowest point: the loaded arc (5 % of the load beyond each end) ends behind within 35 deg of
    straight down, in front short of where the rim meets the undisturbed surface; so the surface the
    rear bears on, dh_b below the undisturbed one, is about the sinkage, and it deepens with omega
    (the structural correction's psi grows with x, as the paper's does)."""
    from intrusim.analysis.contact_load import angular_load, bearing_drop, loaded_arc

    sc, s = grousered_wheel_scenario(), quick_settings("wheel")
    psi = {}
    for rpm in (10.0, 60.0):
        st = run_mpm_steady(sc, s, rpm, tmp_path / f"{rpm:g}")
        snaps = [np.load(f) for f in sorted((tmp_path / f"{rpm:g}").glob("fields_*.npz"))]
        assert len(snaps) >= 2
        load = sum(angular_load(d["x"], d["pressure"], tuple(d["body"][:2]), 1.0, sc.radius, 0.04)[1] for d in snaps)
        ang = angular_load(snaps[0]["x"], snaps[0]["pressure"], (0.0, 0.0), 1.0, sc.radius, 0.04)[0]
        rear, front = loaded_arc(ang, load, 0.05)
        height = float(np.mean([d["body"][1] for d in snaps])) - s.bed_depth
        assert math.radians(-35.0) < rear < math.radians(5.0)
        assert math.radians(20.0) < front < math.acos(min(1.0, height / sc.radius))
        dh_b = bearing_drop(rear, height, sc.radius)
        assert abs(dh_b / st.sinkage - 1.0) < 0.25
        psi[rpm] = dh_b / sc.radius
    assert psi[60.0] > psi[10.0] + 0.2
