"""Shared fixtures of the research tests (not collected by the default run: ``python -m pytest research/tests``)."""

import csv
import importlib.util
import math
import sys
from pathlib import Path

import pytest

RESEARCH = Path(__file__).resolve().parents[1]
ROOT = RESEARCH.parent
OUTPUTS = RESEARCH / "outputs"  # what the scripts wrote (research/outputs/README.md)

if str(RESEARCH) not in sys.path:  # the scripts import their helpers as ``helpers.*``
    sys.path.insert(0, str(RESEARCH))


@pytest.fixture(scope="session")
def load_example():
    """Import ``research/NAME.py`` as a module (the research scripts are not a package)."""

    def load(name: str):
        spec = importlib.util.spec_from_file_location(name, RESEARCH / f"{name}.py")
        mod = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(mod)
        return mod

    return load


class History(dict):
    """A CSV of ``research/run_histories.py``: {(label, window start s): (mean v m/s, mean sinkage m)}."""

    def windows(self, label: str, t_from: float = 0.0, t_to: float = math.inf) -> list[float]:
        """The window starts of one run (label) in [t_from, t_to), in order."""
        return sorted(t for (lab, t) in self if lab == label and t_from <= t < t_to)


@pytest.fixture(scope="session")
def figure_history():
    """Read ``research/outputs/NAME`` (a run_histories.py CSV) as a :class:`History`."""

    def read(name: str) -> History:
        with (OUTPUTS / name).open(newline="") as f:
            return History(
                {
                    (r["label"], round(float(r["t_start"]), 3)): (float(r["velocity"]), float(r["sinkage"]))
                    for r in csv.DictReader(f)
                }
            )

    return read
