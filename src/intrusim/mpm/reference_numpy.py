"""Vectorised NumPy version of one MPM step (no intruders): the benchmark baseline and a
consistency check of the Taichi kernels. Same algorithm and ordering as ``Solver.step``:
P2G (APIC/MLS), grid momentum + gravity, walls, G2P, density, stress update.
"""

from __future__ import annotations

import numpy as np

from .constitutive import drucker_prager_update_numpy

WALL_CODES = {"frictionless": 0, "sticky": 1, "coulomb": 2}


def _weights(x: np.ndarray, h: float, pad: int, shape: tuple[int, int]):
    X = x / h + pad
    base = np.floor(X - 0.5).astype(np.int64)
    base[:, 0] = np.clip(base[:, 0], 0, shape[0] - 3)
    base[:, 1] = np.clip(base[:, 1], 0, shape[1] - 3)
    fx = X - base
    w = np.stack([0.5 * (1.5 - fx) ** 2, 0.75 - (fx - 1.0) ** 2, 0.5 * (fx - 0.5) ** 2])  # (3, N, 2)
    return base, fx, w


def _wall(v: np.ndarray, n: np.ndarray, kind: int, mu: float) -> np.ndarray:
    if kind == 1:
        return np.zeros_like(v)
    mu = mu if kind == 2 else 0.0
    vn = v @ n
    vt = v - vn[:, None] * n
    vt_norm = np.linalg.norm(vt, axis=1)
    scale = np.where(vt_norm > -mu * vn, 1.0 + mu * vn / np.where(vt_norm > 0, vt_norm, 1.0), 0.0)
    return np.where((vn < 0)[:, None], vt * scale[:, None], v)


def numpy_step(
    state: dict[str, np.ndarray],
    h: float,
    pad: int,
    shape: tuple[int, int],
    lx: float,
    dt: float,
    gravity: tuple[float, float],
    prm: tuple[float, ...],
    walls: tuple[tuple[int, float], ...],
    rho_floor: float,
) -> None:
    """Advance ``state`` (dict of particle arrays as in :data:`particles.FIELDS`) by dt in place.

    Parameters
    ----------
    h : grid spacing, m. pad : padding cells. shape : grid node counts.
    lx : domain width, m. dt : s. gravity : m/s^2. prm : material parameters (G, lam, mu_s, rho_c).
    walls : ((kind, mu) for left, right, floor) with kind codes of :data:`WALL_CODES`.
    rho_floor : lowest point density, kg/m^3 (the volume stops growing at m / rho_floor).
    """
    x, v, C = state["x"], state["v"], state["C"]
    mass, vol, sigma = state["mass"], state["vol"], state["sigma"]
    n0, n1 = shape
    base, fx, w = _weights(x, h, pad, shape)
    affine = mass[:, None, None] * C - (dt * vol * 4.0 / h**2)[:, None, None] * sigma
    gm = np.zeros(n0 * n1)
    gp = np.zeros((n0 * n1, 2))
    for i in range(3):
        for j in range(3):
            dpos = (np.array([i, j]) - fx) * h
            weight = w[i][:, 0] * w[j][:, 1]
            idx = (base[:, 0] + i) * n1 + base[:, 1] + j
            mom = weight[:, None] * (mass[:, None] * v + np.einsum("nab,nb->na", affine, dpos))
            gm += np.bincount(idx, weight * mass, minlength=n0 * n1)
            gp[:, 0] += np.bincount(idx, mom[:, 0], minlength=n0 * n1)
            gp[:, 1] += np.bincount(idx, mom[:, 1], minlength=n0 * n1)
    has = gm > 0
    gv = np.zeros_like(gp)
    gv[has] = gp[has] / gm[has, None] + dt * np.asarray(gravity)
    ii, jj = np.divmod(np.arange(n0 * n1), n1)
    xi, zj = (ii - pad) * h, (jj - pad) * h
    for mask, normal, (kind, mu) in (
        (xi <= 0.0, (1.0, 0.0), walls[0]),
        (xi >= lx - 1e-6 * h, (-1.0, 0.0), walls[1]),
        (zj <= 0.0, (0.0, 1.0), walls[2]),
    ):
        sel = mask & has
        gv[sel] = _wall(gv[sel], np.asarray(normal), kind, mu)
    new_v = np.zeros_like(v)
    new_C = np.zeros_like(C)
    for i in range(3):
        for j in range(3):
            dpos = (np.array([i, j]) - fx) * h
            weight = w[i][:, 0] * w[j][:, 1]
            g = gv[(base[:, 0] + i) * n1 + base[:, 1] + j]
            new_v += weight[:, None] * g
            new_C += (4.0 / h**2) * weight[:, None, None] * g[:, :, None] * dpos[:, None, :]
    state["v"] = new_v
    state["C"] = new_C
    state["x"] = x + dt * new_v
    state["vol"] = np.minimum(vol * np.exp(dt * (new_C[:, 0, 0] + new_C[:, 1, 1])), mass / rho_floor)
    sig, syy, dgamma = drucker_prager_update_numpy(sigma, state["s_yy"], new_C, mass / state["vol"], dt, prm)
    state["sigma"], state["s_yy"] = sig, syy
    state["eps_p"] = state["eps_p"] + dgamma
    state["gdot_p"] = dgamma / dt
