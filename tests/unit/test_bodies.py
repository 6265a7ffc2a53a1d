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
    b = simulate(stiff_ground(1e4, 50.0), body, d, a.state(-1), 1.0, s, t0=float(a.t[-1]))
    both = a.concatenate(b)
    assert np.allclose(both.t, one.t) and np.allclose(both.z, one.z, atol=1e-12) and np.allclose(both.theta, one.theta)
