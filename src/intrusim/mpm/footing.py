"""Rough rigid strip footing pushed into a cohesionless bed: bearing capacity against theory.

For a surface strip footing of width B on cohesionless soil of unit weight gamma = rho g the
bearing capacity is q_u = 0.5 gamma B N_gamma (plane strain). The footing here is a rigid
rectangle pushed down at constant speed (a prescribed motion), rough (grain-footing friction
``mu_w``, large by default); q(s) = F_z / B is read against the settlement s, and N_gamma(s) =
q(s) / (0.5 gamma B) with gamma = rho_c g (the bed starts at rho_c).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .config import (
    DEFAULT_CONTACT,
    BedConfig,
    BoundaryConfig,
    DomainConfig,
    IntruderConfig,
    MaterialConfig,
    MPMConfig,
    OutputConfig,
    PrescribedMotion,
    Rectangle,
    TimeConfig,
    WallConfig,
)

# Martin (2005), exact N_gamma of a rough strip footing (method of characteristics, associated flow)
MARTIN_ROUGH = {20.0: 2.839, 25.0: 6.491, 30.0: 14.75, 35.0: 34.48, 40.0: 85.57}


def n_q(phi: float) -> float:
    """Prandtl-Reissner N_q = exp(pi tan phi) tan^2(45 deg + phi / 2), phi in radians."""
    return math.exp(math.pi * math.tan(phi)) * math.tan(math.pi / 4 + phi / 2) ** 2


def n_gamma_hansen(phi: float) -> float:
    """Hansen (1970): N_gamma = 1.5 (N_q - 1) tan phi."""
    return 1.5 * (n_q(phi) - 1.0) * math.tan(phi)


def n_gamma_vesic(phi: float) -> float:
    """Vesic (1973): N_gamma = 2 (N_q + 1) tan phi."""
    return 2.0 * (n_q(phi) + 1.0) * math.tan(phi)


def n_gamma_martin(phi: float) -> float:
    """Martin's (2005) exact rough-footing N_gamma, log-linear between his tabulated angles (5 deg apart)."""
    deg = math.degrees(phi)
    angles = sorted(MARTIN_ROUGH)
    if not angles[0] <= deg <= angles[-1]:
        raise ValueError(f"phi = {deg:.2f} deg lies outside Martin's table {angles[0]}-{angles[-1]} deg")
    return float(np.exp(np.interp(deg, angles, np.log([MARTIN_ROUGH[a] for a in angles]))))


@dataclass
class FootingCase:
    """A rough strip footing of width ``width`` at ``cells_across`` cells across, pushed ``travel`` down."""

    cells_across: int = 10
    width: float = 0.06  # m, B
    thickness_fraction: float = 0.25  # footing thickness / B
    domain_widths: tuple[float, float] = (7.0, 3.5)  # domain (Lx, Lz) / B
    bed_widths: float = 3.0  # bed depth / B
    speed: float = 0.05  # m/s, downward
    travel_fraction: float = 0.1  # settlement pushed, / B
    ramp_fraction: float = 0.01  # ramp time = ramp_fraction B / speed
    mu_s: float = 0.56  # Table S1
    rho: float = 638.0  # kg/m^3, Table S1 rho_c
    mu_w: float = 5.0  # rough footing
    youngs_modulus: float = 1.0e6  # Pa
    cfl: float = 0.3
    dt: float | None = None  # s, None: the stable limit
    contact: str = DEFAULT_CONTACT
    contact_band_cells: float = 1.0
    records: int = 100

    @property
    def h(self) -> float:
        return self.width / self.cells_across

    def config(self, **backend) -> MPMConfig:
        b, h = self.width, self.h
        nx = round(self.domain_widths[0] * self.cells_across)
        nz = round(self.domain_widths[1] * self.cells_across)
        lx, lz = nx * h, nz * h
        bed_top = self.bed_widths * b
        t = self.thickness_fraction * b
        t_end = self.travel_fraction * b / self.speed
        return MPMConfig(
            domain=DomainConfig(size=(lx, lz), cells=(nx, nz)),
            material=MaterialConfig(rho_c=self.rho, mu_s=self.mu_s, youngs_modulus=self.youngs_modulus),
            bed=BedConfig(rectangles=[Rectangle(x0=0.0, z0=0.0, x1=lx, z1=bed_top)]),
            boundaries=BoundaryConfig(floor=WallConfig(kind="sticky")),
            intruders=[
                IntruderConfig(
                    vertices=[(-b / 2, 0.0), (b / 2, 0.0), (b / 2, t), (-b / 2, t)],
                    width=1.0,
                    mu_w=self.mu_w,
                    x=lx / 2,
                    z=bed_top,
                    motion=PrescribedMotion(vz=-self.speed, ramp_time=self.ramp_fraction * b / self.speed),
                )
            ],
            contact=self.contact,
            contact_band_cells=self.contact_band_cells,
            time=TimeConfig(t_end=t_end, cfl=self.cfl, v_max_expected=0.5, dt=self.dt),
            output=OutputConfig(record_every=t_end / self.records),
            backend=backend or {},
        )


def n_gamma_curve(case: FootingCase, rows: list[dict], gravity: float = 9.8) -> tuple[np.ndarray, np.ndarray]:
    """(s / B, N_gamma(s)) from a run's rows: q = F_z / B (the footing's width is 1 m out of plane)."""
    z0 = rows[0]["z"]
    s = np.array([z0 - r["z"] for r in rows[1:]]) / case.width
    q = np.array([r["fz"] for r in rows[1:]]) / case.width
    return s, q / (0.5 * case.rho * gravity * case.width)


def n_gamma_at(case: FootingCase, rows: list[dict], window: tuple[float, float] = (0.04, 0.08)) -> float:
    """Mean N_gamma over a settlement window (s / B)."""
    s, ng = n_gamma_curve(case, rows)
    sel = (s > window[0]) & (s <= window[1])
    return float(np.mean(ng[sel]))
