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


def test_relative_difference_interpolates_the_model_at_the_reference_points():
    import numpy as np
    import pytest

    from intrusim._checks import InputError
    from intrusim.analysis.compare import relative_difference

    d = relative_difference([10, 30, 50], [1.0, 3.0, 5.0], [20, 40, 60], [2.0, 5.0, 1.0])
    assert d[0] == pytest.approx(0.0)  # model 2.0 at 20
    assert d[1] == pytest.approx((4.0 - 5.0) / 5.0)
    assert np.isnan(d[2])  # outside the model's range: no extrapolation
    with pytest.raises(InputError):
        relative_difference([1.0], [1.0], [1.0], [1.0])
