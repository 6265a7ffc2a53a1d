"""The compiled RFT / DRFT element law: the one copy that the force evaluation
(:mod:`intrusim.forces`) and the compiled integrator (:mod:`intrusim._implicit_jit`) both call.

:mod:`intrusim.laws` holds the same equations in readable NumPy form and serves as the test oracle
(``ResistiveForceModel.wrench_numpy``, tests/unit/test_forces.py):

* :func:`element_force`: the force t dA of one submerged, leading element, with
  t = alpha(beta, gamma) |z~| - n lambda rho v_n^2 (paper Eqs. 3-4; ``laws.rft.rft_traction`` and
  ``laws.drft.inertial_traction``), alpha from the Li (2013) Fourier form without trigonometry;
* :func:`rear_surface_drop` and :func:`surface_params`: the structural correction's rear drop
  dh = r psi(r omega^2 / g), psi(x) = offset + slope x (``laws.drft.structural_depth_shift`` with
  the identity or an :class:`~intrusim.laws.drft.AffinePsi`), and the travel sign.
"""

from __future__ import annotations

import numba
import numpy as np


@numba.njit(cache=True)
def alpha_constants(coef: np.ndarray) -> np.ndarray:
    """The Li (2013) Fourier fit (``laws.rft.alpha_fit``) as (2, 9) constants collected by powers of
    cos / sin 2 beta, so that alpha needs no trigonometry per element.

    The fit is a sum over m in {-1, 0, 1}, n in {0, 1} of A, B (alpha_z) and C, D (alpha_x) times
    cos / sin(2 m beta + n gamma), ``coef[k, m + 1, n]``, expanded with the angle-addition formulas.
    With P_m = A[m,0] + A[m,1] cg + B[m,1] sg and Q_m = B[m,0] - A[m,1] sg + B[m,1] cg,
    alpha_z = c2b (P_-1 + P_1) + P_0 + s2b (Q_1 - Q_-1); row 0 holds the factors of alpha_z
    (A, B), row 1 those of alpha_x (C, D), each as [c2b: 1, cg, sg | 1: 1, cg, sg | s2b: 1, cg, sg].
    """
    out = np.empty((2, 9))
    for r in range(2):
        a, b = coef[2 * r], coef[2 * r + 1]
        out[r, 0] = a[0, 0] + a[2, 0]
        out[r, 1] = a[0, 1] + a[2, 1]
        out[r, 2] = b[0, 1] + b[2, 1]
        out[r, 3] = a[1, 0]
        out[r, 4] = a[1, 1]
        out[r, 5] = b[1, 1]
        out[r, 6] = b[2, 0] - b[0, 0]
        out[r, 7] = b[2, 1] - b[0, 1]
        out[r, 8] = a[0, 1] - a[2, 1]
    return out


@numba.njit(cache=True, inline="always")
def fit_rows(k: np.ndarray) -> tuple:
    """The (2, 9) constants of :func:`alpha_constants` as two 9-tuples (alpha_z row, alpha_x row):
    scalars the compiler keeps in registers through an element loop."""
    kz = (k[0, 0], k[0, 1], k[0, 2], k[0, 3], k[0, 4], k[0, 5], k[0, 6], k[0, 7], k[0, 8])
    kx = (k[1, 0], k[1, 1], k[1, 2], k[1, 3], k[1, 4], k[1, 5], k[1, 6], k[1, 7], k[1, 8])
    return kz, kx


@numba.njit(cache=True, inline="always")
def element_force(
    nx: float, nz: float, c2b: float, s2b: float, ux: float, uz: float, vn: float, depth: float,
    kz: tuple, kx: tuple, alpha_scale: float, lam_rho: float, dA: float,
) -> tuple[float, float]:  # fmt: skip
    """(f_x, f_z) = (alpha(beta, gamma) (-depth) - n lam_rho v_n^2) dA of one element (Eq. 4).

    n = (nx, nz) the outward normal, (c2b, s2b) = (n_z^2 - n_x^2, 2 n_x n_z) = cos / sin 2 beta,
    u = (ux, uz) the element velocity, vn = n . u, depth = z~ (< 0 submerged). The caller applies the
    leading-edge rule (vn > 0) and the submersion test (depth < 0). alpha = alpha_scale (alpha_x,
    alpha_z) of the unit-xi fit (kz, kx from :func:`fit_rows`), with cos / sin gamma from the
    velocity and the fit's mirror x -> -x into its range when ux > 0.
    """
    speed = np.sqrt(ux * ux + uz * uz)
    sg = -uz / speed
    cg = abs(ux) / speed
    s2 = -s2b if ux > 0.0 else s2b  # mirrored x -> -x into the fitted range when ux > 0
    az = (c2b * (kz[0] + kz[1] * cg + kz[2] * sg) + (kz[3] + kz[4] * cg + kz[5] * sg)
          + s2 * (kz[6] + kz[7] * cg + kz[8] * sg))  # fmt: skip
    ax = (c2b * (kx[0] + kx[1] * cg + kx[2] * sg) + (kx[3] + kx[4] * cg + kx[5] * sg)
          + s2 * (kx[6] + kx[7] * cg + kx[8] * sg))  # fmt: skip
    ax = -ax if ux > 0.0 else ax
    ex = (alpha_scale * ax * (-depth) - nx * lam_rho * vn * vn) * dA
    ez = (alpha_scale * az * (-depth) - nz * lam_rho * vn * vn) * dA
    return ex, ez


@numba.njit(cache=True)
def rear_surface_drop(radius: float, omega: float, gravity: float, slope: float, offset: float) -> float:
    """dh = r psi(r omega^2 / g), psi(x) = offset + slope x (the identity: slope 1, offset 0), m."""
    return radius * (offset + slope * (radius * omega * omega / gravity))


@numba.njit(cache=True)
def surface_params(fs_kind: int, radius: float, gravity: float, slope: float, offset: float, vx: float, omega: float):
    """(mode, dh, forward sign) of the force kernel, as ``WheelRearHalf.kernel_params``.

    fs_kind 0: flat free surface (mode 0, dh 0); 1 / 2: the wheel's rear half with the "submerged" /
    "effective" split (3: "circle"), dh from :func:`rear_surface_drop`; forward = ``laws.drft.travel_sign``.
    """
    mode, dh, fwd = 0, 0.0, 1.0
    if fs_kind >= 1:
        mode = fs_kind
        dh = rear_surface_drop(radius, omega, gravity, slope, offset)
        if omega != 0.0:  # travel_sign(omega, vx)
            fwd = -1.0 if omega > 0.0 else 1.0
        else:
            fwd = -1.0 if vx < 0.0 else 1.0
    return mode, dh, fwd
