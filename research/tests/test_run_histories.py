"""``research/run_histories.py``: a run's last window, when the run ends inside it, is partial;
it is named on stderr, and ``--whole-only`` leaves it out (the 3.2 s twins' last
0.3536 s window held 0.018 s of the run)."""

from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest


@pytest.fixture
def script(load_example, monkeypatch):
    mod = load_example("run_histories")
    t = np.arange(0.0, 1.0 + 1e-9, 0.01)  # records every 0.01 s to 1.0 s
    series = {"time": t, "vx": 0.1 + 0.0 * t, "sinkage": 0.02 + 0.0 * t}
    monkeypatch.setattr(mod, "summarise_run", lambda run_dir, t_start: SimpleNamespace(series=series))
    return mod


def test_a_partial_last_window_is_named(script, capsys):
    rows = script.windows(Path("run"), 0.3)
    assert [round(r["t_end"], 6) for r in rows] == [0.3, 0.6, 0.9, 1.2]
    assert "the last window, 0.9-1.2 s, is partial (the run ends at 1 s)" in capsys.readouterr().err


def test_whole_only_keeps_the_windows_the_run_covers(script, capsys):
    rows = script.windows(Path("run"), 0.3, whole_only=True)
    assert [round(r["t_end"], 6) for r in rows] == [0.3, 0.6, 0.9]
    assert capsys.readouterr().err == ""


def test_windows_that_fit_exactly_give_no_warning(script, capsys):
    assert len(script.windows(Path("run"), 0.25)) == 4
    assert capsys.readouterr().err == ""


def test_the_warning_and_whole_only_read_one_criterion(script, capsys):
    """A last window that ends within one record interval (0.01 s) of the last record is whole for
    both: no warning, and --whole-only keeps it (windows of 0.3345 s: the third ends at 1.0035 s)."""
    rows = script.windows(Path("run"), 0.3345)
    assert capsys.readouterr().err == ""
    assert rows == script.windows(Path("run"), 0.3345, whole_only=True) and len(rows) == 3


def test_until_keeps_the_windows_that_end_by_then(script):
    rows = script.windows(Path("run"), 0.3, until=0.6)
    assert [round(r["t_end"], 6) for r in rows] == [0.3, 0.6]
