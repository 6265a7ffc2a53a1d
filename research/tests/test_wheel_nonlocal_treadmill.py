"""The free Table S1 wheel with the nonlocal fluidity, run long on the moving window (treadmill)
(research/notes/results_log.md, "Where the 1.25 mm difference comes from", item 11).

The committed histories and steady states (``research/run_histories.py --steady-from``) are
checked against what the docs state.
"""

import csv
from pathlib import Path

import pytest

OUT = Path(__file__).resolve().parents[2] / "research" / "outputs"
LONG = "5 mm, 2.5 m box"
TREADMILLS = ("5 mm, treadmill in 0.8 m", "5 mm, treadmill in 1 m")
FINE = "2.5 mm, treadmill in 1 m from 2.75 s"


def _rows(name):
    with (OUT / name).open(newline="") as f:
        return list(csv.DictReader(f))


def _steady(name):
    return {r["label"]: {k: float(v) for k, v in r.items() if k not in ("run", "label")} for r in _rows(name)}


@pytest.fixture(scope="module")
def history(figure_history):
    return figure_history("wheel_30rpm_nonlocal_treadmill.csv")


def _drft(omega_rpm):
    """The paper's DRFT (lambda 1, rho 638, the paper's dh law) at this omega: (v m/s, sinkage m)."""
    for r in _rows("fig5ab_band0_settled.csv"):
        if r["curve"] == "DRFT" and float(r["omega_rpm"]) == omega_rpm:
            return float(r["velocity_m_s"]), float(r["sinkage_m"])
    raise KeyError(omega_rpm)


def test_the_treadmill_gives_the_long_box_wheel_within_its_measured_error(history):
    """5 mm cells, 10 s: both treadmills against the 2.5 m box, every 0.5 s window: v within
    2.4 % (largest: -2.35 %, 1 m box, 8.5-9 s), sinkage within 1.35 mm (largest +1.31 mm, 0.8 m box)."""
    ts = history.windows(LONG)
    assert len(ts) == 20
    worst_v, worst_s = 0.0, 0.0
    for label in TREADMILLS:
        assert history.windows(label) == ts
        for t in ts:
            (v0, s0), (v1, s1) = history[(LONG, t)], history[(label, t)]
            worst_v, worst_s = max(worst_v, abs(v1 / v0 - 1)), max(worst_s, abs(s1 - s0))
    assert worst_v < 0.024 and worst_s < 1.35e-3
    assert worst_v > 0.015 and worst_s > 1.0e-3  # the error is there, and the docs say how large


def test_at_5_mm_the_wheel_still_climbs_after_10_s_and_2_m(history):
    """The 2.5 m box: the sinkage falls in 17 of the 18 windows after 1 s, by 7.0 mm over 1-10 s, and
    still 0.3 mm in the last second."""
    s = [history[(LONG, t)][1] for t in history.windows(LONG, 1.0)]
    assert sum(b < a for a, b in zip(s, s[1:])) >= 16
    assert s[0] - s[-1] == pytest.approx(7.0e-3, abs=0.2e-3)
    assert s[-3] - s[-1] > 0.2e-3


def test_at_2p5_mm_the_wheel_settles_on_the_treadmill(history):
    """2.5 mm: from 4.5 s on, v moves < 0.5 % and the sinkage < 0.2 mm per 0.5 s window; over
    4.5-6.0 s v 0.2905 m/s, sinkage 20.4 mm, slip 0.128, rear drop 3.0 mm (the identity psi: 11.3)."""
    ts = history.windows(FINE, 4.5)
    assert ts == [4.5, 5.0, 5.5]
    for a, b in zip(ts, ts[1:]):
        (va, sa), (vb, sb) = history[(FINE, a)], history[(FINE, b)]
        assert abs(vb / va - 1) < 0.005 and abs(sb - sa) < 0.2e-3
    st = _steady("wheel_30rpm_nonlocal_treadmill_steady.csv")[FINE]
    assert st["window_start"] == pytest.approx(4.5, abs=0.01) and st["window_end"] == pytest.approx(6.0, abs=0.02)
    assert st["velocity"] == pytest.approx(0.2905, abs=5e-4)
    assert st["sinkage"] == pytest.approx(20.4e-3, abs=0.1e-3)
    assert st["slip"] == pytest.approx(0.128, abs=0.002)
    assert st["surface_drop"] == pytest.approx(3.0e-3, abs=0.1e-3)


def test_the_papers_drft_misses_the_settled_nonlocal_wheel_at_30_rpm():
    """DRFT at 30 RPM (0.252 m/s, 42.2 mm) against the settled 2.5 mm wheel: v -13 %, sinkage +107 %."""
    st = _steady("wheel_30rpm_nonlocal_treadmill_steady.csv")[FINE]
    v, sink = _drft(30.0)
    assert v / st["velocity"] - 1 == pytest.approx(-0.133, abs=0.005)
    assert sink / st["sinkage"] - 1 == pytest.approx(1.07, abs=0.02)


def test_at_90_rpm_the_nonlocal_wheel_neither_plateaus_nor_sinks_deeper(figure_history):
    """90 RPM, 2.5 mm, to 5.5 s: v rises and the sinkage falls in every 0.25 s window after 1 s, by
    < 0.5 % and < 0.5 mm per window at the end; over 4.5-5.5 s v 0.890 m/s, sinkage 19.0 mm,
    slip 0.109, rear drop 3.7 mm: 3.07x the settled 30 RPM speed, a smaller slip and no deeper
    sinkage (no plateau, no sinkage growth); DRFT (0.70 m/s, 43.3 mm): v -21 %, sinkage +128 %."""
    h = figure_history("wheel_90rpm_nonlocal_treadmill.csv")
    label = "2.5 mm, treadmill in 1 m from 1.5 s"
    ts = h.windows(label, 1.0)
    assert ts[-1] == 5.25
    v = [h[(label, t)][0] for t in ts]
    s = [h[(label, t)][1] for t in ts]
    assert all(b > a for a, b in zip(v, v[1:])) and all(b < a for a, b in zip(s, s[1:]))
    assert v[-1] / v[-2] - 1 < 0.005 and s[-2] - s[-1] < 0.5e-3
    st = _steady("wheel_90rpm_nonlocal_treadmill_steady.csv")[label]
    assert st["window_start"] == pytest.approx(4.5, abs=0.01) and st["window_end"] == pytest.approx(5.5, abs=0.02)
    assert st["velocity"] == pytest.approx(0.890, abs=1e-3) and st["sinkage"] == pytest.approx(19.0e-3, abs=0.1e-3)
    assert st["slip"] == pytest.approx(0.109, abs=0.002) and st["surface_drop"] == pytest.approx(3.7e-3, abs=0.1e-3)
    st30 = _steady("wheel_30rpm_nonlocal_treadmill_steady.csv")[FINE]
    assert st["velocity"] / st30["velocity"] == pytest.approx(3.07, abs=0.02)
    assert st["slip"] < st30["slip"] and st["sinkage"] < st30["sinkage"]
    v_drft, s_drft = _drft(90.0)
    assert v_drft / st["velocity"] - 1 == pytest.approx(-0.21, abs=0.01)
    assert s_drft / st["sinkage"] - 1 == pytest.approx(1.28, abs=0.02)


def test_the_nonlocal_wheels_sit_on_the_slip_sinkage_curve_of_the_papers_law():
    """The quadratic sinkage / r = c0 + c1 s + c2 s^2 fitted on 19 runs with the paper's law
    (slip_dependence.json, committed before these runs) gives the nonlocal wheels' sinkage from their
    slip within -4.8 to +1.4 %: 2.5 mm at 30 and 90 RPM, and the three 5 mm runs over 5-10 s."""
    import json

    c0, c1, c2 = json.loads((OUT / "slip_dependence.json").read_text())["slip_sinkage_c0_c1_c2"]
    r = 0.10604  # m, the Table S1 wheel's outer radius (grouser tips)
    steady = {
        **_steady("wheel_30rpm_nonlocal_treadmill_steady.csv"),
        "90 RPM": _steady("wheel_90rpm_nonlocal_treadmill_steady.csv")["2.5 mm, treadmill in 1 m from 1.5 s"],
    }
    misses = {}
    for label in (LONG, *TREADMILLS, FINE, "90 RPM"):
        st = steady[label]
        s = st["slip"]
        misses[label] = st["sinkage"] / (r * (c0 + c1 * s + c2 * s * s)) - 1
    assert all(-0.05 < m < 0.015 for m in misses.values()), misses
    assert min(misses.values()) < -0.04  # the 90 RPM wheel, -4.8 %


def test_the_registered_1p25_mm_outcome_on_the_treadmill(history):
    """Registered (1e0f4c0) before the 1.25 mm run was extended: in the 0.5 s windows 2.0-2.5 and
    2.5-3.0 s the 1.25 mm wheel is faster and shallower than the 2.5 mm one by 0.15-0.40 of the
    5 -> 2.5 mm step (the 5 mm run in the 2.5 m box), written as v 0.281-0.299 and 0.291-0.310 m/s,
    sinkage 19.2-23.2 and 17.3-21.5 mm (1 mm added to the sinkage's upper edges for the treadmill).
    Outcome: met in 2.0-2.5 s (ratios 0.22 in v, 0.18 in sinkage); in 2.5-3.0 s on the lower edge:
    v 0.29097 m/s, 0.00003 below the range as written (rounded) but at a ratio of 0.1504, and the
    sinkage inside its range only through the treadmill's 1 mm (ratio 0.128)."""
    fine = "1.25 mm, treadmill in 0.8 m from 1.75 s"
    assert history.windows(fine, 2.0) == [2.0, 2.5]
    (v5, s5), (v2, s2), (v1, s1) = (history[(lab, 2.0)] for lab in (LONG, FINE, fine))
    assert 0.281 <= v1 <= 0.299 and 19.2e-3 <= s1 <= 23.2e-3
    assert (v1 - v2) / (v2 - v5) == pytest.approx(0.22, abs=0.005) and (s1 - s2) / (s2 - s5) == pytest.approx(
        0.18, abs=0.005
    )
    (v5, s5), (v2, s2), (v1, s1) = (history[(lab, 2.5)] for lab in (LONG, FINE, fine))
    assert 0.291 - 5e-5 < v1 < 0.291 and 17.3e-3 <= s1 <= 21.5e-3  # v just below the written edge
    assert 0.150 <= (v1 - v2) / (v2 - v5) < 0.151  # and just inside the ratio
    assert (s1 - s2) / (s2 - s5) == pytest.approx(0.128, abs=0.002)  # below 0.15: the 1 mm allowance
    assert s1 > s2 - 0.15 * (s5 - s2)  # i.e. without it the sinkage would have missed (too deep)
