"""Rigid-body integrator: drive ramp, free fall, stiff spring-damper, failure messages."""

import math

import numpy as np
import pytest

from intrusim._checks import InputError
from intrusim.bodies import Drive, IntegratorError, IntegratorSettings, RigidBody, simulate
from intrusim.kinematics import BodyState


def no_force(x, z, th, vx, vz, om):
    return 0.0, 0.0, 0.0


def test_drive_ramp_and_angle():
    d = Drive(-4.0, ramp_time=2.0)
    assert d.omega_at(0.0) == 0.0 and d.omega_at(1.0) == -2.0 and d.omega_at(5.0) == -4.0
    ts = np.linspace(0, 5, 5001)
    numeric = np.concatenate(
        [[0], np.cumsum(0.5 * np.diff(ts) * (np.vectorize(d.omega_at)(ts)[1:] + np.vectorize(d.omega_at)(ts)[:-1]))]
    )
    assert np.allclose(np.vectorize(d.angle_at)(ts), numeric, atol=1e-9)


def test_theta_follows_prescribed_omega_exactly():
    d = Drive(3.0, ramp_time=0.3)
    tr = simulate(no_force, RigidBody(1.0, 1.0, gravity=0.0), d, BodyState(theta=0.2), 1.0, IntegratorSettings(dt=0.01))
    assert np.allclose(tr.theta, 0.2 + np.vectorize(d.angle_at)(tr.t), atol=1e-12)


@pytest.mark.parametrize("scheme", ["implicit", "explicit"])
def test_free_fall_first_order(scheme):
    g, T = 9.8, 1.0
    errs = []
    for dt in (1e-2, 5e-3):
        body = RigidBody(2.0, 3.0, gravity=g, external_fx=4.0)  # a_x = 2 m/s^2
        tr = simulate(no_force, body, Drive(0.0, 0.0), BodyState(z=10.0), T, IntegratorSettings(dt=dt, scheme=scheme))
        errs.append(abs(tr.z[-1] - (10.0 - 0.5 * g * T**2)))
        assert tr.vz[-1] == pytest.approx(-g * T, rel=1e-9)
        assert tr.vx[-1] == pytest.approx(2.0 * T, rel=1e-9)
    assert errs[1] < 0.6 * errs[0]  # first order: halving dt halves the error
    assert errs[0] < 0.5 * g * 1e-2 * T * 1.01


def test_free_fall_bdf2_second_order():
    """BDF2 is exact for constant acceleration; only its first (backward-Euler) step errs, by g dt^2 / 2."""
    g, T = 9.8, 1.0
    errs = []
    for dt in (1e-2, 5e-3):
        tr = simulate(no_force, RigidBody(2.0, 3.0, gravity=g), Drive(0.0, 0.0), BodyState(z=10.0), T,
                      IntegratorSettings(dt=dt, scheme="bdf2"))  # fmt: skip
        errs.append(abs(tr.z[-1] - (10.0 - 0.5 * g * T**2)))
        assert tr.vz[-1] == pytest.approx(-g * T, rel=1e-9)
    assert errs[1] < 0.3 * errs[0]  # second order: halving dt quarters the error
    assert errs[0] < g * 1e-2**2  # one first-order step's error, not T / dt of them


def damped_spring(k=400.0, c=4.0):
    """A smooth linear force F = -k (x, z) - c (vx, vz): a damped oscillator with a closed form."""

    def f(x, z, th, vx, vz, om):
        return -k * x - c * vx, -k * z - c * vz, 0.0

    return f


def oscillator_error(dt, scheme, T=1.0, k=400.0, c=4.0):
    """|x(T) - exact| of the unit-mass damped oscillator x'' + c x' + k x = 0 from x = 0.01, v = 0."""
    tr = simulate(damped_spring(k, c), RigidBody(1.0, 1.0, gravity=0.0), Drive(0.0, 0.0), BodyState(x=0.01), T,
                  IntegratorSettings(dt=dt, scheme=scheme, velocity_tol=1e-12))  # fmt: skip
    g, wd = 0.5 * c, math.sqrt(k - 0.25 * c * c)
    exact = 0.01 * math.exp(-g * T) * (math.cos(wd * T) + g / wd * math.sin(wd * T))
    return abs(tr.x[-1] - exact)


@pytest.mark.parametrize("scheme, order", [("bdf2", 2), ("implicit", 1)])
def test_order_of_accuracy_on_a_smooth_oscillator(scheme, order):
    e1, e2, e3 = (oscillator_error(dt, scheme) for dt in (2e-3, 1e-3, 5e-4))
    for coarse, fine in ((e1, e2), (e2, e3)):
        assert math.log2(coarse / fine) == pytest.approx(order, abs=0.25)


def test_bdf2_python_and_compiled_loops_take_the_same_steps():
    from intrusim.scenarios import get_scenario

    sc = get_scenario("wheel")
    shape = sc.rft_shape()
    model = sc.build_model("drft")
    for scheme in ("bdf2", "implicit"):
        runs = [
            simulate(
                model,
                sc.rigid_body(),
                sc.drive(60.0),
                sc.initial_state(shape),
                1.5,
                IntegratorSettings(dt=0.005, scheme=scheme, compiled=compiled),
            )  # fmt: skip
            for compiled in (True, False)
        ]
        assert np.allclose(runs[0].vx, runs[1].vx, rtol=0, atol=1e-9)
        assert np.allclose(runs[0].z, runs[1].z, rtol=0, atol=1e-9)


def stiff_ground(k=1e6, c=1e6):
    """Hunt-Crossley penalty ground: F_z = -k z (1 + (c/k) v_z) for z < 0 (continuous at z = 0)."""

    def f(x, z, th, vx, vz, om):
        return 0.0, (-k * z - c * z * vz) if z < 0 else 0.0, 0.0

    return f


def test_implicit_stable_where_explicit_diverges():
    body = RigidBody(1.0, 1.0)
    settle = -9.8 / 1e6  # static deflection m g / k
    tr = simulate(stiff_ground(), body, Drive(0.0, 0.0), BodyState(z=0.01), 1.0, IntegratorSettings(dt=1e-2))
    assert tr.z[-1] == pytest.approx(settle, rel=1e-3)
    with pytest.raises(IntegratorError, match="smaller time step"):
        simulate(
            stiff_ground(),
            body,
            Drive(0.0, 0.0),
            BodyState(z=0.01),
            1.0,
            IntegratorSettings(dt=1e-2, scheme="explicit"),
        )


def test_newton_failure_is_reported():
    # a force with a jump far above the tolerance and no root: dry friction-like sign(vz)
    def jump(x, z, th, vx, vz, om):
        return 0.0, -1e4 * math.copysign(1.0, vz), 0.0

    with pytest.raises(IntegratorError, match="did not converge.*smaller time step"):
        simulate(jump, RigidBody(1.0, 1.0), Drive(0.0, 0.0), BodyState(), 0.1, IntegratorSettings(dt=1e-2))


def test_sinking_without_bound_is_divergence():
    s = IntegratorSettings(dt=0.05, max_depth=1.0)
    with pytest.raises(IntegratorError, match="sank"):
        simulate(no_force, RigidBody(1.0, 1.0), Drive(0.0, 0.0), BodyState(z=0.0), 5.0, s)


def test_bad_settings_named():
    with pytest.raises(InputError, match="dt"):
        IntegratorSettings(dt=0.0)
    with pytest.raises(InputError, match="scheme"):
        IntegratorSettings(scheme="rk4")  # type: ignore[arg-type]
    with pytest.raises(InputError, match="mass_z"):
        RigidBody(1.0, -1.0)


def test_continuation_equals_single_run():
    body, d, s = RigidBody(2.0, 1.0), Drive(-2.0, 0.5), IntegratorSettings(dt=1e-2)
    one = simulate(stiff_ground(1e4, 50.0), body, d, BodyState(z=0.05), 2.0, s)
    a = simulate(stiff_ground(1e4, 50.0), body, d, BodyState(z=0.05), 1.0, s)
    b = simulate(stiff_ground(1e4, 50.0), body, d, a.state(-1), 1.0, s, t0=float(a.t[-1]), previous=a.state(-2))
    both = a.concatenate(b)
    assert np.allclose(both.t, one.t) and np.allclose(both.z, one.z, atol=1e-12) and np.allclose(both.theta, one.theta)
