"""The implicit integrator stays bounded at large steps and agrees with small steps (wheel, DRFT)."""

import pytest

from intrusim.analysis.steady import steady_state
from intrusim.bodies import IntegratorError, IntegratorSettings, simulate
from intrusim.scenarios import get_scenario


def run(dt, scheme="implicit"):
    s = get_scenario("wheel")
    model, shape, drive = s.build_model("drft"), s.rft_shape(), s.drive(60.0)
    tr = simulate(model, s.rigid_body(), drive, s.initial_state(shape), 8.0, IntegratorSettings(dt=dt, scheme=scheme))
    return steady_state(tr, shape, 2)


def test_large_steps_agree_with_small_steps():
    fine = run(1e-3)
    mid = run(2e-2)  # 20x
    coarse = run(5e-2)  # 50x: longer than a grouser passing (50 ms at 60 RPM)
    assert mid.velocity == pytest.approx(fine.velocity, rel=5e-3)
    assert mid.sinkage == pytest.approx(fine.sinkage, abs=2e-4)  # 0.5 % of the sinkage
    assert coarse.velocity == pytest.approx(fine.velocity, rel=5e-2)
    assert coarse.sinkage == pytest.approx(fine.sinkage, abs=1e-3)


def test_explicit_euler_diverges_at_the_same_large_step():
    with pytest.raises(IntegratorError, match="divergence.*smaller time step"):
        run(5e-2, scheme="explicit")
