"""Plate drag (paper Fig 6) at CI resolution (h = 5 mm, the paper's cell size): the structure of
F = K |z| + lambda rho A v^2. Bands are broad on purpose; the measured numbers at a finer
resolution are in docs/mpm.md (they exceed the paper's K by about 2-3x)."""

import numpy as np
import pytest

from intrusim.mpm.plate import PlateDragCase, fit_drag_law, steady_force
from intrusim.mpm.solver import Solver

SLOW = 0.08


def drag(depth: float, speed: float) -> float:
    case = PlateDragCase(depth=depth, speed=speed, travel=0.03, cells=(60, 30))
    return -steady_force(Solver(case.config()).run(), "fx")


@pytest.fixture(scope="module")
def forces():
    runs = [(0.02, SLOW), (0.04, SLOW), (0.02, 0.32), (0.02, 0.64)]
    return {run: drag(*run) for run in runs}


def test_slow_drag_grows_linearly_with_depth(forces):
    f2, f4 = forces[(0.02, SLOW)], forces[(0.04, SLOW)]
    assert f2 > 0
    assert 1.4 < f4 / f2 < 2.6  # F = K |z|: ratio 2


def test_speed_excess_is_positive_and_superlinear(forces):
    base = forces[(0.02, SLOW)]
    e1 = forces[(0.02, 0.32)] - base
    e2 = forces[(0.02, 0.64)] - base
    assert e1 > 0 and e2 > e1
    assert 1.8 < e2 / e1 < 6.0  # rho v^2 gives ~4 (minus the small slow-speed part)


def test_fitted_constants_in_broad_band(forces):
    d, v = np.array(list(forces)).T
    K, lam = fit_drag_law(d, v, np.array(list(forces.values())), 900.0, 0.016)
    assert 200.0 < K < 3000.0  # N/m per metre width; paper 580
    assert 0.3 < lam < 15.0  # paper 1.1
