"""The compiled (Numba) implicit step loop against the Python reference loop of bodies.simulate."""

import math

import numpy as np
import pytest

from intrusim.analysis.steady import run_steady
from intrusim.bodies import Drive, IntegratorError, IntegratorSettings, RigidBody, simulate
from intrusim.forces import ResistiveForceModel, make_force_model
from intrusim.laws.drft import WheelRearHalf
from intrusim.scenarios import get_scenario

CASES = [("wheel", "drft", 30.0, None), ("wheel", "drft", 90.0, None), ("runner", "drft", 200.0, 4.0)]


@pytest.mark.parametrize("name, kind, rpm, lam", CASES)
def test_compiled_matches_python_steady_state(name, kind, rpm, lam):
    sc = get_scenario(name)
    fast = run_steady(sc, kind, rpm, lam)
    ref = run_steady(sc, kind, rpm, lam, compiled=False)
    assert fast.velocity == pytest.approx(ref.velocity, rel=5e-3)
    assert fast.sinkage == pytest.approx(ref.sinkage, abs=2e-4)
    assert fast.settled == ref.settled
    # same scheme, same steps: the trajectories agree far below the solver tolerance
    a, b = fast.trajectory, ref.trajectory
    assert len(a.t) == len(b.t)
    assert np.allclose(a.vx, b.vx, rtol=0, atol=1e-9) and np.allclose(a.z, b.z, rtol=0, atol=1e-9)
    assert np.allclose(a.theta, b.theta, rtol=0, atol=1e-12)


def test_compiled_path_is_used_and_theta_follows_the_ramp():
    sc = get_scenario("wheel")
    shape = sc.rft_shape()
    model = sc.build_model("drft")
    assert model.compiled_spec() is not None
    d = Drive(-3.0, ramp_time=0.4)
    tr = simulate(model, sc.rigid_body(), d, sc.initial_state(shape), 1.0, IntegratorSettings(dt=0.01))
    assert np.allclose(tr.theta, np.vectorize(d.angle_at)(tr.t), atol=1e-12)
    assert np.allclose(tr.omega, np.vectorize(d.omega_at)(tr.t), atol=0)


def test_custom_free_surface_falls_back_to_python():
    shape = get_scenario("wheel").rft_shape()
    model = make_force_model("drft", shape, structural="wheel-rear-half")
    custom = ResistiveForceModel(
        shape.elements, lam=1.0, free_surface=WheelRearHalf(shape.radius, psi=lambda x: 0.5 * x)
    )
    assert model.compiled_spec() is not None and custom.compiled_spec() is None
    sc = get_scenario("wheel")
    s = IntegratorSettings(dt=0.01)
    tr = simulate(custom, sc.rigid_body(), sc.drive(30.0), sc.initial_state(shape), 0.5, s)  # Python loop
    assert np.all(np.isfinite(tr.vx))


def test_compiled_failure_messages_match_python():
    sc = get_scenario("wheel")
    shape = sc.rft_shape()
    model = sc.build_model("drft")
    heavy = RigidBody(23.0, 6.3, gravity=9.8, external_fz=-1e6)  # pushed far below any support
    msgs = []
    for compiled in (True, False):
        s = IntegratorSettings(dt=0.01, max_depth=0.5, compiled=compiled)
        with pytest.raises(IntegratorError, match="smaller time step") as err:
            simulate(model, heavy, sc.drive(30.0), sc.initial_state(shape), 2.0, s)
        msgs.append(str(err.value))
    assert msgs[0] == msgs[1]


def test_continuation_compiled():
    sc = get_scenario("wheel")
    shape = sc.rft_shape()
    model, body, d = sc.build_model("drft"), sc.rigid_body(), sc.drive(60.0)
    s = IntegratorSettings(dt=0.01)
    whole = simulate(model, body, d, sc.initial_state(shape), 1.0, s)
    first = simulate(model, body, d, sc.initial_state(shape), 0.5, s)
    rest = simulate(model, body, d, first.state(-1), 0.5, s, t0=float(first.t[-1]))
    joined = first.concatenate(rest)
    assert len(joined.t) == len(whole.t)
    assert math.isclose(joined.vx[-1], whole.vx[-1], rel_tol=1e-3, abs_tol=1e-6)


def test_continued_bdf2_run_equals_the_uninterrupted_one():
    """run_steady extends its runs: the continuation starts BDF2 from the last two states and makes up
    the impulse the former run left unbalanced."""
    sc = get_scenario("wheel")
    shape, model, drive = sc.rft_shape(), sc.build_model("drft"), sc.drive(60.0)
    s = IntegratorSettings(dt=0.005)
    one = simulate(model, sc.rigid_body(), drive, sc.initial_state(shape), 2.0, s)
    a = simulate(model, sc.rigid_body(), drive, sc.initial_state(shape), 1.0, s)
    b = simulate(
        model,
        sc.rigid_body(),
        drive,
        a.state(-1),
        1.0,
        s,
        t0=float(a.t[-1]),
        previous=a.state(-2),
        carry=a.meta["carry"],
    )
    cold = simulate(model, sc.rigid_body(), drive, a.state(-1), 1.0, s, t0=float(a.t[-1]))  # backward-Euler start
    both = a.concatenate(b)
    assert np.allclose(both.t, one.t, rtol=0, atol=1e-12)
    gap = np.max(np.abs(both.vx - one.vx))
    assert gap < 1e-12  # the same steps: the Newton Jacobian and the unbalanced impulse carry over
    assert np.max(np.abs(cold.vx - b.vx)) > 10 * gap
