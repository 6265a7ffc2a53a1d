"""Steady-state window, sinkage definition, no-contact detection."""

import numpy as np
import pytest

from intrusim._checks import InputError
from intrusim.analysis.steady import (
    NoContactError,
    interval_means,
    outline_sinkage,
    run_steady,
    steady_state,
    window_means,
)
from intrusim.bodies import Drive, IntegratorError, IntegratorSettings, RigidBody, simulate
from intrusim.geometry import circle, polygon_shape
from intrusim.kinematics import BodyState


def test_outline_sinkage_formula():
    square = np.array([[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]])
    assert outline_sinkage(square, np.array([0.5]), np.array([0.0]))[0] == pytest.approx(0.5)
    # rotated by 45 degrees the lowest corner is sqrt(2) below the centre
    assert outline_sinkage(square, np.array([0.5]), np.array([np.pi / 4]))[0] == pytest.approx(np.sqrt(2) - 0.5)


def test_window_is_whole_revolutions_and_slip():
    shape = circle(0.1, 0.1, 36)
    omega = -2 * np.pi  # one revolution per second

    def f(x, z, th, vx, vz, om):  # no vertical motion: ground force balances weight; vx -> 0.05
        return -10.0 * (vx - 0.05), 9.8, 0.0

    tr = simulate(f, RigidBody(1.0, 1.0), Drive(omega, 0.0), BodyState(z=0.08), 5.0, IntegratorSettings(dt=1e-3))
    st = steady_state(tr, shape, 2)
    assert st.window[1] - st.window[0] == pytest.approx(2.0)
    assert st.velocity == pytest.approx(0.05, rel=1e-6)
    assert st.slip == pytest.approx(1 - 0.05 / (0.1 * 2 * np.pi))
    # the lowest VERTEX of the 36-gon: between the inscribed and the circumscribed depth
    assert 0.02 - 0.1 * (1 - np.cos(np.pi / 36)) < st.sinkage < 0.02


def test_body_that_never_touches_is_reported():
    shape = polygon_shape([[-0.1, -0.1], [0.1, -0.1], [0.1, 0.1], [-0.1, 0.1]], 0.1)
    body = RigidBody(1.0, 1.0, external_fz=9.8)  # weight exactly carried by the external force

    def air(x, z, th, vx, vz, om):
        return 0.0, 0.0, 0.0

    tr = simulate(air, body, Drive(-3.0, 0.1), BodyState(z=0.5), 6.0, IntegratorSettings(dt=1e-2))
    with pytest.raises(NoContactError, match="never touched"):
        steady_state(tr, shape, 2)


def test_interval_means_take_the_samples_of_a_closed_window_despite_rounded_times():
    t = 0.1 * np.arange(10)  # 0.30000000000000004 and 0.7000000000000001 among them
    v = np.arange(10.0)
    assert interval_means(t, {"v": v, "twice": 2 * v}, 0.3, 0.7) == {"v": 5.0, "twice": 10.0}
    assert interval_means(t, {"v": v}, 0.31, 0.69) == {"v": 5.0}
    with pytest.raises(InputError, match="no sample in the window"):
        interval_means(t, {"v": v}, 0.91, 1.5)


def test_window_means_average_each_window_and_skip_empty_ones():
    t = np.array([0.0, 0.1, 0.2, 0.3, 0.9, 0.95])
    v = np.array([1.0, 3.0, 5.0, 7.0, 2.0, 4.0])
    rows = window_means(t, {"v": v, "twice": 2 * v}, 0.25)
    assert [(r["t_start"], r["t_end"]) for r in rows] == [(0.0, 0.25), (0.25, 0.5), (0.75, 1.0)]
    assert [r["v"] for r in rows] == pytest.approx([3.0, 7.0, 3.0])
    assert [r["twice"] for r in rows] == pytest.approx([6.0, 14.0, 6.0])
    with pytest.raises(InputError):
        window_means(t, {"v": v}, 0.0)
    with pytest.raises(InputError):
        window_means(t, {"v": v[:-1]}, 0.25)


def test_window_means_from_an_origin_right_closed_and_whole_only():
    # records every 0.1 s from a switch at 1.0 s; (t0, t1] windows give the record at the switch
    # to the motion before it, and a 0.3 s window the series stops short of (by more than one
    # record interval) is left out
    t = 1.0 + 0.1 * np.arange(-2, 8)  # 0.8 ... 1.7 s (sample times with rounding)
    v = np.arange(len(t), dtype=float)  # 0 ... 9
    rows = window_means(t, {"v": v}, 0.3, origin=1.0, right_closed=True, whole_only=True)
    assert [(r["t_start"], r["t_end"]) for r in rows] == [(0.0, 0.3), (0.3, 0.6)]
    assert [r["v"] for r in rows] == pytest.approx([4.0, 7.0])  # samples 3-5 and 6-8
    part = window_means(t, {"v": v}, 0.3, origin=1.0, right_closed=True)
    assert len(part) == 3 and part[-1]["v"] == pytest.approx(9.0)  # the partial window (1.6, 1.9]
    left = window_means(t, {"v": v}, 0.3, origin=1.0)
    assert left[0]["v"] == pytest.approx(3.0)  # [1.0, 1.3): samples 2-4
    t2 = np.append(t, 1.8)  # the last record one interval before 1.9: (1.6, 1.9] is whole
    assert len(window_means(t2, {"v": np.append(v, 10.0)}, 0.3, origin=1.0, whole_only=True)) == 3


def test_mean_wrench_along_own_steady_motion_is_the_load():
    # along DRFT's own steady trajectory its mean force balances the load (no push: fx = 0,
    # fz = weight); along a faster, slipping-less copy of it the wheel is pushed back and lifted
    from intrusim.analysis.compare import mean_wrench_along
    from intrusim.scenarios import grousered_wheel_scenario

    sc = grousered_wheel_scenario()
    st = run_steady(sc, "drft", 10.0)
    tr = st.trajectory
    m = (tr.t >= st.window[0]) & (tr.t <= st.window[1])
    series = {k: np.asarray(getattr(tr, k))[m] for k in ("x", "z", "theta", "vx", "vz", "omega")}
    fx, fz, _ = mean_wrench_along(sc.build_model("drft"), series)
    weight = sc.mass_z * sc.gravity
    assert abs(fx) < 0.01 * weight and fz == pytest.approx(weight, rel=0.01)
    # the same motion with the surface 0.3 m lower, given as 0.3 m higher in the series' frame
    shifted = dict(series, z=series["z"] + 0.3)
    assert np.allclose(mean_wrench_along(sc.build_model("drft"), shifted, 0.3), (fx, fz, _), rtol=1e-9, atol=1e-9)
    faster = dict(series, vx=1.2 * series["vx"])
    fx2, fz2, _ = mean_wrench_along(sc.build_model("drft"), faster)
    assert fx2 < -0.05 * weight and fz2 > fz
    with pytest.raises(InputError):
        mean_wrench_along(sc.build_model("drft"), {"x": [0.0]})
    with pytest.raises(InputError):
        mean_wrench_along(sc.build_model("drft"), dict(series, vx=series["vx"][:-1]))


def test_forces_by_part_splits_every_element_once():
    from intrusim.analysis.compare import forces_by_part

    tags = np.array([0, 0, 1, 1, 2, 2])
    ahead = np.array([True, False, True, False, True, True])
    f = np.arange(12.0).reshape(6, 2)
    parts = forces_by_part(tags, ahead, f, halves=("front", "rear"))
    assert list(parts) == ["rim, front", "rim, rear", "grouser sides, front", "grouser sides, rear",
                           "grouser tips, front", "grouser tips, rear"]  # fmt: skip
    assert np.allclose(parts["rim, front"], f[0]) and np.allclose(parts["grouser tips, front"], f[4] + f[5])
    assert np.allclose(parts["grouser tips, rear"], 0.0)
    assert np.allclose(sum(parts.values()), f.sum(axis=0))


def test_window_drift_is_the_larger_change_between_the_halves():
    from intrusim.analysis.steady import window_drift

    v = [1.0, 1.0, 1.2, 1.2]  # mean 1.1, halves 1.0 and 1.2
    sk = [0.040, 0.040, 0.041, 0.041]  # halves 1 mm apart
    assert window_drift(v, sk, radius=0.1) == pytest.approx(0.2 / 1.1)
    assert window_drift([1.0] * 4, sk, radius=0.001) == pytest.approx(1.0)  # the sinkage term wins
    assert window_drift([0.3], [0.04], radius=0.1) == 0.0  # one sample: no halves


def _zone_wheel():
    """The 30-grouser wheel with a rough calibration's force model (the effective rear-half zone,
    benchmarks/data/rough_zone_wheel.model.json):
    at 5 RPM its default step leaves Newton without a root within 8 sub-steps."""
    from intrusim.analysis.calibration import with_mpm_push
    from intrusim.scenarios import load_scenario

    s = load_scenario("wheel-30-grousers")
    fm = s.force_model.validated_copy(
        xi=0.545, lam=0.0912, psi_slope=0.604, psi_offset=0.311, structural="wheel-rear-half-effective"
    )
    return with_mpm_push(s.validated_copy(force_model=fm.model_dump()))


def test_a_failed_run_is_made_again_with_finer_steps_and_says_so(tmp_path):
    from intrusim.analysis.steady import FINER_STEP, run_steady, run_until_steady
    from intrusim.analysis.sweep import SweepResult, sweep_omega

    s = _zone_wheel()
    shape, drive = s.rft_shape(), s.drive(5.0)
    with pytest.raises(IntegratorError, match="did not converge"):
        run_until_steady(s.build_model("drft"), shape, s.rigid_body(), drive, s.initial_state(shape), s.run)
    st = run_steady(s, "drft", 5.0)
    assert st.meta["retried"].startswith(f"{FINER_STEP} x finer steps") and "did not converge" in st.meta["retried"]
    finer = s.run.model_copy(
        update=dict(dt_max=s.run.dt_max / FINER_STEP, steps_per_revolution=4 * s.run.steps_per_revolution)
    )
    direct = run_steady(s.model_copy(update=dict(run=finer)), "drft", 5.0)
    assert st.velocity == direct.velocity and st.sinkage == direct.sinkage and direct.meta["retried"] is None
    res = sweep_omega(s, "drft", [5.0], parallel=False, progress=False)
    assert res.records[0]["ok"] and "finer step" in res.table()
    back = SweepResult.from_csv(res.to_csv(tmp_path / "s.csv"))
    assert back.records[0]["retried"] == st.meta["retried"] and back.records[0]["velocity"] == st.velocity


def test_a_run_that_fails_at_finer_steps_too_names_both_tries():
    from intrusim.analysis.steady import run_steady
    from intrusim.scenarios import get_scenario

    s = get_scenario("wheel")
    heavy = s.model_copy(update={"mass_z": 1e5, "run": s.run.model_copy(update={"max_extensions": 0})})
    with pytest.raises(IntegratorError, match="with 4 x finer steps; at the default step: .*sank") as err:
        run_steady(heavy, "rft", 30.0)
    assert "[run] dt_max (now 0.01 s) and steps_per_revolution (now 72)" in str(err.value)
