"""Steady-state window, sinkage definition, no-contact detection."""

import numpy as np
import pytest

from intrusim._checks import InputError
from intrusim.analysis.steady import NoContactError, outline_sinkage, steady_state, window_means
from intrusim.bodies import Drive, IntegratorSettings, RigidBody, simulate
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
