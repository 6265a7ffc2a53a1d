"""Unit tests of the DRFT corrections (paper Eq. 4, Fig 5C)."""

import numpy as np
import pytest

from intrusim._checks import InputError
from intrusim.laws.drft import WheelRearHalf, inertial_traction, rear_half_mask, structural_depth_shift, travel_sign


def test_inertial_term_on_one_element():
    # -n lambda rho v_n^2: bottom face (n = -z) moving down at 2 m/s in rho = 638, lambda = 1
    t = inertial_traction(np.array([[0.0, -1.0]]), np.array([[0.0, -2.0]]), rho=638.0, lam=1.0)
    assert t[0] == pytest.approx([0.0, 638.0 * 4.0])


def test_inertial_term_oblique_and_trailing():
    n = np.array([[np.sqrt(0.5), np.sqrt(0.5)], [1.0, 0.0]])
    v = np.array([[1.0, 0.0], [-1.0, 0.0]])
    t = inertial_traction(n, v, rho=900.0, lam=1.1)
    vn = np.sqrt(0.5)
    assert t[0] == pytest.approx(-n[0] * 1.1 * 900.0 * vn * vn)
    assert np.all(t[1] == 0.0)  # moving away from the medium: no correction


@pytest.mark.parametrize("rpm,expected", [(30, 0.0113158), (60, 0.0452632), (90, 0.1018422)])
def test_structural_drop_at_paper_speeds(rpm, expected):
    omega = rpm * 2 * np.pi / 60
    r = 0.106
    assert structural_depth_shift(r, omega, 9.8) == pytest.approx(r * r * omega**2 / 9.8)
    assert structural_depth_shift(r, omega, 9.8) == pytest.approx(expected, rel=1e-5)
    assert structural_depth_shift(r, -omega, 9.8) == structural_depth_shift(r, omega, 9.8)


def test_structural_drop_custom_psi():
    assert structural_depth_shift(0.1, 3.0, 9.8, psi=lambda x: 2 * x) == pytest.approx(2 * 0.1 * 0.1 * 9 / 9.8)


def test_rear_half_split_by_angle():
    # a half-buried ring of points: contact arc from -60 deg (rear) to +60 deg (front)
    ang = np.radians(np.arange(-60, 61, 10))
    pos = np.column_stack([np.sin(ang), -np.cos(ang)])
    rear = rear_half_mask(pos, np.zeros(2), np.ones(len(ang), bool), forward=+1.0)
    assert list(rear) == list(ang < 0)
    rear_back = rear_half_mask(pos, np.zeros(2), np.ones(len(ang), bool), forward=-1.0)
    assert list(rear_back) == list(ang > 0)


def test_travel_sign():
    assert travel_sign(-1.0, 0.0) == 1.0  # clockwise spin rolls towards +x
    assert travel_sign(2.0, 0.0) == -1.0
    assert travel_sign(0.0, -0.1) == -1.0


def test_wheel_model_applies_drop_to_rear_only():
    model = WheelRearHalf(radius=0.1)
    ang = np.radians(np.arange(-50, 51, 10))
    pos = np.column_stack([0.1 * np.sin(ang), 0.05 - 0.1 * np.cos(ang)])
    dh = model.depth_shift(pos, np.array([0.0, 0.05]), omega=-2 * np.pi, vx=0.1, surface_z=0.0)
    expected = structural_depth_shift(0.1, 2 * np.pi)
    assert np.all(dh[ang < 0] == pytest.approx(expected)) and np.all(dh[ang > 0] == 0)


def test_bad_input_names_parameter():
    with pytest.raises(InputError, match="lambda"):
        inertial_traction(np.array([[0.0, 1.0]]), np.array([[0.0, 1.0]]), rho=1.0, lam=-1.0)
    with pytest.raises(InputError, match="omega"):
        structural_depth_shift(0.1, float("inf"))
    with pytest.raises(InputError, match="radius"):
        WheelRearHalf(radius=-0.1)


def test_zone_band_lowers_the_surface_by_a_share_that_falls_across_the_band():
    """zone_weight: all of dh behind the band, none in front of it, linear across it; width 0 is the sharp split."""
    from intrusim.laws.drft import zone_weight

    assert [zone_weight(a, 0.2, 0.4) for a in (-0.1, 0.0, 0.1, 0.2, 0.3, 0.4, 0.5)] == pytest.approx(
        [1.0, 1.0, 0.75, 0.5, 0.25, 0.0, 0.0]
    )
    assert zone_weight(0.19, 0.2, 0.0) == 1.0 and zone_weight(0.2, 0.2, 0.0) == 0.0
    # on a wheel: between the sharp split's 0 and dh, falling with the angle, and the sharp split as width -> 0
    ang = np.linspace(-1.2, 1.2, 241)
    pos = np.c_[0.1 * np.sin(ang), -0.1 * np.cos(ang)]
    for split in ("submerged", "circle"):
        sharp = WheelRearHalf(0.1, split=split).depth_shift(pos, np.array([0.0, 0.05]), -10.0, 0.0, 0.0)
        band = WheelRearHalf(0.1, split=split, zone_width=0.4).depth_shift(pos, np.array([0.0, 0.05]), -10.0, 0.0, 0.0)
        dh = sharp.max()
        assert dh > 0 and np.all(np.diff(band) <= 1e-15) and np.any((band > 0.01 * dh) & (band < 0.99 * dh))
        assert abs(band.sum() - sharp.sum()) < 0.03 * sharp.sum()  # the band moves dh about, symmetric about the split
        thin = WheelRearHalf(0.1, split=split, zone_width=1e-9).depth_shift(pos, np.array([0.0, 0.05]), -10.0, 0.0, 0.0)
        assert np.array_equal(thin, sharp)
