"""The bulldozing resistance (laws.bulldozing) against its formula, and in the force models and integrators."""

import math

import numpy as np
import pytest

from intrusim._checks import InputError
from intrusim.analysis.calibration import PARAMETERS, with_parameters
from intrusim.analysis.steady import run_steady
from intrusim.forces import ResistiveForceModel, make_force_model
from intrusim.kinematics import BodyState
from intrusim.laws.bulldozing import V_REG, bulldozing_force, bulldozing_scale, bulldozing_wrench, passive_coefficient
from intrusim.params import GRAVITY
from intrusim.scenarios import ForceModelConfig, get_scenario


def test_passive_coefficient_is_rankine():
    assert passive_coefficient(math.tan(math.radians(30.0))) == pytest.approx(3.0, rel=1e-12)
    assert passive_coefficient(0.0) == 1.0
    phi = math.atan(0.56)
    assert passive_coefficient(0.56) == pytest.approx(math.tan(math.pi / 4 + phi / 2) ** 2, rel=1e-12)


def test_scale_and_force_follow_the_formula():
    k_p = passive_coefficient(0.56)
    scale = bulldozing_scale(4.0, 0.56, 638.0, 9.81, 0.14)
    assert scale == pytest.approx(4.0 * 0.5 * k_p * 638.0 * 9.81 * 0.14, rel=1e-14)
    d = np.array([-0.01, 0.0, 0.02, 0.05])
    v = np.array([0.2, 0.2, 0.2, -0.3])
    f = bulldozing_force(scale, d, v)
    assert f[0] == 0.0 and f[1] == 0.0  # above the surface: nothing
    assert f[2] == pytest.approx(-scale * 0.02**2 * math.tanh(0.2 / V_REG), rel=1e-14)
    assert f[3] > 0.0  # against the travel
    assert bulldozing_force(scale, 0.03, 0.0) == 0.0  # at rest: smoothed to zero


def test_scalar_wrench_matches_vectorised_force_and_acts_two_thirds_down():
    scale, radius, surface, z, vx = 300.0, 0.106, 0.0, 0.07, 0.15
    fx, moment = bulldozing_wrench(scale, radius, surface, z, vx)
    d = surface - (z - radius)
    assert fx == pytest.approx(float(bulldozing_force(scale, d, vx)), rel=1e-14)
    lever = surface - 2.0 * d / 3.0 - z  # height of the resultant above the centre (< 0: below it)
    assert moment == pytest.approx(-lever * fx, rel=1e-14)
    assert bulldozing_wrench(scale, radius, surface, 0.2, vx) == (0.0, 0.0)  # lifted clear


@pytest.mark.parametrize("bad", [dict(coefficient=-1.0), dict(width=0.0), dict(rho=-1.0), dict(mu=float("nan"))])
def test_bad_inputs_fail_by_name(bad):
    args = dict(coefficient=1.0, mu=0.56, rho=638.0, gravity=9.81, width=0.14) | bad
    with pytest.raises(InputError):
        bulldozing_scale(**args)


def test_force_model_adds_the_term_on_both_paths():
    sc = get_scenario("wheel")
    shape = sc.rft_shape()
    plain = make_force_model("drft", shape, structural="wheel-rear-half")
    bull = make_force_model("drft", shape, structural="wheel-rear-half", bulldozing=4.0)
    assert bull.bulldozing == pytest.approx(bulldozing_scale(4.0, 0.56, 638.0, GRAVITY, 0.14), rel=1e-14)
    assert bull.radius == shape.radius
    state = BodyState(0.0, 0.07, 0.3, 0.15, -0.01, -3.0)
    expect_fx, expect_m = bulldozing_wrench(bull.bulldozing, shape.radius, 0.0, state.z, state.vx)
    assert expect_fx < -1.0
    a, b = np.array(plain.wrench(state).as_array()), np.array(bull.wrench(state).as_array())
    assert b - a == pytest.approx([expect_fx, 0.0, expect_m], rel=1e-9, abs=1e-12)
    assert np.array(bull.wrench_numpy(state).as_array()) == pytest.approx(b, rel=1e-9, abs=1e-9)
    assert np.array(plain.wrench_numpy(state).as_array()) == pytest.approx(a, rel=1e-9, abs=1e-9)


def test_force_model_rejects_a_bulldozing_term_without_radius():
    shape = get_scenario("wheel").rft_shape()
    with pytest.raises(InputError, match="radius"):
        ResistiveForceModel(shape.elements, bulldozing=100.0)
    with pytest.raises(InputError, match="bulldozing"):
        ResistiveForceModel(shape.elements, bulldozing=-1.0, radius=0.1)


def _with_bulldozing(k_b):
    return with_parameters(get_scenario("wheel"), {"bulldozing": k_b})


def test_compiled_loop_matches_python_loop_with_the_term():
    sc = _with_bulldozing(4.0)
    fast = run_steady(sc, "drft", 30.0)
    ref = run_steady(sc, "drft", 30.0, compiled=False)
    assert fast.velocity == pytest.approx(ref.velocity, rel=5e-3)
    assert fast.sinkage == pytest.approx(ref.sinkage, abs=2e-4)
    a, b = fast.trajectory, ref.trajectory
    assert len(a.t) == len(b.t)
    assert np.allclose(a.vx, b.vx, rtol=0, atol=1e-9) and np.allclose(a.fx, b.fx, rtol=0, atol=1e-6)


def test_resistance_slows_the_wheel_and_zero_changes_nothing():
    base = run_steady(get_scenario("wheel"), "drft", 30.0)
    zero = run_steady(_with_bulldozing(0.0), "drft", 30.0)
    assert zero.velocity == base.velocity and zero.sinkage == base.sinkage
    slow = run_steady(_with_bulldozing(4.0), "drft", 30.0)
    assert slow.velocity < 0.8 * base.velocity  # held back ...
    assert slow.sinkage > base.sinkage  # ... it slips more and digs deeper


def test_config_and_calibration_parameter():
    assert ForceModelConfig().bulldozing == 0.0 and ForceModelConfig().internal_friction == 0.56
    with pytest.raises(ValueError):
        ForceModelConfig(bulldozing=-0.5)
    assert PARAMETERS["bulldozing"].field == "bulldozing"
    assert _with_bulldozing(2.5).force_model.bulldozing == 2.5
