"""Initial material points of a granular bed and their geostatic stress."""

from __future__ import annotations

import numpy as np
from matplotlib.path import Path as _MplPath

from .config import BedConfig, MaterialConfig


def points_in_polygon(points: np.ndarray, vertices: np.ndarray) -> np.ndarray:
    """Boolean mask of points (N, 2) strictly inside a closed polygon (M, 2)."""
    return _MplPath(np.asarray(vertices, float)).contains_points(points)


def lattice_points(size: tuple[float, float], h: float, ppc: int) -> np.ndarray:
    """Regular ppc x ppc points per cell over the domain, at sub-cell centres (m)."""
    dx = h / ppc
    nx = int(round(size[0] / dx))
    nz = int(round(size[1] / dx))
    xs = (np.arange(nx) + 0.5) * dx
    zs = (np.arange(nz) + 0.5) * dx
    X, Z = np.meshgrid(xs, zs, indexing="ij")
    return np.stack([X.ravel(), Z.ravel()], axis=1)


def bed_mask(points: np.ndarray, bed: BedConfig, exclude: list[np.ndarray]) -> np.ndarray:
    """Points in the union of the bed's rectangles and polygons, outside the excluded polygons."""
    keep = np.zeros(len(points), bool)
    for r in bed.rectangles:
        keep |= (points[:, 0] > r.x0) & (points[:, 0] < r.x1) & (points[:, 1] > r.z0) & (points[:, 1] < r.z1)
    for poly in bed.polygons:
        keep |= points_in_polygon(points, np.asarray(poly))
    for poly in exclude:
        keep &= ~points_in_polygon(points, poly)
    return keep


def k0_value(bed: BedConfig, material: MaterialConfig) -> float:
    """Lateral earth-pressure ratio K0 = sigma_h / sigma_v."""
    if bed.k0 == "elastic":
        nu = material.poisson_ratio
        return nu / (1.0 - nu)  # uniaxial strain of an isotropic elastic solid
    if bed.k0 == "jaky":
        return 1.0 - np.sin(np.arctan(material.mu_s))  # Jaky, friction angle atan(mu_s)
    return float(bed.k0)


def build_bed(
    size: tuple[float, float],
    h: float,
    ppc: int,
    bed: BedConfig,
    material: MaterialConfig,
    gravity: tuple[float, float],
    exclude: list[np.ndarray] | None = None,
) -> dict[str, np.ndarray]:
    """Material points of the bed with mass, area and geostatic stress.

    The vertical stress is sigma_zz = rho g_z d, with d the depth below the top of the material
    in the point's column; sigma_xx = s_yy = K0 sigma_zz. Points are elastically compressed to
    match: rho = rho_0 (1 + P / K_bulk), so that the separation test (rho < rho_c) does not fire
    inside a bed at rest. Loose beds (density_ratio < 1) start stress-free.

    Returns
    -------
    dict with x (N, 2) m, mass (N,) kg/m, vol (N,) m^2, sigma (N, 2, 2) Pa, s_yy (N,) Pa.
    """
    pts = lattice_points(size, h, ppc)
    pts = pts[bed_mask(pts, bed, exclude or [])]
    n = len(pts)
    dx = h / ppc
    rho0 = bed.density_ratio * material.rho_c
    vol = np.full(n, dx * dx)
    sigma = np.zeros((n, 2, 2))
    s_yy = np.zeros(n)
    pressure = np.zeros(n)
    if bed.geostatic and bed.density_ratio >= 1.0 and n:
        col = np.round(pts[:, 0] / dx).astype(np.int64)
        order = np.argsort(col, kind="stable")
        top = np.full(col.max() + 1, -np.inf)
        np.maximum.at(top, col[order], pts[order, 1])
        depth = top[col] + 0.5 * dx - pts[:, 1]
        s_v = rho0 * gravity[1] * depth  # gravity[1] < 0 gives compression
        k0 = k0_value(bed, material)
        sigma[:, 1, 1] = s_v
        sigma[:, 0, 0] = k0 * s_v
        s_yy[:] = k0 * s_v
        pressure = -(1.0 + 2.0 * k0) * s_v / 3.0
    k_bulk = material.lame_lambda + 2.0 * material.shear_modulus / 3.0
    mass = rho0 * (1.0 + pressure / k_bulk) * vol
    return {"x": pts, "mass": mass, "vol": vol, "sigma": sigma, "s_yy": s_yy}
