"""research/plate_node_entry.py: the drop measure (formula) and one coarse run end to end."""

import importlib.util
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from intrusim._checks import InputError

SCRIPT = Path(__file__).resolve().parents[1] / "plate_node_entry.py"
spec = importlib.util.spec_from_file_location("plate_node_entry", SCRIPT)
pne = importlib.util.module_from_spec(spec)
spec.loader.exec_module(pne)


def test_the_deepest_drop_is_measured_below_the_window_median_and_only_in_the_window():
    t = np.linspace(0.0, 1.0, 11)
    alpha = np.array([0.0, 50.0, 100, 100, 100, 100, 100, 100, 80, 100, 100])  # the start's low values are outside
    assert pne.deepest_drop(t, alpha, (0.5, 1.0)) == pytest.approx(0.2)
    with pytest.raises(InputError, match="no records"):
        pne.deepest_drop(t, alpha, (1.0, 1.0))


def test_a_plate_is_beta_comma_gamma():
    assert pne.plate("-60,30") == (-60.0, 30.0)
    assert pne.plates("0,90 -60,30") == [(0.0, 90.0), (-60.0, 30.0)]
    with pytest.raises(Exception, match="BETA,GAMMA"):
        pne.plate("60")


def test_one_coarse_run_writes_its_table_and_plot(tmp_path):
    out = tmp_path / "pne"
    r = subprocess.run([sys.executable, str(SCRIPT), "--cell-mm", "10", "--cfl", "0.3", "--contacts", "nodes",
                        "--out", str(out)], capture_output=True, text=True, timeout=600)  # fmt: skip
    assert r.returncode == 0, r.stderr
    rows = (out.with_suffix(".csv")).read_text().splitlines()
    assert len(rows) == 2 and rows[0].startswith("contact,cell_mm,cfl,beta_deg,gamma_deg,alpha_x,alpha_z")
    assert float(rows[1].split(",")[6]) > 0  # pushed down: resisted upwards
    assert out.with_suffix(".png").stat().st_size > 0
