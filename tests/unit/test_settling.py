"""The stop test of a continuum run (analysis.settling) on series whose answer is known."""

import math

import numpy as np
import pytest

from intrusim.analysis.settling import settle_window, settling

OMEGA = 2 * math.pi  # one revolution a second: settling windows of 1 s


def _t(t_end=5.0):
    return np.arange(0.0, t_end + 1e-9, 0.01)


def test_a_steady_run_is_settled_with_its_last_revolutions_means():
    t = _t()
    v = 0.2 + 0.001 * np.sin(2 * math.pi * 7 * t)  # lugs' ripple, no trend
    s = 0.05 + 0.5e-3 * np.exp(-t)  # a transient long gone
    j = settling(t, v, s, OMEGA, t_start=1.0)
    assert j.outcome == "settled" and j.settled and j.window == pytest.approx(1.0)
    assert j.velocity == pytest.approx(0.2, abs=2e-3) and j.sinkage == pytest.approx(0.05, abs=1e-4)
    assert j.dv < 0.01 and j.ds < 0.01 and "settled" in j.text


def test_a_body_still_sinking_says_how_fast():
    t = _t()
    s = 0.04 + 0.004 * t  # 4 mm/s, 10 % of the sinkage over a revolution
    j = settling(t, np.full_like(t, 0.15), s, OMEGA, t_start=1.0)
    assert j.outcome == "sinking" and not j.settled
    assert j.sinkage_rate == pytest.approx(0.004, rel=1e-6) and "still sinking at 4 mm/s" in j.text
    assert settling(t, np.full_like(t, 0.15), 0.1 - 0.004 * t, OMEGA, 1.0).outcome == "rising"


def test_a_body_still_changing_speed_says_which_way_and_how_fast():
    t = _t()
    s = np.full_like(t, 0.05)
    up = settling(t, 0.1 + 0.02 * t, s, OMEGA, 1.0)
    assert up.outcome == "accelerating" and up.acceleration == pytest.approx(0.02, rel=1e-6)
    assert "still accelerating at 0.02 m/s^2" in up.text
    assert settling(t, 0.3 - 0.02 * t, s, OMEGA, 1.0).outcome == "slowing"
    # the tolerance decides: a 1.2 % change per revolution passes at 2 %, not at 1 %
    slow = 0.2 * (1 + 0.012 * t)
    assert settling(t, slow, s, OMEGA, 1.0, tol=0.02).settled and not settling(t, slow, s, OMEGA, 1.0, tol=0.01).settled


def test_a_buried_body_is_entrapped_whatever_else_it_does():
    t = _t()
    j = settling(t, np.full_like(t, 0.01), np.full_like(t, 0.25), OMEGA, 1.0, radius=0.106)
    assert j.outcome == "buried" and "38 mm under the surface" in j.text and not j.settled
    assert settling(t, np.full_like(t, 0.01), np.full_like(t, 0.25), OMEGA, 1.0).outcome == "settled"  # no radius


def test_a_body_riding_at_the_surface_is_judged_on_its_own_size_not_on_a_near_zero_mean():
    t = _t()
    s = 2e-4 + 5e-5 * np.sin(2 * math.pi * 0.3 * t)  # 0.2 +- 0.05 mm: bobbing at the surface
    v = np.full_like(t, 0.3)
    assert settling(t, v, s, OMEGA, 1.0).outcome in ("rising", "sinking")  # relative to 0.2 mm: never settles
    assert settling(t, v, s, OMEGA, 1.0, radius=0.1).settled  # relative to r / 10 = 10 mm: 0.5 % at most
    stopped = 0.002 + 0.0005 * np.sin(2 * math.pi * 0.3 * t)  # a body nearly at rest, v 2 +- 0.5 mm/s
    assert not settling(t, stopped, np.full_like(t, 0.05), OMEGA, 1.0).settled
    assert settling(t, stopped, np.full_like(t, 0.05), OMEGA, 1.0, radius=0.1).settled  # scale r |omega| / 10


def test_a_run_shorter_than_two_revolutions_after_its_transient_is_not_judged():
    t = _t(2.5)
    j = settling(t, np.full_like(t, 0.2), np.full_like(t, 0.05), OMEGA, t_start=1.0)
    assert j.outcome == "too short" and math.isnan(j.velocity) and "to t = 3 s" in j.text


def test_bad_input_is_refused():
    with pytest.raises(ValueError, match="turning body"):
        settle_window(0.0)
    with pytest.raises(ValueError, match="tol"):
        settling(_t(), np.ones(501), np.ones(501), OMEGA, 1.0, tol=1.5)
