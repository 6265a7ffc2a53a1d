"""Plate drag (paper Fig 6) and vertical plate intrusion (Fig S3B) drivers and the drag-law fit.

Choices (see docs/mpm.md): forces are per unit width (N/m, plane strain, ``width = 1 m``), so
F = K |z| + lambda rho A v^2 with A = plate length (m^2 per metre of width) and K in N/m per
metre of width; |z| is the depth of the plate centre below the initial free surface.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from intrusim.analysis.plates import fit_drag_law  # noqa: F401  (re-exported: the Fig 6 fit)

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
    TransferConfig,
    WallConfig,
)


def plate_polygon(length: float, thickness: float, vertical: bool = True) -> list[tuple[float, float]]:
    """Rectangle centred on the body origin, ccw; ``vertical``: long side along z, m."""
    a, b = (thickness / 2, length / 2) if vertical else (length / 2, thickness / 2)
    return [(-a, -b), (a, -b), (a, b), (-a, b)]


@dataclass
class PlateDragCase:
    """One horizontal drag run: a vertical plate of ``length`` dragged in +x at ``speed``."""

    depth: float  # m, plate centre below the free surface
    speed: float  # m/s
    plate_length: float = 0.016  # m
    plate_thickness: float = 0.004  # m
    travel: float = 0.08  # m, distance dragged
    start_x: float = 0.05  # m
    bed_height: float = 0.10  # m
    domain: tuple[float, float] = (0.30, 0.15)  # m
    cells: tuple[int, int] = (120, 60)
    rho: float = 900.0  # kg/m^3, rho_c = initial density
    mu_s: float = 0.56
    mu_w: float = 0.35  # plate-grain friction (not given for Fig 6; the wheel value)
    youngs_modulus: float = 1.0e6  # Pa
    ramp_fraction: float = 0.25  # ramp time = ramp_fraction * plate_length / speed
    contact: str = DEFAULT_CONTACT  # MPMConfig.contact (docs/mpm.md)
    contact_band_cells: float = 1.0  # contact "band": nodes this close outside the plate are in contact
    cfl: float = 0.3  # C in dt = C h sqrt(rho / E) (TimeConfig.cfl)
    flip: float | None = None  # FLIP's share of the velocity update (TransferConfig.flip; None: the default; 0: APIC)
    shape: str = "quadratic"  # shape functions of the transfers (TransferConfig.shape)

    def config(self, directory: str | None = None, **backend) -> MPMConfig:
        t_end = self.travel / self.speed
        z_surface = self.bed_height
        return MPMConfig(
            domain=DomainConfig(size=self.domain, cells=self.cells),
            material=MaterialConfig(rho_c=self.rho, mu_s=self.mu_s, youngs_modulus=self.youngs_modulus),
            bed=BedConfig(rectangles=[Rectangle(x0=0, z0=0, x1=self.domain[0], z1=self.bed_height)]),
            boundaries=BoundaryConfig(floor=WallConfig(kind="sticky")),
            intruders=[
                IntruderConfig(
                    vertices=plate_polygon(self.plate_length, self.plate_thickness),
                    width=1.0,
                    mu_w=self.mu_w,
                    x=self.start_x,
                    z=z_surface - self.depth,
                    motion=PrescribedMotion(
                        vx=self.speed, ramp_time=self.ramp_fraction * self.plate_length / self.speed
                    ),
                )
            ],
            contact=self.contact,
            contact_band_cells=self.contact_band_cells,
            time=TimeConfig(t_end=t_end, cfl=self.cfl, v_max_expected=max(self.speed, 0.5)),
            transfer=TransferConfig(flip=self.flip, shape=self.shape),
            output=OutputConfig(directory=directory, record_every=t_end / 100),
            backend=backend or {},
        )


@dataclass
class VerticalPlateCase:
    """Vertical intrusion (Fig S3B): a horizontal plate of ``length`` pushed down at ``speed``."""

    speed: float  # m/s
    plate_length: float = 0.16  # m
    plate_thickness: float = 0.01  # m
    travel: float = 0.08  # m
    bed_height: float = 0.25  # m
    domain: tuple[float, float] = (0.8, 0.4)  # m
    cells: tuple[int, int] = (160, 80)
    rho: float = 2500.0  # kg/m^3 (printed as the granular volume density)
    mu_s: float = 0.62
    mu_w: float = 0.35
    youngs_modulus: float = 1.0e6  # Pa, as every other case (lambda depends strongly on E here: docs/mpm.md)
    ramp_fraction: float = 0.05

    def config(self, directory: str | None = None, **backend) -> MPMConfig:
        t_end = self.travel / self.speed
        return MPMConfig(
            domain=DomainConfig(size=self.domain, cells=self.cells),
            material=MaterialConfig(rho_c=self.rho, mu_s=self.mu_s, youngs_modulus=self.youngs_modulus),
            bed=BedConfig(rectangles=[Rectangle(x0=0, z0=0, x1=self.domain[0], z1=self.bed_height)]),
            intruders=[
                IntruderConfig(
                    vertices=plate_polygon(self.plate_length, self.plate_thickness, vertical=False),
                    width=1.0,
                    mu_w=self.mu_w,
                    x=self.domain[0] / 2,
                    z=self.bed_height + self.plate_thickness / 2 + 0.5 * self.domain[0] / self.cells[0],
                    motion=PrescribedMotion(
                        vz=-self.speed, ramp_time=self.ramp_fraction * self.plate_length / self.speed
                    ),
                )
            ],
            time=TimeConfig(t_end=t_end, v_max_expected=max(self.speed, 0.5)),
            output=OutputConfig(directory=directory, record_every=t_end / 100),
            backend=backend or {},
        )


def window_mask(t: np.ndarray, window: tuple[float, float]) -> np.ndarray:
    """The records whose time lies in the fraction ``window`` of the run, (w0 t_end, w1 t_end]."""
    return (t > window[0] * t[-1]) & (t <= window[1] * t[-1])


def steady_force(rows: list[dict], key: str = "fx", window: tuple[float, float] = (0.5, 1.0)) -> float:
    """Mean of ``key`` over a fraction window of the recorded run (forces in N, here N/m)."""
    t = np.array([r["time"] for r in rows])
    f = np.array([r[key] for r in rows])
    return float(np.mean(f[window_mask(t, window)]))
