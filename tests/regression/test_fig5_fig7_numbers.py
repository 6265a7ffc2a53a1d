"""Pinned numbers of Fig 5 (DRFT wheel) and Fig 7 (runner, lambda = 4), so a refactor cannot
silently move them. Values recorded on branch loco (see docs/locomotion.md); tolerance 0.5 %
on speed and 0.2 mm on sinkage (the integrator's own dt sensitivity is below both)."""

import pytest

from intrusim.analysis.steady import run_steady
from intrusim.scenarios import get_scenario

PINNED = [
    # scenario, model, omega_rpm, lam, velocity m/s, sinkage m
    ("wheel", "drft", 30.0, None, 0.2519, 0.04222),
    ("wheel", "drft", 90.0, None, 0.7006, 0.04334),
    ("wheel", "rft", 90.0, None, 0.7750, 0.04182),
    ("runner", "drft", 200.0, 4.0, 1.6474, 0.03694),
]


@pytest.mark.parametrize("name, kind, rpm, lam, v, sink", PINNED)
def test_pinned(name, kind, rpm, lam, v, sink):
    st = run_steady(get_scenario(name), kind, rpm, lam)
    assert st.settled
    assert st.velocity == pytest.approx(v, rel=5e-3)
    assert st.sinkage == pytest.approx(sink, abs=2e-4)
