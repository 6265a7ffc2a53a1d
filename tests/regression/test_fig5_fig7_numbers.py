"""Pinned numbers of Fig 5 (DRFT wheel) and Fig 7 (runner, lambda = 4), so a refactor cannot
silently move them. Values with the default integrator (BDF2 at ``RunConfig.dt``), each within
0.04 % in speed and 0.01 mm in sinkage of the same run at 1/16 of the step over 8 revolutions;
tolerance 0.5 % on speed and 0.2 mm on sinkage."""

import pytest

from intrusim.analysis.steady import run_steady
from intrusim.scenarios import get_scenario

PINNED = [
    # scenario, model, omega_rpm, lam, velocity m/s, sinkage m
    ("wheel", "drft", 30.0, None, 0.2522, 0.04221),
    ("wheel", "drft", 90.0, None, 0.7120, 0.04302),
    ("wheel", "rft", 90.0, None, 0.7748, 0.04186),
    ("runner", "drft", 200.0, 4.0, 1.6450, 0.03710),
]


@pytest.mark.parametrize("name, kind, rpm, lam, v, sink", PINNED)
def test_pinned(name, kind, rpm, lam, v, sink):
    st = run_steady(get_scenario(name), kind, rpm, lam)
    assert st.settled
    assert st.velocity == pytest.approx(v, rel=5e-3)
    assert st.sinkage == pytest.approx(sink, abs=2e-4)
