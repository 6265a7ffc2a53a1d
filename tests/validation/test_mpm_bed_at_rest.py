"""A geostatic bed at rest keeps its mass, holds P = rho g depth and stays still."""

import numpy as np
import pytest

from intrusim.mpm.config import BedConfig, DomainConfig, MaterialConfig, MPMConfig, Rectangle, TimeConfig
from intrusim.mpm.solver import Solver

RHO, G, DEPTH = 900.0, 9.8, 0.10


@pytest.fixture(scope="module")
def settled():
    cfg = MPMConfig(
        domain=DomainConfig(size=(0.2, 0.15), cells=(40, 30)),
        material=MaterialConfig(rho_c=RHO, mu_s=0.56, youngs_modulus=1e6),
        bed=BedConfig(rectangles=[Rectangle(x0=0, z0=0, x1=0.2, z1=DEPTH)]),
        time=TimeConfig(t_end=0.3),
    )
    solver = Solver(cfg)
    mass0 = solver.particle_fields()["mass"].sum()
    rows = solver.run()
    return solver, mass0, rows


def test_mass_is_conserved(settled):
    solver, mass0, rows = settled
    d = solver.particle_fields()
    assert d["mass"].sum() == pytest.approx(mass0, rel=1e-12)
    assert rows[-1]["grain_mass"] == pytest.approx(mass0, rel=1e-6)


def test_vertical_stress_is_hydrostatic(settled):
    solver, _, _ = settled
    d = solver.particle_fields()
    x, z = d["x"][:, 0], d["x"][:, 1]
    h = solver.h
    inner = (x > 0.05) & (x < 0.15)  # away from the side walls
    errors = []
    for top in np.arange(2 * h, DEPTH - 2 * h, h):  # away from the surface and the floor
        band = inner & (z < DEPTH - top) & (z >= DEPTH - top - h)  # one cell high
        depth = DEPTH - z[band]
        ratio = (-d["sigma"][band, 1, 1]).sum() / (RHO * G * depth).sum()
        errors.append(abs(ratio - 1.0))
    assert max(errors) < 0.05, errors
    # pressure P = (1 + 2 K0)/3 rho g depth with the elastic K0 = nu/(1-nu)
    k0 = 0.3 / 0.7
    deep = inner & (z < DEPTH - 2 * h) & (z > 2 * h)
    p_ratio = d["pressure"][deep].sum() / (RHO * G * (DEPTH - z[deep])).sum()
    assert p_ratio == pytest.approx((1 + 2 * k0) / 3, rel=0.05)


def test_bed_stays_still(settled):
    solver, _, rows = settled
    d = solver.particle_fields()
    speed = np.linalg.norm(d["v"], axis=1)
    assert speed.max() < 0.01  # m/s, against sqrt(g depth) ~ 1 m/s
    settle = max(abs(r["kinetic_energy"]) for r in rows)
    assert settle < 1e-3 * rows[-1]["grain_mass"] * G * DEPTH  # KE << potential energy scale
