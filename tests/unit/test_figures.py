"""Figure writers: PNG + CSV, non-dimensional columns consistent with the SI ones."""

import csv
import math

import pytest

from intrusim.figures.rft import fig7bc


def test_fig7bc_quick_csv_is_nondimensionalised(tmp_path):
    png, path = fig7bc(tmp_path, quick=True, parallel=False)
    assert png.stat().st_size > 1000
    rows = list(csv.DictReader(path.open()))
    assert {r["lambda"] for r in rows} == {"0.0", "2.0", "4.0"} and len(rows) == 15
    for r in rows:
        length = float(r["length_scale_m"])
        assert length == 0.19
        assert float(r["v_over_sqrt_gl"]) == pytest.approx(float(r["velocity_m_s"]) / math.sqrt(9.8 * length))
        assert float(r["sinkage_over_l"]) == pytest.approx(float(r["sinkage_m"]) / length)
        assert float(r["omega_over_omega0"]) == pytest.approx(
            float(r["omega_rpm"]) * 2 * math.pi / 60 / math.sqrt(9.8 / length)
        )


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


def test_vertical_plate_lambda_recovers_a_synthetic_static_plus_inertial_law():
    import numpy as np
    import pytest

    from intrusim.figures.mpm_plates import static_plus_inertial_lambda

    rho, area, lam = 2500.0, 0.16, 2.8
    depth = np.linspace(-0.005, 0.08, 200)
    static = 2e5 * np.clip(depth, 0, None) + 3e3 * np.sin(40 * depth)  # any static curve
    series = [
        {"speed_m_s": v, "depth_m": list(depth), "force_N_per_m": list(static + lam * rho * area * v**2)}
        for v in (0.1, 0.5, 1.0, 2.0)
    ]
    # the slowest run is taken as static, so its own v^2 part is subtracted from the others
    got, grid, f_static = static_plus_inertial_lambda(series, rho, area, min_depth=0.01)
    expected = lam * sum((v**2 - 0.01) * v**2 for v in (0.5, 1.0, 2.0)) / sum(v**4 for v in (0.5, 1.0, 2.0))
    assert got == pytest.approx(expected, rel=1e-9)
    assert grid[0] == pytest.approx(0.01) and len(f_static) == len(grid)
