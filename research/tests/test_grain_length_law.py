"""The grain-length law of DRFT's xi (helpers.grain_length): xi = xi_ref (q / q_ref)^p, q = d / r."""

import math

import numpy as np
import pytest
from helpers.grain_length import XiLengthLaw, d_over_r, fit_xi_length_law


def test_two_points_give_the_law_through_both():
    law = fit_xi_length_law([0.05, 0.1], [2.0, 3.0])
    assert law.xi(0.05) == pytest.approx(2.0, rel=1e-12) and law.xi(0.1) == pytest.approx(3.0, rel=1e-12)
    assert law.exponent == pytest.approx(math.log(1.5) / math.log(2.0), rel=1e-12)
    assert law.q_ref == pytest.approx(math.sqrt(0.05 * 0.1), rel=1e-12)
    assert law.xi_ref == pytest.approx(math.sqrt(2.0 * 3.0), rel=1e-12)  # xi at the geometric mean of q


def test_a_power_law_is_recovered_from_noisy_points_and_the_fit_is_least_squares_in_log_xi():
    rng = np.random.default_rng(3)
    q = np.geomspace(0.02, 0.3, 9)
    xi = 1.7 * (q / 0.08) ** 0.9 * np.exp(rng.normal(0.0, 0.02, q.size))
    law = fit_xi_length_law(q, xi)
    assert law.exponent == pytest.approx(0.9, abs=0.05)
    assert law.xi(0.08) == pytest.approx(1.7, rel=0.03)
    p, c = np.polyfit(np.log(q), np.log(xi), 1)
    assert law.exponent == pytest.approx(p, rel=1e-10)
    assert law.xi(1.0) == pytest.approx(math.exp(c), rel=1e-10)


def test_the_law_takes_arrays_and_scalars():
    law = XiLengthLaw(2.0, 0.1, 1.0)
    assert law.xi(0.2) == pytest.approx(4.0)
    assert isinstance(law.xi(0.2), float)
    np.testing.assert_allclose(law.xi(np.array([0.05, 0.1, 0.4])), [1.0, 2.0, 8.0])
    assert law.summary() == {"xi_ref": 2.0, "q_ref": 0.1, "exponent": 1.0}


def test_d_over_r():
    assert d_over_r(6e-3, 0.106) == pytest.approx(0.0566, rel=1e-3)


@pytest.mark.parametrize("q, xi, match", [
    ([0.1, 0.1], [2.0, 3.0], "two distinct"),
    ([0.1], [2.0], "two distinct"),
    ([0.1, 0.2], [2.0], "equal length"),
    ([[0.1, 0.2]], [[2.0, 3.0]], "1-D"),
    ([0.1, -0.2], [2.0, 3.0], "> 0"),
    ([0.1, 0.2], [2.0, 0.0], "> 0"),
    ([0.1, float("nan")], [2.0, 3.0], "finite"),
])  # fmt: skip
def test_bad_fit_input_is_refused(q, xi, match):
    with pytest.raises(ValueError, match=match):
        fit_xi_length_law(q, xi)


@pytest.mark.parametrize(
    "args", [(0.0, 0.1, 1.0), (2.0, -0.1, 1.0), (float("inf"), 0.1, 1.0), (2.0, 0.1, float("nan"))]
)
def test_a_bad_law_is_refused(args):
    with pytest.raises(ValueError):
        XiLengthLaw(*args)


@pytest.mark.parametrize("q", [0.0, -0.1, float("nan"), [0.1, 0.0]])
def test_the_law_refuses_a_bad_d_over_r(q):
    with pytest.raises(ValueError, match="d / r"):
        XiLengthLaw(2.0, 0.1, 1.0).xi(q)


@pytest.mark.parametrize("d, r", [(0.0, 0.1), (6e-3, -0.1), (float("nan"), 0.1), ("6e-3", 0.1)])
def test_d_over_r_refuses_bad_lengths(d, r):
    with pytest.raises(ValueError):
        d_over_r(d, r)
