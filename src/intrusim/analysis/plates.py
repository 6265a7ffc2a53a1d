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
    a = np.column_stack([D.ravel(), rho * area * V.ravel() ** 2])
    (K, lam), *_ = np.linalg.lstsq(a, f.ravel(), rcond=None)
    return float(K), float(lam)
