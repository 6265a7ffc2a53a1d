"""Guards stop the run with a diagnosis and a failure checkpoint."""

import numpy as np
import pytest

from intrusim.mpm.config import BedConfig, DomainConfig, MPMConfig, OutputConfig, Rectangle, TimeConfig
from intrusim.mpm.diagnostics import SimulationError
from intrusim.mpm.solver import Solver


def _solver(tmp_path, p2g_chunks: int = 16):
    cfg = MPMConfig(
        domain=DomainConfig(size=(0.1, 0.1), cells=(10, 10)),
        bed=BedConfig(rectangles=[Rectangle(x0=0, z0=0, x1=0.1, z1=0.05)]),
        time=TimeConfig(t_end=0.01),
        output=OutputConfig(directory=str(tmp_path), guard_every_steps=1),
        backend=dict(p2g_chunks=p2g_chunks),
    )
    return Solver(cfg)


def test_nan_is_reported_with_place_and_time(tmp_path):
    s = _solver(tmp_path)
    d = s.particles.to_numpy(["v"])
    d["v"][5] = np.nan
    s.particles.load(d)
    with pytest.raises(SimulationError, match=r"NaN.*point.*t=.*step 1"):
        s.run()
    assert (tmp_path / "checkpoint_failure.npz").exists()


@pytest.mark.parametrize("p2g_chunks", [16, 1])  # chunked float sums; one copy, fixed-point atomic sums (a GPU's)
@pytest.mark.parametrize("field", ["v", "C", "sigma"])
def test_a_nan_is_reported_at_the_point_that_carries_it(tmp_path, field, p2g_chunks):
    # integer sums carry no NaN: with fixed-point P2G the point itself is marked, so the guard names
    # it rather than the escape of its neighbours that garbage sums would cause
    s = _solver(tmp_path, p2g_chunks)
    assert (s.fixed_scale is not None) == (p2g_chunks == 1)
    d = s.particles.to_numpy([field])
    d[field][5] = np.nan
    s.particles.load(d)
    # float sums spread the NaN over the grid to the neighbours (any of them is named); integer sums
    # cannot, and the point itself is the one named
    where = r"1 points, e\.g\. point 5 " if p2g_chunks == 1 else r"\d+ points, e\.g\. point \d+ "
    with pytest.raises(SimulationError, match=r"NaN/inf in particle state: " + where + r".*step 1"):
        s.run()


def test_cfl_breach_is_reported(tmp_path):
    s = _solver(tmp_path)
    d = s.particles.to_numpy(["v"])
    d["v"][:, 1] = 0.9 * s.h / s.dt  # far above max_cell_fraction * h / dt
    s.particles.load(d)
    with pytest.raises(SimulationError, match="CFL breach|escape"):
        s.run()


def test_escape_is_reported(tmp_path):
    s = _solver(tmp_path)
    d = s.particles.to_numpy(["x"])
    d["x"][3] = (0.05, 0.5)  # above the open top
    s.particles.load(d)
    with pytest.raises(SimulationError, match="escape.*point 3"):
        s.run()
