"""Fit of the paper's plate-drag law F = K |z| + lambda rho A v^2 (Fig 6A, Fig S2-S3)."""

from __future__ import annotations

import numpy as np

from intrusim._checks import InputError, positive


def fit_static_plus_inertial(
    depths: np.ndarray, speeds: np.ndarray, force: np.ndarray, rho: float, area: float
) -> tuple[float, float]:
    """Least-squares (K, lambda) of F = K |z| + lambda rho A v^2 over a (depth, speed) grid.

    Parameters
    ----------
    depths : (n,) m; speeds : (k,) m/s; force : (n, k) N; rho : kg/m^3; area : m^2.

    Returns
    -------
    K in N/m, lambda (dimensionless).
    """
    d = np.abs(np.asarray(depths, float))
    v = np.asarray(speeds, float)
    f = np.asarray(force, float)
    if f.shape != (len(d), len(v)):
        raise InputError(f"force must have shape ({len(d)}, {len(v)}), got {f.shape}")
    rho, area = positive("rho", rho), positive("area", area)
    D, V = np.meshgrid(d, v, indexing="ij")
    return fit_drag_law(D.ravel(), V.ravel(), f.ravel(), rho, area)


def fit_drag_law(
    depth: np.ndarray, speed: np.ndarray, force: np.ndarray, rho: float, area: float
) -> tuple[float, float]:
    """Least-squares (K, lambda) of F = K |z| + lambda rho A v^2 over scattered samples.

    Parameters
    ----------
    depth : (n,) |z|, m.   speed : (n,) m/s.   force : (n,) N (or N/m per unit width).
    rho : kg/m^3.   area : m^2 (or m per unit width).

    Returns
    -------
    K in N/m (or N/m per metre of width), lambda (dimensionless).
    """
    d, v, f = (np.asarray(a, float).ravel() for a in (depth, speed, force))
    if not (len(d) == len(v) == len(f)) or len(d) < 2:
        raise InputError(f"need >= 2 samples of equal length, got {len(d)}, {len(v)}, {len(f)}")
    a = np.column_stack([np.abs(d), rho * area * v**2])
    (K, lam), *_ = np.linalg.lstsq(a, f, rcond=None)
    return float(K), float(lam)
