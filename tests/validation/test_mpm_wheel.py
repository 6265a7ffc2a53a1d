"""Coupled rigid intruder: a wheel resting on the bed is carried by the contact force, and a
driven grousered wheel (omega < 0) moves forward."""

import numpy as np
import pytest

from intrusim.mpm.config import (
    BedConfig,
    CoupledMotion,
    DomainConfig,
    IntruderConfig,
    MaterialConfig,
    MPMConfig,
    OutputConfig,
    Rectangle,
    TimeConfig,
)
from intrusim.mpm.solver import Solver

R, WIDTH, BED = 0.04, 0.1, 0.1


def wheel_polygon(radius: float, grousers: int = 0, height: float = 0.0, n: int = 48) -> np.ndarray:
    """Disc (n-gon) with optional rectangular-ish grousers, body frame, ccw, m."""
    phi = np.linspace(0, 2 * np.pi, n, endpoint=False)
    r = np.full(n, radius)
    if grousers:
        r[(np.floor(phi / (2 * np.pi) * grousers * 4) % 4) == 0] += height
    return np.column_stack([r * np.cos(phi), r * np.sin(phi)])


def wheel_config(omega: float, mass_z: float, grousers: int, t_end: float, free_x: bool) -> MPMConfig:
    return MPMConfig(
        domain=DomainConfig(size=(0.4, 0.2), cells=(80, 40)),
        material=MaterialConfig(rho_c=638.0, mu_s=0.56, youngs_modulus=1e6),
        bed=BedConfig(rectangles=[Rectangle(x0=0, z0=0, x1=0.4, z1=BED)]),
        intruders=[
            IntruderConfig(
                vertices=wheel_polygon(R, grousers, 0.008).tolist(),
                width=WIDTH,
                mu_w=0.35,
                x=0.12,
                z=BED + R + 0.009,
                motion=CoupledMotion(omega=omega, ramp_time=0.05, mass_x=4 * mass_z, mass_z=mass_z, free_x=free_x),
            )
        ],
        time=TimeConfig(t_end=t_end, v_max_expected=1.0),
        output=OutputConfig(record_every=0.01),
    )


@pytest.fixture(scope="module")
def resting():
    """Time series of a wheel (1 kg per 0.1 m) left to rest on the bed, by contact band (cells; contact "band")."""
    cache: dict[float, list] = {}

    def run(band: float) -> list:
        if band not in cache:
            cfg = wheel_config(omega=0.0, mass_z=1.0, grousers=0, t_end=0.4, free_x=False)
            cache[band] = Solver(cfg.model_copy(update=dict(contact="band", contact_band_cells=band))).run()
        return cache[band]

    return run


def test_resting_wheel_weight_is_carried_by_contact(resting):
    mass_z, g = 1.0, 9.8
    rows = resting(1.0)
    late = [r for r in rows if r["time"] > 0.25]
    fz = np.mean([r["fz"] for r in late])
    assert fz == pytest.approx(mass_z * g, rel=0.1)  # 3D force (N) balances the weight
    assert abs(np.mean([r["vz"] for r in late])) < 0.01
    sinkage = BED - (rows[-1]["z"] - R)
    assert 0 < sinkage < R


def test_contact_band_carries_the_wheel_higher(resting):
    """Nodes up to `band` cells outside the body are in contact, so the body acts larger on the grid:
    a resting wheel sits higher with band 1 than with band 0 (measured: 2.6 and 11.9 mm of sinkage
    with 5 mm cells, i.e. ~1.9 cells), and still carries its weight with band 0."""
    h = 0.4 / 80
    sink = {b: BED - (resting(b)[-1]["z"] - R) for b in (0.0, 1.0)}
    assert sink[0.0] - sink[1.0] > h
    late = [r for r in resting(0.0) if r["time"] > 0.25]
    assert np.mean([r["fz"] for r in late]) == pytest.approx(9.8, rel=0.1)


def test_driven_grousered_wheel_moves_forward():
    solver = Solver(wheel_config(omega=-15.0, mass_z=1.0, grousers=8, t_end=0.35, free_x=True))
    rows = solver.run()
    assert rows[-1]["omega"] == pytest.approx(-15.0)
    assert rows[-1]["x"] - rows[0]["x"] > 0.01  # m forward
    assert np.mean([r["vx"] for r in rows[-10:]]) > 0.05
    assert rows[-1]["theta"] < -2.0  # rad, turned clockwise
