"""The free Table S1 wheel with the nonlocal fluidity at 5, 2.5 and 1.25 mm cells
(research/notes/results_log.md, "Where the 1.25 mm difference comes from", item 10).

The committed histories (``research/run_histories.py`` over the run folders, 0.25 s windows) are
checked against what the docs state, the registered 1.25 mm outcome included.
"""

import pytest

CELLS = {"5 mm cells": 5.0, "2.5 mm cells": 2.5, "1.25 mm cells, 0.8 m box": 1.25}
REGISTERED = (1.0, 1.25, 1.5)  # window starts of the registered prediction, s


@pytest.fixture(scope="module")
def history(figure_history):
    return figure_history("wheel_30rpm_nonlocal_cells.csv")


def test_the_shorter_box_leaves_the_wheel_as_it_was(history):
    """5 mm cells: the 0.8 m box gives the 1 m box's v within 0.5 % and sinkage within 0.1 mm to 2 s."""
    ts = history.windows("5 mm cells, 0.8 m box", t_to=2.0)
    assert len(ts) == 8
    for t in ts:
        (v1, s1), (v8, s8) = history[("5 mm cells", t)], history[("5 mm cells, 0.8 m box", t)]
        assert v8 == pytest.approx(v1, rel=0.005) and abs(s8 - s1) < 1e-4


def test_from_5_to_2p5_mm_the_wheel_runs_faster_and_shallower(history):
    ts = history.windows("2.5 mm cells", t_from=0.5)
    assert len(ts) >= 8
    for t in ts:
        (v5, s5), (v2, s2) = history[("5 mm cells", t)], history[("2.5 mm cells", t)]
        assert v2 > 1.1 * v5 and s2 < s5 - 4e-3


def test_the_registered_1p25_mm_outcome_met_in_one_window_of_three(history):
    """Registered before the 1.25 mm run finished: in each window from 1.0 to 1.75 s the 1.25 mm
    wheel is faster and shallower than the 2.5 mm one by 0.3-0.9 of the 5 -> 2.5 mm step.
    Outcome: the direction holds in all three, the size (0.33) in the first only; after it the
    change is 0.26-0.29 of the step, a little below the registered range, and falling."""
    fine = "1.25 mm cells, 0.8 m box"
    assert history.windows(fine, t_from=1.0) == list(REGISTERED)
    ratios = []
    for t in REGISTERED:
        (v5, s5), (v2, s2), (v1, s1) = (history[(lab, t)] for lab in CELLS)
        assert v1 > v2 > v5 and s1 < s2 < s5
        ratios.append([(v1 - v2) / (v2 - v5), (s1 - s2) / (s2 - s5)])
    met = [all(0.3 <= r <= 0.9 for r in pair) for pair in ratios]
    assert met == [True, False, False]
    assert all(0.25 < r < 0.3 for pair in ratios[1:] for r in pair)


def test_at_90_rpm_the_nonlocal_wheel_climbs_where_the_papers_law_digs_in(figure_history):
    """2.5 mm cells, band 0, over 0.5-1.5 s: with the nonlocal law v rises and the sinkage falls in
    every 0.25 s window; with the paper's law (wheel_band0_settling.csv) v falls and the wheel sinks."""

    def series(name, label):
        h = figure_history(name)
        v, s = zip(*(h[(label, t)] for t in h.windows(label, t_from=0.5, t_to=1.5)))
        return list(v), list(s)

    v, s = series("wheel_90rpm_nonlocal.csv", "90 RPM, 2.5 mm cells")
    vp, sp = series("wheel_band0_settling.csv", "90 RPM")
    assert len(v) == len(vp) == 4
    assert all(b > a for a, b in zip(v, v[1:])) and all(b < a for a, b in zip(s, s[1:]))
    assert all(b < a for a, b in zip(vp, vp[1:])) and all(b > a for a, b in zip(sp, sp[1:]))
    assert min(v) > 1.5 * max(vp) and max(s) < min(sp)
