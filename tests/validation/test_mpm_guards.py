"""Guards stop the run with a diagnosis and a failure checkpoint."""

import numpy as np
import pytest

from intrusim.mpm.config import BedConfig, DomainConfig, MPMConfig, OutputConfig, Rectangle, TimeConfig
from intrusim.mpm.diagnostics import SimulationError
from intrusim.mpm.solver import Solver


def _solver(tmp_path):
    cfg = MPMConfig(
        domain=DomainConfig(size=(0.1, 0.1), cells=(10, 10)),
        bed=BedConfig(rectangles=[Rectangle(x0=0, z0=0, x1=0.1, z1=0.05)]),
        time=TimeConfig(t_end=0.01),
        output=OutputConfig(directory=str(tmp_path), guard_every_steps=1),
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
