"""Figure writers: PNG + CSV, non-dimensional columns consistent with the SI ones."""

import csv
import math

import pytest

from intrusim.figures import fig7bc


def test_fig7bc_quick_csv_is_nondimensionalised(tmp_path):
    png, path = fig7bc(tmp_path, quick=True, parallel=False)
    assert png.stat().st_size > 1000
    rows = list(csv.DictReader(path.open()))
    assert {r["lambda"] for r in rows} == {"0.0", "2.0", "4.0"} and len(rows) == 15
    for r in rows:
        l = float(r["length_scale_m"])
        assert l == 0.19
        assert float(r["v_over_sqrt_gl"]) == pytest.approx(float(r["velocity_m_s"]) / math.sqrt(9.8 * l))
        assert float(r["sinkage_over_l"]) == pytest.approx(float(r["sinkage_m"]) / l)
        assert float(r["omega_over_omega0"]) == pytest.approx(float(r["omega_rpm"]) * 2 * math.pi / 60 / math.sqrt(9.8 / l))
