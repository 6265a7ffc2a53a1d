"""Drucker-Prager granular continuum with free separation (SPEC 1, Eq. 1-2).

State per material point (plane strain): the in-plane Cauchy stress ``sigma`` (2x2 symmetric,
components xx, xz, zz; Pa) and the out-of-plane normal stress ``s_yy`` (Pa).

Update (Dunatunga & Kamrin 2015, explicit):

1. hypoelastic Jaumann trial  T* = T + dt (2 G D + lam tr(D) I + W T - T W)
2. free separation            T = 0          if rho < rho_c or P* <= 0
3. Drucker-Prager return       T' <- T' mu_s P* / tau*   if tau* > mu_s P*   (P unchanged)

with P = -tr(T)/3 (3D trace), T' = T + P I, tau = sqrt(T':T'/2), D = sym(L), W = skew(L).
Plastic flow is incompressible (pressure is kept) and coaxial (radial return).
The same law is written twice: a Taichi function for the solver and a NumPy function for the
reference step and the unit tests.
"""


from dataclasses import dataclass

import numpy as np
import taichi as ti

from .config import MaterialConfig


@ti.func
def drucker_prager_update(sigma, s_yy, L, rho, dt, prm):
    """Stress update of one point; ``prm`` = (G, lam, mu_s, rho_c). Returns (sigma, s_yy, dgamma_p).

    dgamma_p is the equivalent plastic shear strain increment (tau* - mu_s P*)/G; for
    disconnected material (stress-free) it is the total shear strain increment dt*sqrt(2 D':D') (3D deviator).
    """
    G, lam, mu_s, rho_c = prm[0], prm[1], prm[2], prm[3]
    D = 0.5 * (L + L.transpose())
    W = 0.5 * (L - L.transpose())
    tr_d = D.trace()
    eye = ti.Matrix.identity(float, 2)
    # Jaumann trial stress: T* = T + dt (2 G D + lam tr(D) I + W T - T W); D_yy = 0 (plane strain)
    sig = sigma + dt * (2.0 * G * D + lam * tr_d * eye + W @ sigma - sigma @ W)
    syy = s_yy + dt * lam * tr_d
    p = -(sig.trace() + syy) / 3.0
    dgamma = 0.0 * p
    if rho < rho_c or p <= 0.0:
        # free separation: (rho - rho_c) P = 0, disconnected material carries no stress
        dev_rate = D - tr_d / 3.0 * eye  # 3D deviator of D, whose yy part is -tr(D)/3
        dgamma = dt * ti.sqrt(2.0 * ((dev_rate * dev_rate).sum() + (tr_d / 3.0) ** 2))
        sig = sig * 0.0
        syy = 0.0 * syy
    else:
        dev = sig + p * eye
        dev_yy = syy + p
        tau = ti.sqrt(0.5 * ((dev * dev).sum() + dev_yy * dev_yy))
        if tau > mu_s * p:
            # radial return at fixed pressure: tau -> mu_s P
            scale = mu_s * p / tau
            dgamma = (tau - mu_s * p) / G
            sig = dev * scale - p * eye
            syy = dev_yy * scale - p
    return sig, syy, dgamma


def drucker_prager_update_numpy(
    sigma: np.ndarray,
    s_yy: np.ndarray,
    L: np.ndarray,
    rho: np.ndarray,
    dt: float,
    prm: tuple[float, float, float, float],
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Vectorised NumPy twin of :func:`drucker_prager_update`.

    Parameters
    ----------
    sigma : (N, 2, 2) in-plane stress, Pa.
    s_yy : (N,) out-of-plane stress, Pa.
    L : (N, 2, 2) velocity gradient dv_i/dx_j, 1/s.
    rho : (N,) density, kg/m^3.
    dt : time step, s.
    prm : (G, lam, mu_s, rho_c) in Pa, Pa, -, kg/m^3.
    """
    G, lam, mu_s, rho_c = prm
    D = 0.5 * (L + np.swapaxes(L, 1, 2))
    W = 0.5 * (L - np.swapaxes(L, 1, 2))
    tr_d = D[:, 0, 0] + D[:, 1, 1]
    eye = np.eye(2)
    sig = sigma + dt * (
        2 * G * D + lam * tr_d[:, None, None] * eye + W @ sigma - sigma @ W
    )
    syy = s_yy + dt * lam * tr_d
    p = -(sig[:, 0, 0] + sig[:, 1, 1] + syy) / 3.0
    dev = sig + p[:, None, None] * eye
    dev_yy = syy + p
    tau = np.sqrt(0.5 * ((dev * dev).sum(axis=(1, 2)) + dev_yy**2))
    yielding = tau > mu_s * p
    scale = np.where(yielding, mu_s * p / np.where(tau > 0, tau, 1.0), 1.0)
    dgamma = np.where(yielding, (tau - mu_s * p) / G, 0.0)
    sig = dev * scale[:, None, None] - p[:, None, None] * eye
    syy = dev_yy * scale - p
    free = (rho < rho_c) | (p <= 0.0)
    dev_rate = D - tr_d[:, None, None] / 3.0 * eye
    gdot = np.sqrt(2.0 * ((dev_rate**2).sum(axis=(1, 2)) + (tr_d / 3.0) ** 2))
    dgamma = np.where(free, dt * gdot, dgamma)
    sig[free] = 0.0
    syy = np.where(free, 0.0, syy)
    return sig, syy, dgamma


@dataclass(frozen=True)
class DruckerPragerSeparation:
    """Material object: rate-independent Drucker-Prager with free separation.

    The solver uses only ``taichi_update`` (a ``ti.func`` with the signature of
    :func:`drucker_prager_update`) and ``params`` (a tuple of floats passed to it);
    a new rheology is a new class with the same two members.
    """

    shear_modulus: float
    lame_lambda: float
    mu_s: float
    rho_c: float

    taichi_update = staticmethod(drucker_prager_update)
    numpy_update = staticmethod(drucker_prager_update_numpy)

    @classmethod
    def from_config(cls, cfg: MaterialConfig) -> "DruckerPragerSeparation":
        return cls(cfg.shear_modulus, cfg.lame_lambda, cfg.mu_s, cfg.rho_c)

    @property
    def params(self) -> tuple[float, float, float, float]:
        """(G Pa, lam Pa, mu_s, rho_c kg/m^3) in the order the update functions expect."""
        return (self.shear_modulus, self.lame_lambda, self.mu_s, self.rho_c)


def pressure(sigma: np.ndarray, s_yy: np.ndarray) -> np.ndarray:
    """P = -tr(sigma)/3 with the out-of-plane component, Pa."""
    return -(sigma[..., 0, 0] + sigma[..., 1, 1] + s_yy) / 3.0


@ti.kernel
def stress_update_batch(
    sigma: ti.types.ndarray(), s_yy: ti.types.ndarray(), L: ti.types.ndarray(),
    rho: ti.types.ndarray(), dgamma: ti.types.ndarray(), dt: float,
    prm: ti.types.vector(4, float),
):
    """Apply :func:`drucker_prager_update` to arrays of points in place (tests, diagnostics)."""
    for p in range(sigma.shape[0]):
        sig, syy, dg = drucker_prager_update(sigma[p], s_yy[p], L[p], rho[p], dt, prm)
        sigma[p] = sig
        s_yy[p] = syy
        dgamma[p] = dg
