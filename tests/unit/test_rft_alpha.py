"""Unit tests of the Li (2013) RFT stress-per-depth fit alpha(beta, gamma) (paper Eq. 3)."""

import numpy as np
import pytest

from intrusim._checks import InputError
from intrusim.laws.rft import alpha, alpha_fit, element_angles, rft_traction


def hand_alpha(beta, gamma):
    """Li et al. 2013 generic fit written out term by term (N/cm^3)."""
    az = (
        0.206
        + 0.169 * np.cos(2 * beta)
        + 0.212 * np.sin(2 * beta + gamma)
        + 0.358 * np.sin(gamma)
        + 0.055 * np.sin(-2 * beta + gamma)
    )
    ax = (
        -0.124 * np.cos(2 * beta + gamma)
        + 0.253 * np.cos(gamma)
        + 0.007 * np.cos(-2 * beta + gamma)
        + 0.088 * np.sin(2 * beta)
    )
    return ax, az


def test_horizontal_plate_down_and_up():
    # the reference hint: alpha_z(0, +pi/2) = 1.0, alpha_z(0, -pi/2) = -0.25 N/cm^3
    assert alpha_fit(0.0, np.pi / 2)[1] == pytest.approx(1.0)
    assert alpha_fit(0.0, -np.pi / 2)[1] == pytest.approx(-0.25)
    assert alpha_fit(0.0, np.pi / 2)[0] == pytest.approx(0.0, abs=1e-12)


@pytest.mark.parametrize("beta,gamma", [(0.3, 0.2), (-0.7, 1.1), (np.pi / 4, np.pi / 6), (1.2, -0.9)])
def test_fit_matches_hand_formula(beta, gamma):
    assert np.allclose(alpha_fit(beta, gamma), hand_alpha(beta, gamma), atol=1e-12)


def test_si_units_and_xi_scaling():
    ax, az = alpha(0.0, np.pi / 2, xi=0.35)
    assert az == pytest.approx(0.35e6)
    ax2, az2 = alpha(0.4, 0.3, xi=0.7)
    hx, hz = hand_alpha(0.4, 0.3)
    assert (ax2, az2) == pytest.approx((0.7e6 * hx, 0.7e6 * hz))


def test_orientation_is_modulo_pi():
    b = np.linspace(-1.5, 1.5, 13)
    g = np.linspace(-1.4, 1.4, 13)
    assert np.allclose(alpha(b, g), alpha(b + np.pi, g))
    assert np.allclose(alpha(b, g), alpha(b - np.pi, g))


def test_mirror_symmetry_extends_fit():
    b = np.linspace(-1.5, 1.5, 31)
    g = np.linspace(-1.5, 1.5, 31)
    ax, az = alpha(b, g)
    mx, mz = alpha(-b, np.pi - g)
    assert np.allclose(mx, -ax) and np.allclose(mz, az)


def test_continuous_across_vertical_motion():
    b = np.linspace(-1.5, 1.5, 31)
    eps = 1e-7
    for g0 in (np.pi / 2, -np.pi / 2):
        lo = np.array(alpha(b, g0 - eps))
        hi = np.array(alpha(b, g0 + eps))
        assert np.allclose(lo, hi, rtol=1e-5, atol=1.0)


def test_resistance_always_opposes_motion():
    # F . v < 0 for every orientation and direction: velocity v = -(cos g, sin g)
    b, g = np.meshgrid(np.linspace(-np.pi, np.pi, 181), np.linspace(-np.pi, np.pi, 181))
    ax, az = alpha(b, g)
    assert np.all(ax * np.cos(g) + az * np.sin(g) > 0)


def test_element_angles():
    beta, gamma = element_angles(np.array([[0.0, -1.0]]), np.array([[0.0, -2.0]]))
    assert beta[0] == pytest.approx(0.0) and gamma[0] == pytest.approx(np.pi / 2)
    # lower-front element of a wheel (normal pointing down and forward): beta = -pi/4
    n = np.array([[np.sqrt(0.5), -np.sqrt(0.5)]])
    beta, gamma = element_angles(n, np.array([[-1.0, 0.0]]))
    assert beta[0] == pytest.approx(-np.pi / 4) and gamma[0] == pytest.approx(0.0)


def test_traction_leading_edge_and_depth():
    n = np.array([[0.0, -1.0], [0.0, 1.0], [0.0, -1.0]])
    v = np.array([[0.0, -1.0], [0.0, -1.0], [0.0, -1.0]])
    depth = np.array([-0.02, -0.02, 0.01])
    t = rft_traction(n, v, depth, xi=0.35)
    assert t[0] == pytest.approx([0.0, 0.35e6 * 0.02])  # bottom face pushing down at 2 cm
    assert np.all(t[1] == 0)  # trailing face
    assert np.all(t[2] == 0)  # above the surface


def test_bad_xi():
    with pytest.raises(InputError, match="xi"):
        alpha(0.0, 0.0, xi=-1.0)
    with pytest.raises(InputError, match="xi"):
        alpha(0.0, 0.0, xi=float("nan"))
