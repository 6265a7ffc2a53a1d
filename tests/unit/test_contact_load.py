"""Where a wheel bears on the grains (analysis.contact_load): the load by angle, the loaded arc, dh_b."""

import numpy as np
import pytest

from intrusim._checks import InputError
from intrusim.analysis.contact_load import angular_load, bearing_drop, loaded_arc


def _ring(phi_deg, pressure, radius=0.1, centre=(0.5, 0.3)):
    """Grains at ``radius`` from ``centre`` at angles ``phi_deg`` from straight down (+ towards +x)."""
    a = np.radians(np.asarray(phi_deg, float))
    pos = np.c_[centre[0] + radius * np.sin(a), centre[1] - radius * np.cos(a)]
    return pos, np.broadcast_to(np.asarray(pressure, float), a.shape).copy()


def test_load_is_summed_by_angle_from_straight_down_positive_forward():
    pos, p = _ring([30.0, 30.0, -60.0], [100.0, 50.0, 10.0])
    far, pf = _ring([0.0], [1e6], radius=0.3)  # beyond radius + shell: not the wheel's load
    ang, load = angular_load(np.r_[pos, far], np.r_[p, pf], (0.5, 0.3), 1.0, 0.1, 0.01, bins=36)
    assert load.sum() == pytest.approx(160.0)
    assert load[np.argmin(np.abs(ang - np.radians(35.0)))] == pytest.approx(150.0)  # the 30-40 deg bin
    # travelling towards -x, the same grains are behind the wheel
    ang, back = angular_load(pos, p, (0.5, 0.3), -1.0, 0.1, 0.01, bins=36)
    assert back[np.argmin(np.abs(ang + np.radians(35.0)))] == pytest.approx(150.0)
    # a pulled grain (tension) carries nothing
    _, pulled = angular_load(pos, -p, (0.5, 0.3), 1.0, 0.1, 0.01)
    assert pulled.sum() == 0.0


def test_loaded_arc_ends_are_quantiles_of_the_load():
    ang = np.radians(np.arange(-87.5, 90.0, 5.0))
    load = np.where((ang > np.radians(-20)) & (ang < np.radians(60)), 1.0, 0.0)  # uniform from -20 to +60 deg
    rear, front = loaded_arc(ang, load, 0.05)
    assert np.degrees(rear) == pytest.approx(-20 + 0.05 * 80, abs=1e-9)
    assert np.degrees(front) == pytest.approx(60 - 0.05 * 80, abs=1e-9)
    # a heavier front moves only the front end's share
    rear2, front2 = loaded_arc(ang, load * np.where(ang > np.radians(40), 3.0, 1.0), 0.05)
    assert rear2 > rear and front2 > front
    assert all(np.isnan(loaded_arc(ang, 0 * load)))


def test_bearing_drop_hand_values():
    r = 0.106
    assert bearing_drop(0.0, r - 0.05, r) == pytest.approx(0.05)  # rear end straight down: the sinkage
    assert bearing_drop(np.radians(-60.0), 0.0, r) == pytest.approx(r / 2)  # centre at the surface


@pytest.mark.parametrize(
    "call",
    [
        lambda: angular_load(np.zeros((2, 2)), np.zeros(3), (0, 0), 1.0, 0.1, 0.01),
        lambda: angular_load(np.zeros((2, 2)), np.zeros(2), (0, 0), 0.5, 0.1, 0.01),
        lambda: angular_load(np.zeros((2, 2)), np.zeros(2), (0, 0), 1.0, -0.1, 0.01),
        lambda: angular_load(np.full((2, 2), np.nan), np.zeros(2), (0, 0), 1.0, 0.1, 0.01),
        lambda: loaded_arc(np.array([0.0, 1.0]), np.array([1.0, 1.0]), 0.5),
        lambda: loaded_arc(np.array([1.0, 0.0]), np.array([1.0, 1.0])),
        lambda: loaded_arc(np.array([0.0, 1.0]), np.array([1.0, -1.0])),
        lambda: bearing_drop(np.nan, 0.0, 0.1),
    ],
)
def test_bad_input_is_refused(call):
    with pytest.raises(InputError):
        call()
