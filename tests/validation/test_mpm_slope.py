"""A block on a Coulomb floor under tilted gravity slides only when tan(slope) > mu_floor."""

import math

import pytest

from intrusim.mpm.config import (
    BedConfig,
    BoundaryConfig,
    DomainConfig,
    MaterialConfig,
    MPMConfig,
    Rectangle,
    TimeConfig,
    WallConfig,
)
from intrusim.mpm.solver import Solver

MU_FLOOR, G, T = 0.4, 9.8, 0.2


def run_block(tan_slope: float) -> tuple[float, float]:
    a = math.atan(tan_slope)
    cfg = MPMConfig(
        domain=DomainConfig(size=(0.4, 0.1), cells=(40, 10)),
        material=MaterialConfig(rho_c=1000.0, mu_s=3.0, youngs_modulus=1e6),  # block does not yield
        bed=BedConfig(rectangles=[Rectangle(x0=0.1, z0=0, x1=0.2, z1=0.04)]),
        boundaries=BoundaryConfig(floor=WallConfig(kind="coulomb", mu=MU_FLOOR)),
        gravity=(G * math.sin(a), -G * math.cos(a)),
        time=TimeConfig(t_end=T),
    )
    solver = Solver(cfg)
    x0 = solver.particle_fields()["x"][:, 0].mean()
    solver.run()
    d = solver.particle_fields()
    return d["x"][:, 0].mean() - x0, d["v"][:, 0].mean()


@pytest.mark.parametrize("tan_slope", [0.5 * MU_FLOOR, 1.5 * MU_FLOOR])
def test_block_slides_only_beyond_friction(tan_slope):
    dx, vx = run_block(tan_slope)
    a = math.atan(tan_slope)
    acc = G * (math.sin(a) - MU_FLOOR * math.cos(a))
    if acc <= 0:
        assert abs(dx) < 1e-3 and abs(vx) < 0.01  # sticks (free slide would move 0.2 m/s^2-ish)
    else:
        assert vx == pytest.approx(acc * T, rel=0.15)
        assert dx == pytest.approx(0.5 * acc * T**2, rel=0.2)
