"""Is the MPM size-similar when all its lengths scale together? The small wheel at 2.5 mm cells
with 3 mm grains in a half box against the Table S1 wheel at 5 mm cells with 6 mm grains
(research/notes/results_log.md, registered before the run).

Runs ``research/similarity_twin.py`` on the committed window CSVs. The registered reading, over the
reference's 3.5-4.5 s (the twin's 2.475-3.182 s): similar if |d slip| <= 0.03 and |d sinkage / r|
<= 0.015; not similar if either is off by more than 0.06 or 0.03; in between, in part.
"""

from pathlib import Path

import pytest

OUT = Path(__file__).resolve().parents[2] / "research" / "outputs"
REFERENCE = (OUT / "wheel_30rpm_nonlocal_treadmill.csv", "5 mm, treadmill in 1 m", 30.0)


@pytest.fixture(scope="module")
def script(load_example):
    return load_example("similarity_twin")


def test_the_verdict_reads_the_registered_thresholds(script):
    assert script.verdict(0.03, -0.015) == "similar"
    assert script.verdict(-0.02, 0.02) == "in part"  # the sinkage alone out of the band
    assert script.verdict(0.061, 0.0) == "not similar"
    assert script.verdict(0.0, -0.031) == "not similar"
    assert script.verdict(0.05, 0.025) == "in part"


def test_the_verdict_reads_other_registered_bands(script):
    """The bands for the steady state (0.008 / 0.004 within, 0.015 / 0.008 past)."""
    bands = dict(similar=(0.008, 0.004), not_similar=(0.015, 0.008))
    assert script.verdict(0.008, -0.004, **bands) == "similar"
    assert script.verdict(0.01, 0.0, **bands) == "in part"
    assert script.verdict(0.0, 0.0081, **bands) == "not similar"
    assert script.verdict(0.01, 0.0) == "similar"  # the same difference under the bands


@pytest.mark.parametrize("similar, not_similar", [((0.02, 0.01), (0.01, 0.02)), ((0.0, 0.01), (0.02, 0.02))])
def test_bands_out_of_order_or_not_positive_are_refused(script, similar, not_similar):
    from intrusim._checks import InputError

    with pytest.raises(InputError, match="bands must be positive"):
        script.verdict(0.0, 0.0, similar, not_similar)
    with pytest.raises(InputError, match="bands must be positive"):  # before the CSVs are read
        script.analyse(REFERENCE, (OUT / "missing.csv", "none", 42.4264), (3.5, 4.5), similar, not_similar)


def test_windows_that_are_not_the_reference_scaled_are_refused(script):
    """The reference's own 0.5 s windows are not its 0.3536 s twin's: the script names the --every to use."""
    rows = script.read_windows(REFERENCE[0], REFERENCE[1])
    assert len(
        script.pair_windows(
            rows, [dict(r, t_start=r["t_start"] * 0.5**0.5, t_end=r["t_end"] * 0.5**0.5) for r in rows], 0.5**0.5
        )
    ) == len(rows)
    with pytest.raises(SystemExit, match="--every 0.35355339"):
        script.pair_windows(rows, rows, 0.5**0.5)


def test_a_twin_at_another_omega_over_omega_0_is_refused(script):
    with pytest.raises(SystemExit, match="42.4264 RPM"):
        script.analyse(REFERENCE, (REFERENCE[0], REFERENCE[1], 30.0), (3.5, 4.5))


TWIN = (OUT / "small_wheel_42rpm_twin.csv", "small wheel, 2.5 mm, 3 mm grains, half box", 42.4264)


def _against_reference(script, name: str, label: str) -> tuple[list[dict], dict]:
    """A half-size twin's committed windows (``name``, run ``label``) against the reference over 3.5-4.5 s."""
    return script.analyse(REFERENCE, (OUT / name, label, 42.4264), (3.5, 4.5))


@pytest.fixture(scope="module")
def twin(script):
    return script.analyse(REFERENCE, TWIN, (3.5, 4.5))


def test_the_twin_reads_in_part_at_the_edge_of_similar(twin):
    """Outcome: over 2.475-3.182 s the twin slips 0.405 at sinkage / r 0.335 (drift
    3.0 %), the reference over 3.5-4.5 s 0.376 and 0.319: slip +0.029 (within 0.03), sinkage / r
    +0.016 (past 0.015 by 0.001): 'in part' by the registered thresholds."""
    rows, res = twin
    ref, tw = res["reference"], res["twin"]
    assert ref["windows"] == tw["windows"] == 2 and abs(tw["drift"]) < 0.05
    assert (ref["slip"], ref["sinkage_over_r"]) == (pytest.approx(0.376, abs=0.001), pytest.approx(0.319, abs=0.001))
    assert (tw["slip"], tw["sinkage_over_r"]) == (pytest.approx(0.405, abs=0.001), pytest.approx(0.335, abs=0.001))
    assert tw["velocity"] == pytest.approx(0.1401, abs=2e-4) and tw["sinkage"] == pytest.approx(17.77e-3, abs=0.02e-3)
    assert res["difference"]["slip"] == pytest.approx(0.029, abs=0.001)
    assert res["difference"]["sinkage_over_r"] == pytest.approx(0.016, abs=0.001)
    assert res["verdict"] == "in part"


def test_the_twin_follows_the_reference_window_by_window_to_2p5_s_then_rides_deeper(twin):
    """Over the reference's 0.5-2.5 s every pair agrees within 0.025 in slip and 0.007 in sinkage / r;
    over 2.5-5.0 s the twin slips 0.006-0.037 more and sinks 0.005-0.019 r deeper."""
    rows, _ = twin
    early = [r for r in rows if 0.5 <= r["t_start"] < 2.5]
    late = [r for r in rows if 2.5 <= r["t_start"] < 5.0]
    assert len(early) == 4 and len(late) == 5
    assert max(abs(r["slip_twin"] - r["slip_reference"]) for r in early) < 0.025
    assert max(abs(r["sinkage_over_r_twin"] - r["sinkage_over_r_reference"]) for r in early) < 0.007
    assert all(0.005 < r["slip_twin"] - r["slip_reference"] < 0.04 for r in late)
    assert all(0.004 < r["sinkage_over_r_twin"] - r["sinkage_over_r_reference"] < 0.02 for r in late)


def test_with_6_mm_grains_the_twin_slips_0p165_less_the_registered_grain_length_effect(script, twin):
    """Outcome (registered before its run): over 2.475-3.182 s the twin with 6 mm grains
    slips 0.240 at sinkage / r 0.247 (v 0.1789 m/s, 13.11 mm), 0.165 below the 3 mm twin's 0.405:
    more than the registered 0.06, so the grain length makes the size effect at 2.5 mm cells too."""
    _, d6 = _against_reference(script, "small_wheel_42rpm_twin_d6.csv", "small wheel, 2.5 mm, 6 mm grains, half box")
    tw = d6["twin"]
    assert tw["windows"] == 2 and abs(tw["drift"]) < 0.05
    assert (tw["slip"], tw["sinkage_over_r"]) == (pytest.approx(0.240, abs=0.001), pytest.approx(0.247, abs=0.001))
    assert twin[1]["twin"]["slip"] - tw["slip"] == pytest.approx(0.165, abs=0.002)
    assert twin[1]["twin"]["slip"] - tw["slip"] > 0.06
    assert d6["verdict"] == "not similar"


SET_UP_MADE_IT = (0.01, 0.005)  # registered: |d slip|, |d sinkage / r| over 2.475-3.182 s


@pytest.fixture(scope="module")
def scaled(script):
    return _against_reference(
        script, "small_wheel_42rpm_twin_scaled.csv", "small wheel, 2.5 mm, 3 mm grains, half box, set-up scaled"
    )


@pytest.fixture(scope="module")
def e_only(script):
    return _against_reference(
        script, "small_wheel_42rpm_twin_E.csv", "small wheel, 2.5 mm, 3 mm grains, half box, E scaled"
    )


def test_with_its_set_up_scaled_the_twin_is_the_reference_replica(scaled):
    """Outcome (registered before its run): with the start, E, spin-up and run-control
    interval scaled too, over 2.475-3.182 s the twin slips 0.377 at sinkage / r 0.320 against 0.376
    and 0.319 (within the registered 0.01 and 0.005: the set-up made the first twin's residual), and
    every 0.3536 s window to the reference's 4.5 s agrees within 0.0015 in slip and sinkage / r."""
    rows, res = scaled
    tw, d = res["twin"], res["difference"]
    assert tw["windows"] == 2 and abs(tw["drift"]) < 0.05
    assert (tw["slip"], tw["sinkage_over_r"]) == (pytest.approx(0.377, abs=0.001), pytest.approx(0.320, abs=0.001))
    assert abs(d["slip"]) <= SET_UP_MADE_IT[0] and abs(d["sinkage_over_r"]) <= SET_UP_MADE_IT[1]
    assert abs(d["slip"]) < 0.002 and abs(d["sinkage_over_r"]) < 0.002
    assert res["verdict"] == "similar"
    upto = [r for r in rows if r["t_end"] <= 4.5 + 1e-6]
    assert len(upto) == 9
    assert max(abs(r["slip_twin"] - r["slip_reference"]) for r in upto) < 0.0015
    assert max(abs(r["sinkage_over_r_twin"] - r["sinkage_over_r_reference"]) for r in upto) < 0.0015


def _within(a: dict, b: dict, band: tuple[float, float]) -> bool:
    return abs(a["slip"] - b["slip"]) <= band[0] and abs(a["sinkage_over_r"] - b["sinkage_over_r"]) <= band[1]


def test_the_stiffness_alone_made_the_first_twins_residual(twin, scaled, e_only):
    """Outcome (registered before its run): the first twin with only E scaled (0.5 MPa)
    slips 0.376 at sinkage / r 0.319 over 2.475-3.182 s: within the registered 0.01 and 0.005 of the
    scaled twin (0.377, 0.320), not of the first twin (0.405, 0.335): the stiffness made it."""
    rows, res = e_only
    tw, first = res["twin"], twin[1]["twin"]
    assert tw["windows"] == 2 and abs(tw["drift"]) < 0.05
    assert (tw["slip"], tw["sinkage_over_r"]) == (pytest.approx(0.376, abs=0.001), pytest.approx(0.319, abs=0.001))
    assert _within(tw, scaled[1]["twin"], SET_UP_MADE_IT)
    assert first["slip"] - tw["slip"] > 0.02 and first["sinkage_over_r"] - tw["sinkage_over_r"] > 0.01
    # the unscaled start and spin-up show in the first window only
    assert rows[0]["slip_twin"] - rows[0]["slip_reference"] > 0.02
    assert all(abs(r["slip_twin"] - r["slip_reference"]) < 0.005 for r in rows[2:9])


def test_the_stiffness_not_the_time_step(script, twin, e_only):
    """Outcome (registered before its run): the E-only twin at the first twin's dt
    (C = 0.2121) slips 0.371 at sinkage / r 0.316 over 2.475-3.182 s: within the registered 0.01
    and 0.005 of the E-only twin (0.376, 0.319), 0.034 and 0.019 from the first twin (0.405, 0.335)."""
    _, res = _against_reference(
        script,
        "small_wheel_42rpm_twin_E_dt.csv",
        "small wheel, 2.5 mm, 3 mm grains, half box, E scaled, first twin's dt",
    )
    tw, first = res["twin"], twin[1]["twin"]
    assert tw["windows"] == 2 and abs(tw["drift"]) < 0.05
    assert (tw["slip"], tw["sinkage_over_r"]) == (pytest.approx(0.371, abs=0.001), pytest.approx(0.316, abs=0.001))
    assert _within(tw, e_only[1]["twin"], SET_UP_MADE_IT)
    assert first["slip"] - tw["slip"] > 0.03 and first["sinkage_over_r"] - tw["sinkage_over_r"] > 0.015


def test_a_softer_bed_slips_more_too(script, e_only, twin):
    """Outcome (registered before its run): at half the reference's E / (rho_c g r)
    (E 0.25 MPa) the twin slips 0.399 at sinkage / r 0.335 over 2.475-3.182 s: above the registered
    0.357 (not log-linear), so both halving and doubling the stiffness add slip (+0.022, +0.029),
    and the soft twin is still easing over its last windows, like the first twin."""
    rows, res = _against_reference(
        script, "small_wheel_42rpm_twin_E_soft.csv", "small wheel, 2.5 mm, 3 mm grains, half box, E 0.25 MPa"
    )
    tw = res["twin"]
    assert tw["windows"] == 2
    assert (tw["slip"], tw["sinkage_over_r"]) == (pytest.approx(0.399, abs=0.001), pytest.approx(0.335, abs=0.001))
    assert tw["slip"] > 0.357  # the registered "fades on the soft side" bound
    assert (
        tw["slip"] - e_only[1]["twin"]["slip"] > 0.015 and twin[1]["twin"]["slip"] - e_only[1]["twin"]["slip"] > 0.015
    )
    late = [r["slip_twin"] for r in rows if r["t_start"] >= 2.0 - 1e-6 and r["t_end"] <= 4.5 + 1e-6]  # whole windows
    assert late[0] - late[-1] > 0.03  # still easing from 2.0 to 4.5 s (reference time)


STEADY_BANDS = dict(similar=(0.008, 0.004), not_similar=(0.015, 0.008))  # registered.0-8.5 s


def _late(script, name: str, label: str) -> tuple[list[dict], dict]:
    """A twin carried to 6.05 s (``*_6s.csv``, whole windows only) against the reference over 6.0-8.5 s."""
    return script.analyse(REFERENCE, (OUT / name, label, 42.4264), (6.0, 8.5), **STEADY_BANDS)


@pytest.fixture(scope="module")
def late_soft(script):
    return _late(
        script, "small_wheel_42rpm_twin_E_soft_6s.csv", "small wheel, 2.5 mm, 3 mm grains, half box, E 0.25 MPa"
    )


@pytest.fixture(scope="module")
def late_first(script):
    return _late(script, "small_wheel_42rpm_twin_6s.csv", "small wheel, 2.5 mm, 3 mm grains, half box")


def test_the_softer_bed_carried_to_6_s_comes_back_to_the_reference(late_soft):
    """Outcome (registered before the run): over the reference's 6.0-8.5 s the E 0.25 MPa
    twin slips 0.360 at sinkage / r 0.309 against 0.356 and 0.304: in part (slip within 0.008,
    sinkage / r 0.001 past 0.004); it falls faster than the reference and crosses it by 8.0-8.5 s."""
    rows, res = late_soft
    tw, d = res["twin"], res["difference"]
    assert tw["windows"] == 5 and rows[-1]["t_end"] == pytest.approx(8.5, abs=1e-6)  # no partial window
    assert (tw["slip"], tw["sinkage_over_r"]) == (pytest.approx(0.360, abs=0.001), pytest.approx(0.309, abs=0.001))
    assert abs(d["slip"]) <= 0.008 and 0.004 < d["sinkage_over_r"] <= 0.008
    assert res["verdict"] == "in part"
    gap = {round(r["t_start"], 3): r["slip_twin"] - r["slip_reference"] for r in rows}
    assert gap[2.0] > 0.025 and gap[5.5] > 0.02 and gap[8.0] < 0.0  # the transient, then the crossing


def test_the_first_twin_carried_to_6_s_comes_back_to_the_reference_too(late_first):
    """Outcome (registered before the run): over the reference's 6.0-8.5 s the E 1 MPa
    twin slips 0.361 at sinkage / r 0.310 against 0.356 and 0.304: in part (slip within 0.008,
    sinkage / r 0.001 past 0.004); its gap to the reference closes from +0.038 of slip at 3.5-4.0 s."""
    rows, res = late_first
    tw, d = res["twin"], res["difference"]
    assert tw["windows"] == 5 and rows[-1]["t_end"] == pytest.approx(8.5, abs=1e-6)
    assert (tw["slip"], tw["sinkage_over_r"]) == (pytest.approx(0.361, abs=0.001), pytest.approx(0.310, abs=0.001))
    assert abs(d["slip"]) <= 0.008 and 0.004 < d["sinkage_over_r"] <= 0.008
    assert res["verdict"] == "in part"
    gap = {round(r["t_start"], 3): r["slip_twin"] - r["slip_reference"] for r in rows}
    assert gap[3.5] > 0.03 and gap[5.5] > 0.008 and abs(gap[8.0]) < 0.003  # the transient closes


def test_the_e_scaled_twin_stays_a_replica_to_8p5_s_and_e_leaves_no_steady_effect(script, late_first, late_soft):
    """Outcome (registered before the run): over the reference's 6.0-8.5 s the E-scaled
    twin slips 0.358 at sinkage / r 0.305 against 0.356 and 0.304 (within the registered 0.005 and
    0.003: still a replica), and the E 1 MPa and E 0.25 MPa twins come within 0.0031 in slip and
    0.0051 in sinkage / r of it: E / (rho_c g r) lengthened the transient, not the steady state."""
    rows, res = _late(script, "small_wheel_42rpm_twin_E_6s.csv", "small wheel, 2.5 mm, 3 mm grains, half box, E scaled")
    tw, d = res["twin"], res["difference"]
    assert tw["windows"] == 5 and rows[-1]["t_end"] == pytest.approx(8.5, abs=1e-6)
    assert (tw["slip"], tw["sinkage_over_r"]) == (pytest.approx(0.358, abs=0.001), pytest.approx(0.305, abs=0.001))
    assert abs(d["slip"]) <= 0.005 and abs(d["sinkage_over_r"]) <= 0.003  # the registered replica band
    late = [r for r in rows if r["t_start"] >= 4.5 - 1e-6]
    assert max(abs(r["slip_twin"] - r["slip_reference"]) for r in late) < 0.007
    for other in (late_first[1]["twin"], late_soft[1]["twin"]):
        assert (
            abs(other["slip"] - tw["slip"]) <= 0.0035 and abs(other["sinkage_over_r"] - tw["sinkage_over_r"]) <= 0.0055
        )


def test_the_6_mm_twin_carried_to_6_s_holds_a_steady_grain_length_effect(script, late_first):
    """Outcome (registered before the run): over the reference's 6.0-8.5 s the 6 mm
    twin slips 0.248 at sinkage / r 0.246 against the 3 mm first twin's 0.361 and 0.310: 0.113 and
    0.064 below, past the registered 0.06 and 0.03, so d / r is a steady size effect; the 6 mm
    twin has held 0.235-0.261 over the reference's 3.5-8.5 s while the 3 mm twin eased."""
    rows, res = script.analyse(
        REFERENCE,
        (OUT / "small_wheel_42rpm_twin_d6_6s.csv", "small wheel, 2.5 mm, 6 mm grains, half box", 42.4264),
        (6.0, 8.5),
    )
    tw, first = res["twin"], late_first[1]["twin"]
    assert tw["windows"] == 5 and rows[-1]["t_end"] == pytest.approx(8.5, abs=1e-6) and abs(tw["drift"]) < 0.05
    assert (tw["slip"], tw["sinkage_over_r"]) == (pytest.approx(0.248, abs=0.001), pytest.approx(0.246, abs=0.001))
    d_slip, d_sink = tw["slip"] - first["slip"], tw["sinkage_over_r"] - first["sinkage_over_r"]
    assert (d_slip, d_sink) == (pytest.approx(-0.113, abs=0.002), pytest.approx(-0.064, abs=0.002))
    assert script.verdict(d_slip, d_sink) == "not similar"  # the registered bands: 0.03 / 0.015, 0.06 / 0.03
    held = [r["slip_twin"] for r in rows if r["t_start"] >= 3.5 - 1e-6]
    assert len(held) == 10 and 0.23 < min(held) and max(held) < 0.265
    assert res["difference"]["slip"] == pytest.approx(-0.108, abs=0.002)  # against the large wheel, same grains
