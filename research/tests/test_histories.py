"""Reading run_histories.py's window and steady tables back (helpers.histories)."""

import math

import pytest
from helpers.histories import read_steady, read_windows, slip, window_mean

from intrusim._checks import InputError

WINDOWS = """run,label,t_start,t_end,velocity,sinkage
a,fast,0.5,1.0,0.30,0.010
b,slow,0.0,0.5,0.05,0.020
a,fast,0.0,0.5,0.10,0.012
a,fast,1.0,1.5,0.50,0.008
"""
STEADY = """run,label,omega,velocity,sinkage,slip,drift
a,fast,3.14159265,0.2,0.01,0.37,0.01
"""


@pytest.fixture
def tables(tmp_path):
    (tmp_path / "w.csv").write_text(WINDOWS)
    (tmp_path / "s.csv").write_text(STEADY)
    return tmp_path / "w.csv", tmp_path / "s.csv"


def test_slip_is_one_minus_v_over_r_omega():
    assert slip(0.0, 30.0, 0.1) == 1.0
    assert slip(0.1 * math.pi, 30.0, 0.1) == pytest.approx(0.0, abs=1e-15)  # r omega = 0.1 pi m/s
    assert slip(0.05 * math.pi, 30.0, 0.1) == pytest.approx(0.5)
    with pytest.raises(InputError, match="radius"):
        slip(0.1, 30.0, 0.0)


def test_windows_of_one_label_in_time_order(tables):
    rows = read_windows(tables[0], "fast")
    assert [r["t_start"] for r in rows] == [0.0, 0.5, 1.0]
    assert rows[1] == {"t_start": 0.5, "t_end": 1.0, "velocity": 0.30, "sinkage": 0.010}


def test_window_mean_over_the_windows_inside(tables):
    rows = read_windows(tables[0], "fast")
    m = window_mean(rows, 0.5, 1.5)
    assert m["windows"] == 2
    assert m["velocity"] == pytest.approx(0.40) and m["sinkage"] == pytest.approx(0.009)
    assert m["drift"] == pytest.approx((0.50 - 0.30) / 0.40)
    assert window_mean(rows, 0.0, 1.5)["velocity"] == pytest.approx(0.30)


def test_steady_row_gives_omega_in_rpm(tables):
    row = read_steady(tables[1], "fast")
    assert row["omega_rpm"] == pytest.approx(30.0)
    assert (row["velocity"], row["sinkage"], row["slip"]) == (0.2, 0.01, 0.37)


def test_bad_input_is_refused_by_name(tables, tmp_path):
    with pytest.raises(InputError, match="no run labelled 'none'"):
        read_windows(tables[0], "none")
    with pytest.raises(InputError, match="no window inside 2.0-3.0 s"):
        window_mean(read_windows(tables[0], "fast"), 2.0, 3.0)
    with pytest.raises(InputError, match="no row labelled"):
        read_steady(tables[1], "slow")
    with pytest.raises(InputError, match="no such file"):
        read_windows(tmp_path / "missing.csv", "fast")
    (tmp_path / "bad.csv").write_text("label,t_start\nfast,0\n")
    with pytest.raises(InputError, match="no t_end, velocity, sinkage column"):
        read_windows(tmp_path / "bad.csv", "fast")
