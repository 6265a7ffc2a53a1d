"""Material below rho_c is disconnected: it carries no stress and falls freely."""

import numpy as np
import pytest

from intrusim.mpm.config import BedConfig, DomainConfig, MaterialConfig, MPMConfig, Rectangle, TimeConfig
from intrusim.mpm.solver import Solver


def test_loose_patch_is_stress_free_and_falls_freely():
    t_end, g = 0.1, 9.8
    cfg = MPMConfig(
        domain=DomainConfig(size=(0.2, 0.2), cells=(20, 20)),
        material=MaterialConfig(rho_c=900.0),
        bed=BedConfig(rectangles=[Rectangle(x0=0.06, z0=0.12, x1=0.14, z1=0.18)], density_ratio=0.8),
        time=TimeConfig(t_end=t_end),
    )
    solver = Solver(cfg)
    z0 = solver.particle_fields()["x"][:, 1].mean()
    max_stress = 0.0
    for _ in range(5):
        solver.run(t_end=solver.t + t_end / 5)
        d = solver.particle_fields()
        max_stress = max(max_stress, np.abs(d["sigma"]).max(), np.abs(d["s_yy"]).max())
    assert max_stress == 0.0
    drop = z0 - d["x"][:, 1].mean()
    assert drop == pytest.approx(0.5 * g * solver.t**2, rel=0.02)
    assert np.all(d["density"] < 900.0)
