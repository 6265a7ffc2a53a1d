"""The MPM's steady state against the grain length d / r: the half-size twins at d = 3, 6 (and 12) mm
over the reference's 6.0-8.5 s (research/notes/results_log.md, registered before the runs).

Runs ``research/grain_length_twins.py`` on the committed window CSVs.
"""

import math
from pathlib import Path

import pytest

OUT = Path(__file__).resolve().parents[2] / "research" / "outputs"
D3 = (OUT / "small_wheel_42rpm_twin_6s.csv", "small wheel, 2.5 mm, 3 mm grains, half box", 3e-3)
D6 = (OUT / "small_wheel_42rpm_twin_d6_6s.csv", "small wheel, 2.5 mm, 6 mm grains, half box", 6e-3)
REFERENCE = (OUT / "wheel_30rpm_nonlocal_treadmill.csv", "5 mm, treadmill in 1 m", 6e-3)


@pytest.fixture(scope="module")
def script(load_example):
    return load_example("grain_length_twins")


def test_the_window_is_the_twins_time_scaled_and_the_runs_sorted_by_d(script):
    res = script.analyse([D6, D3], REFERENCE, (6.0, 8.5))
    ratio = math.sqrt(0.053 / 0.106)
    assert res["twin_window"] == pytest.approx([6.0 * ratio, 8.5 * ratio], rel=1e-3)
    assert [r["d"] for r in res["runs"]] == [3e-3, 6e-3] and all(r["windows"] == 5 for r in res["runs"])
    assert res["reference"]["windows"] == 5 and res["reference"]["d_over_r"] == pytest.approx(6e-3 / 0.106, rel=1e-3)


def test_doubling_d_from_3_to_6_mm_takes_0p113_of_slip_and_0p064_of_sinkage_over_r(script):
    """The outcome: 0.361 -> 0.248 in slip, 0.310 -> 0.246 in sinkage / r; one doubling."""
    res = script.analyse([D3, D6], None, (6.0, 8.5))
    (step,) = res["steps"]
    assert step["slip_per_doubling"] == pytest.approx(-0.113, abs=0.002)
    assert step["sinkage_over_r_per_doubling"] == pytest.approx(-0.064, abs=0.002)
    assert "reference" not in res


@pytest.mark.parametrize("runs, window, match", [
    ([D3], (6.0, 8.5), "two or more runs"),
    ([D3, D3], (6.0, 8.5), "two or more runs"),
    ([D3, D6], (8.5, 6.0), "must end after"),
    ([D3, (OUT / "no_such.csv", "x", 1e-3)], (6.0, 8.5), "no such file"),
    ([D3, (D6[0], D6[1], -6e-3)], (6.0, 8.5), "grain diameter"),
])  # fmt: skip
def test_bad_input_is_refused_with_a_reason(script, runs, window, match):
    from intrusim._checks import InputError

    with pytest.raises(InputError, match=match):
        script.analyse(runs, None, window)


D12 = (OUT / "small_wheel_42rpm_twin_d12_6s.csv", "small wheel, 2.5 mm, 12 mm grains, half box", 12e-3)


def test_with_12_mm_grains_the_effect_goes_on_a_little_slower_per_doubling(script):
    """Outcome (registered before the run): the 12 mm twin slips 0.162 at sinkage / r
    0.209 over the reference's 6.0-8.5 s, 0.086 below the 6 mm twin (registered: goes on if more
    than 0.03 below); per doubling of d the slip falls 0.113 then 0.086."""
    res = script.analyse([D3, D6, D12], REFERENCE, (6.0, 8.5))
    d12 = res["runs"][-1]
    assert d12["windows"] == 5 and abs(d12["drift"]) < 0.02
    assert (d12["slip"], d12["sinkage_over_r"]) == (pytest.approx(0.162, abs=0.001), pytest.approx(0.209, abs=0.001))
    assert res["runs"][1]["slip"] - d12["slip"] > 0.03
    first, second = (s["slip_per_doubling"] for s in res["steps"])
    assert first == pytest.approx(-0.113, abs=0.002) and second == pytest.approx(-0.086, abs=0.002)
    assert first < second < 0  # monotonic, the second doubling takes less


FINE_D6 = (OUT / "wheel_30rpm_nonlocal_treadmill.csv", "2.5 mm, treadmill in 1 m from 2.75 s", 6e-3)
SMALL_PAIR = [
    (OUT / "small_wheel_30rpm_nonlocal_cells_3p5s.csv", "small wheel, 1.25 mm, 0.45 m box, to 3.5 s", 6e-3, 30.0, (3.0, 3.5)),
    (OUT / "small_wheel_60rpm_nonlocal_cells_3s.csv", "small wheel, 1.25 mm, 60 RPM, 0.45 m box, to 3.0 s", 6e-3, 60.0,
     (2.5, 3.0)),
]  # fmt: skip


def test_the_resolved_grid_series_reads_the_large_wheel_and_interpolates_the_small_one(script):
    """The registration: the 2.5 mm large wheel with 6 mm grains (slip 0.128, sinkage / r 0.192
    over 4.5-6.0 s) and the 1.25 mm small wheel at 30 and 60 RPM (0.106 / 0.183 and 0.061 / 0.159)
    interpolated linearly in omega to 42.43 RPM: 0.087 and 0.173."""
    res = script.analyse([D3, D6], None, (6.0, 8.5), [FINE_D6], (4.5, 6.0), SMALL_PAIR)
    (fine,) = res["fine"]
    assert fine["windows"] == 3 and res["fine_steps"] == []
    assert (fine["slip"], fine["sinkage_over_r"]) == (pytest.approx(0.128, abs=0.001), pytest.approx(0.192, abs=0.001))
    si = res["small_interpolated"]
    a, b = si["from"]
    assert (a["slip"], b["slip"]) == (pytest.approx(0.106, abs=0.001), pytest.approx(0.061, abs=0.001))
    f = (42.4264 - 30.0) / 30.0
    assert si["slip"] == pytest.approx(a["slip"] + f * (b["slip"] - a["slip"]), rel=1e-12)
    assert (si["slip"], si["sinkage_over_r"]) == (pytest.approx(0.087, abs=0.001), pytest.approx(0.173, abs=0.001))
    assert si["d_over_r"] == pytest.approx(6e-3 / 0.053, rel=1e-3)


@pytest.mark.parametrize("fine, fine_window, pair, match", [
    ([FINE_D6], None, None, "their window"),
    ([FINE_D6], (6.0, 4.5), None, "must end after"),
    ([FINE_D6, FINE_D6], (4.5, 6.0), None, "its own grain diameter"),
    (None, None, SMALL_PAIR[:1], "two small-wheel runs"),
    (None, None, [SMALL_PAIR[0], SMALL_PAIR[0]], "two small-wheel runs"),
    (None, None, [SMALL_PAIR[0], (*SMALL_PAIR[1][:2], 3e-3, *SMALL_PAIR[1][3:])], "same grain diameter"),
])  # fmt: skip
def test_bad_fine_grid_input_is_refused_with_a_reason(script, fine, fine_window, pair, match):
    from intrusim._checks import InputError

    with pytest.raises(InputError, match=match):
        script.analyse([D3, D6], None, (6.0, 8.5), fine, fine_window, pair)


def test_the_twins_omega_must_be_the_references_omega_over_omega0(script, monkeypatch):
    script._check_twin_rpm(0.106, 0.053)
    monkeypatch.setattr(script, "TWIN_RPM", 40.0)
    from intrusim._checks import InputError

    with pytest.raises(InputError, match="omega / omega_0"):
        script.analyse([D3, D6], None, (6.0, 8.5))


FINE_D12 = (OUT / "wheel_30rpm_nonlocal_d12.csv", "2.5 mm, 12 mm grains, treadmill in 1 m", 12e-3)


def test_on_the_resolved_grid_doubling_d_still_takes_slip_at_0p6x_the_coarse_grids_rate(script):
    """The outcome (registered before the run): the 2.5 mm large wheel with 12 mm grains slips
    0.061 at sinkage / r 0.163 over 4.5-6.0 s, 0.067 below the 6 mm wheel's 0.128 (registered: a steady
    size effect if more than 0.025 below); the coarse twins' 6 -> 12 mm step was -0.086. Against the
    interpolated 1.25 mm small wheel (registered within 0.02 in slip, 0.015 in sinkage / r): the
    sinkage / r met (-0.010), the slip missed (-0.026)."""
    res = script.analyse([D3, D6, D12], None, (6.0, 8.5), [FINE_D12, FINE_D6], (4.5, 6.0), SMALL_PAIR)
    d6, d12 = res["fine"]
    assert d12["windows"] == 3 and abs(d12["drift"]) < 0.01
    assert (d12["slip"], d12["sinkage_over_r"]) == (pytest.approx(0.061, abs=0.001), pytest.approx(0.163, abs=0.001))
    assert d6["slip"] - d12["slip"] > 0.025
    (step,) = res["fine_steps"]
    assert step["slip_per_doubling"] == pytest.approx(-0.067, abs=0.002)
    assert res["steps"][1]["slip_per_doubling"] < step["slip_per_doubling"] < 0  # smaller on the finer grid
    si = res["small_interpolated"]
    assert abs(d12["sinkage_over_r"] - si["sinkage_over_r"]) < 0.015
    assert abs(d12["slip"] - si["slip"]) > 0.02  # (b) missed in slip, as reported


def test_at_the_small_wheels_own_omega_the_12_mm_large_wheel_is_its_twin(script):
    """The second outcome (registered): the 12 mm-grain large wheel at 42.43 RPM over 3.5-4.0 s
    against the 1.25 mm small wheel with 6 mm grains at 60 RPM over 2.5-3.0 s (the same omega / omega_0,
    d / r and h / r): within 0.015 in slip and 0.010 in sinkage / r."""
    big = script.state(OUT / "wheel_42rpm_nonlocal_d12.csv", "2.5 mm, 12 mm grains, 42.43 RPM, treadmill in 1 m", 12e-3,
                       42.4264, 0.106, (3.5, 4.0))  # fmt: skip
    small = script.state(*SMALL_PAIR[1][:3], 60.0, 0.053, (2.5, 3.0))
    assert (big["slip"], big["sinkage_over_r"]) == (pytest.approx(0.048, abs=0.001), pytest.approx(0.156, abs=0.001))
    assert abs(big["slip"] - small["slip"]) < 0.015 and abs(big["sinkage_over_r"] - small["sinkage_over_r"]) < 0.010


def test_at_10_rpm_doubling_d_takes_the_same_slip_and_leaves_the_excess(script):
    """The registered low-omega run, earlier over 5.0-6.0 s: the 12 mm-grain large
    wheel at 10 RPM against the 6 mm one. (a) slip more than 0.03 below 0.246: met (0.174); (b) the
    excess slip over 30 RPM is a length effect below 0.120, not one above 0.161: not (0.174);
    (c), (d) xi-DRFT within 15 % in v and sinkage: both miss the sinkage."""
    big = script.state(OUT / "wheel_10rpm_nonlocal_d12.csv", "2.5 mm, 12 mm grains, 10 RPM, treadmill in 1 m", 12e-3,
                       10.0, 0.106, (5.0, 6.0))  # fmt: skip
    assert big["windows"] == 2 and big["drift"] < 0.05  # settled by the registered rule
    assert (big["velocity"], big["sinkage"], big["slip"]) == (
        pytest.approx(0.0917, abs=2e-4),
        pytest.approx(24.27e-3, abs=0.02e-3),
        pytest.approx(0.174, abs=0.001),
    )
    six = script.state(OUT / "wheel_10rpm_nonlocal_treadmill.csv", "2.5 mm, 10 RPM, treadmill in 1 m", 6e-3, 10.0, 0.106,
                       (5.0, 6.0))  # the 6 mm-grain wheel, an earlier study  # fmt: skip
    six_slip, six_sinkage = six["slip"], six["sinkage"]
    assert (six_slip, six_sinkage) == (pytest.approx(0.246, abs=0.001), pytest.approx(26.93e-3, abs=0.02e-3))
    assert six_slip - big["slip"] > 0.03  # (a)
    assert big["slip"] - 0.061 == pytest.approx(0.113, abs=0.002)  # its excess over its own 30 RPM slip
    assert big["slip"] > 0.061 + 0.100  # (b): not a grain-length effect
    per_doubling = (big["slip"] - six_slip, (big["sinkage"] - six_sinkage) / 0.106)
    assert per_doubling == (pytest.approx(-0.072, abs=0.002), pytest.approx(-0.025, abs=0.002))
    for v, sink, dv, ds in (
        (0.0996, 19.7e-3, 0.086, -0.188),
        (0.1002, 16.57e-3, 0.093, -0.317),
    ):  # (c) xi 1.94, (d) 3.773
        assert v / big["velocity"] - 1 == pytest.approx(dv, abs=0.002)
        assert sink / big["sinkage"] - 1 == pytest.approx(ds, abs=0.002)
        assert abs(ds) > 0.15  # the sinkage misses


def test_carried_to_8_s_the_10_rpm_sinkage_settles_just_outside_xi_drfts_15_percent(script):
    """The registered extension of that run from 6.0 to 8.0 s, read over 7.0-8.0 s: (e) the
    sinkage settles (7.5-8.0 s within 0.2 mm of 7.0-7.5 s: 0.03 mm); (c) xi-DRFT (xi 1.94: 0.0996 m/s,
    19.7 mm) is met if the MPM sinks at most 23.19 mm: it sinks 23.35 mm, so the sinkage misses by 0.6
    points (-15.6 %) and v is within (+8.0 %); the excess slip stays above (b)'s 0.161."""
    label = "2.5 mm, 12 mm grains, 10 RPM, treadmill in 1 m"
    csv = OUT / "wheel_10rpm_nonlocal_d12_to8s.csv"
    late = script.state(csv, label, 12e-3, 10.0, 0.106, (7.0, 8.0))
    halves = [script.state(csv, label, 12e-3, 10.0, 0.106, w) for w in ((7.0, 7.5), (7.5, 8.0))]
    assert late["windows"] == 2 and abs(late["drift"]) < 0.01
    assert abs(halves[1]["sinkage"] - halves[0]["sinkage"]) < 0.2e-3  # (e) settled
    assert (late["velocity"], late["sinkage"], late["slip"]) == (
        pytest.approx(0.0922, abs=2e-4),
        pytest.approx(23.35e-3, abs=0.02e-3),
        pytest.approx(0.170, abs=0.001),
    )
    earlier = script.state(csv, label, 12e-3, 10.0, 0.106, (5.0, 6.0))  # the same run's 5.0-6.0 s, as earlier
    assert earlier["sinkage"] == pytest.approx(24.27e-3, abs=0.02e-3) and earlier["sinkage"] - late["sinkage"] > 0.8e-3
    assert late["sinkage"] > 19.7e-3 / 0.85  # (c) missed, by 0.16 mm of sinkage
    assert 19.7e-3 / late["sinkage"] - 1 == pytest.approx(-0.156, abs=0.002)
    assert 0.0996 / late["velocity"] - 1 == pytest.approx(0.080, abs=0.002)
    assert late["slip"] > 0.061 + 0.100  # (b) unchanged: not a grain-length effect


def test_carried_to_10_s_the_10_rpm_sinkage_eases_slowly_and_sits_on_xi_drfts_15_percent(script):
    """The second registered extension, 8.0 -> 10.0 s, read over 9.0-10.0 s. (e') neither
    settled (the halves differ by 0.22 mm, limit 0.2) nor still easing by the rule (0.17 mm below
    7.0-8.0 s, limit 0.3): the decline slowed from ~0.8 to ~0.09 mm/s. (c') met by the registered
    threshold (23.19 mm) by 0.01 mm; with the DRFT run's unrounded sinkage (19.66 mm) -15.2 %: on the edge."""
    label = "2.5 mm, 12 mm grains, 10 RPM, treadmill in 1 m"
    csv = OUT / "wheel_10rpm_nonlocal_d12_to10s.csv"
    late = script.state(csv, label, 12e-3, 10.0, 0.106, (9.0, 10.0))
    halves = [script.state(csv, label, 12e-3, 10.0, 0.106, w) for w in ((9.0, 9.5), (9.5, 10.0))]
    before = script.state(csv, label, 12e-3, 10.0, 0.106, (7.0, 8.0))
    assert late["windows"] == 2 and abs(late["drift"]) < 0.01
    assert (late["velocity"], late["sinkage"], late["slip"]) == (
        pytest.approx(0.0919, abs=2e-4),
        pytest.approx(23.18e-3, abs=0.02e-3),
        pytest.approx(0.172, abs=0.001),
    )
    assert before["sinkage"] == pytest.approx(23.35e-3, abs=0.02e-3)  # the first extension's reading
    assert abs(halves[1]["sinkage"] - halves[0]["sinkage"]) > 0.2e-3  # (e') not settled by the rule ...
    assert 0 < before["sinkage"] - late["sinkage"] < 0.3e-3  # ... nor still easing by it
    assert late["sinkage"] <= 23.19e-3 and late["velocity"] >= 0.0866  # (c') met by the registered threshold
    assert 19.66e-3 / late["sinkage"] - 1 == pytest.approx(-0.152, abs=0.002)  # unrounded DRFT: just outside
    assert late["slip"] > 0.061 + 0.100  # (b) unchanged


def test_carried_to_14_s_the_10_rpm_sinkage_has_stopped_at_xi_drfts_limit(script):
    """The third registered extension, 10 -> 14 s, read over 13.0-14.0 s: (e'') the easing has
    ended (11-12 s and 13-14 s within 0.2 mm: 0.19 mm); (c'') on the edge (23.30 mm, between the
    registered 22.93 and 23.33). Over 7-14 s (14 windows) the sinkage is 23.22 mm (23.03-23.37):
    xi-DRFT (unrounded 19.66 mm) -15.3 % in sinkage, +8.5 % in v."""
    label = "2.5 mm, 12 mm grains, 10 RPM, treadmill in 1 m"
    csv = OUT / "wheel_10rpm_nonlocal_d12_to14s.csv"
    late = script.state(csv, label, 12e-3, 10.0, 0.106, (13.0, 14.0))
    mid = script.state(csv, label, 12e-3, 10.0, 0.106, (11.0, 12.0))
    plateau = script.state(csv, label, 12e-3, 10.0, 0.106, (7.0, 14.0))
    assert late["windows"] == 2 and plateau["windows"] == 14 and abs(plateau["drift"]) < 0.01
    assert (late["velocity"], late["sinkage"], late["slip"]) == (
        pytest.approx(0.0914, abs=2e-4),
        pytest.approx(23.30e-3, abs=0.02e-3),
        pytest.approx(0.177, abs=0.001),
    )
    assert abs(late["sinkage"] - mid["sinkage"]) < 0.2e-3  # (e'') ended
    assert 22.93e-3 < late["sinkage"] < 23.33e-3  # (c'') on the edge
    assert plateau["sinkage"] == pytest.approx(23.22e-3, abs=0.02e-3)
    assert 19.66e-3 / plateau["sinkage"] - 1 == pytest.approx(-0.153, abs=0.002)  # just outside 15 %
    assert 0.0996 / plateau["velocity"] - 1 == pytest.approx(0.085, abs=0.003)
    assert plateau["slip"] > 0.061 + 0.100  # (b): the low-omega excess slip is not a grain-length effect
