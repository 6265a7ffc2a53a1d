"""Is it the grain size? The 1.25 mm small wheel at 60 RPM with 3 mm grains against 6 mm grains
(research/notes/results_log.md, registered in b119ed1 before the run).

Runs ``research/grain_size_pair.py`` on the committed window CSVs. The registered reading, over
1.5-2.0 s: the grain length explains the size effect if the 3 mm wheel slips >= 0.11 and sinks
>= 9.9 mm; it does not if slip <= 0.095 and sinkage <= 9.6 mm; in between, in part.
"""

from pathlib import Path

import pytest

from intrusim._checks import InputError

OUT = Path(__file__).resolve().parents[2] / "research" / "outputs"
D6 = (OUT / "small_wheel_60rpm_nonlocal_cells_3p5s.csv", "small wheel, 1.25 mm, 60 RPM, 0.45 m box, to 3.5 s", 6e-3)
LARGE = [
    (OUT / "wheel_30rpm_nonlocal_treadmill_steady.csv", "2.5 mm, treadmill in 1 m from 2.75 s"),
    (OUT / "wheel_60rpm_nonlocal_treadmill_steady.csv", "2.5 mm, treadmill in 1 m"),
]


@pytest.fixture(scope="module")
def script(load_example):
    return load_example("grain_size_pair")


def test_the_verdict_reads_the_registered_thresholds(script):
    assert script.verdict({"slip": 0.11, "sinkage": 9.9e-3}) == "in full"
    assert script.verdict({"slip": 0.20, "sinkage": 9.8e-3}) == "in part"  # slip alone is not enough
    assert script.verdict({"slip": 0.095, "sinkage": 9.6e-3}) == "not at all"
    assert script.verdict({"slip": 0.10, "sinkage": 9.0e-3}) == "in part"


def test_the_6_mm_run_against_itself_changes_nothing_and_reads_not_at_all(script):
    """The 6 mm run's window (v 0.3036 m/s, sinkage 9.23 mm, slip 0.088) is below the 'not at all'
    thresholds: the test could have failed only through the 3 mm run."""
    _, res = script.analyse([D6, D6], LARGE, 60.0, (1.5, 2.0))
    first = res["runs"][0]
    assert first["windows"] == 2 and abs(first["drift"]) < 0.05
    assert first["velocity"] == pytest.approx(0.3036, abs=2e-4) and first["sinkage"] == pytest.approx(
        9.23e-3, abs=0.02e-3
    )
    assert first["slip"] == pytest.approx(0.088, abs=0.001)
    assert res["change"] == {"slip": 0.0, "sinkage": 0.0, "velocity": 0.0}
    assert res["verdict"] == "not at all"
    large = res["large_wheel"]
    assert large["omega_rpm"] == pytest.approx(42.43, abs=0.01)
    assert (large["slip"], large["sinkage_over_r"]) == (
        pytest.approx(0.117, abs=0.002),
        pytest.approx(0.187, abs=0.002),
    )
    assert large["grain_over_r"] == pytest.approx(0.057, abs=0.001) and first["grain_over_r"] == pytest.approx(
        0.113, abs=0.001
    )


def test_a_window_past_the_run_is_refused(script):
    with pytest.raises(InputError, match="no window inside"):
        script.analyse([D6, D6], LARGE, 60.0, (3.5, 4.0))


D3 = (OUT / "small_wheel_60rpm_nonlocal_d3mm.csv", "small wheel, 1.25 mm, 60 RPM, 0.45 m box, 3 mm grains", 3e-3)


@pytest.fixture(scope="module")
def pair(script):
    """The comparison of the 6 mm and 3 mm runs over the registered window 1.5-2.0 s."""
    return script.analyse([D6, D3], LARGE, 60.0, (1.5, 2.0))[1]


def test_halving_the_grain_doubles_the_slip_past_the_registered_threshold(pair):
    """Outcome: over 1.5-2.0 s (drift 3.0 %) the 3 mm wheel: v 0.2654 m/s, sinkage
    12.05 mm, slip 0.203; the 6 mm wheel 0.3036 m/s, 9.23 mm, 0.088: 'in full' by the registered
    thresholds, and past the large wheel's steady state (slip 0.117, sinkage / r 0.187)."""
    d3 = pair["runs"][1]
    assert d3["windows"] == 2 and abs(d3["drift"]) < 0.05
    assert d3["velocity"] == pytest.approx(0.2654, abs=2e-4) and d3["sinkage"] == pytest.approx(12.05e-3, abs=0.02e-3)
    assert d3["slip"] == pytest.approx(0.203, abs=0.002)
    assert pair["verdict"] == "in full"
    assert pair["change"]["slip"] == pytest.approx(0.115, abs=0.002)
    assert d3["slip"] > pair["large_wheel"]["slip"] and d3["sinkage_over_r"] > pair["large_wheel"]["sinkage_over_r"]


def test_the_3_mm_wheel_is_still_easing_and_xi_drft_misses_its_sinkage(pair, figure_history):
    """The 0.25 s windows from 1.5 s: v 0.2615 -> 0.2694 m/s, sinkage 12.35 -> 11.75 mm. xi-DRFT
    (0.2982 m/s, 9.86 mm): v +12.4 %, sinkage -18.2 %; the paper's DRFT (0.2780 m/s, 20.05 mm) +4.7 % / +66 %."""
    h = figure_history(D3[0].name)
    ts = h.windows(D3[1], 1.5, 2.0)
    (v0, s0), (v1, s1) = h[D3[1], ts[0]], h[D3[1], ts[1]]
    assert v1 > v0 and s1 < s0
    d3 = pair["runs"][1]
    assert 0.2982 / d3["velocity"] - 1 == pytest.approx(0.124, abs=0.003)
    assert 9.86e-3 / d3["sinkage"] - 1 == pytest.approx(-0.182, abs=0.003)
    assert 20.05e-3 / d3["sinkage"] - 1 == pytest.approx(0.66, abs=0.01)
