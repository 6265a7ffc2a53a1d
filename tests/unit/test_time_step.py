"""The locomotion time step (RunConfig.dt): k + 0.618 steps per lug pitch within the run's bounds."""

import math

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from intrusim._checks import InputError
from intrusim.scenarios import RunConfig, get_scenario
from intrusim.scenarios.base import GOLDEN_FRACTION


@settings(max_examples=200, deadline=None)
@given(
    rpm=st.floats(0.5, 2000.0),
    symmetry=st.integers(1, 64),
    steps=st.integers(8, 2000),
    dt_max=st.floats(1e-5, 0.1),
)
def test_steps_per_pitch_are_whole_plus_the_golden_fraction(rpm, symmetry, steps, dt_max):
    run = RunConfig(steps_per_revolution=steps, dt_max=dt_max)
    omega = rpm * 2.0 * math.pi / 60.0
    period = run.period(omega)
    dt = run.dt(omega, symmetry)
    per_pitch = period / dt / symmetry
    k = round(per_pitch - GOLDEN_FRACTION)
    assert per_pitch == pytest.approx(k + GOLDEN_FRACTION, rel=1e-12)
    # within the bounds ...
    assert dt <= dt_max * (1 + 1e-12)
    assert period / dt >= steps * (1 - 1e-12)
    # ... and the largest such step: one step fewer per pitch breaks a bound
    fewer = (k - 1 + GOLDEN_FRACTION) * symmetry
    assert k == 0 or period / fewer > dt_max * (1 + 1e-12) or fewer < steps


def test_scenario_steps_use_the_lug_count():
    wheel = get_scenario("wheel")  # 20 grousers, 72 steps a revolution at least
    assert wheel.rft_shape().symmetry == wheel.lug_count == 20
    omega = 90.0 * 2.0 * math.pi / 60.0
    assert wheel.run.period(omega) / wheel.run.dt(omega, 20) == pytest.approx(20 * 3.618034, rel=1e-6)
    runner = get_scenario("runner")  # 4 flaps, 200 steps a revolution, at most 4 ms
    assert runner.rft_shape().symmetry == 4
    assert runner.run.period(omega) / runner.run.dt(omega, 4) == pytest.approx(4 * 50.618034, rel=1e-6)


def test_bad_symmetry_is_refused():
    with pytest.raises(InputError, match="symmetry"):
        RunConfig().dt(3.0, 0)
