"""Drucker-Prager granular continuum with free separation (SPEC 1, Eq. 1-2).

State per material point (plane strain): the in-plane Cauchy stress ``sigma`` (2x2 symmetric,
components xx, xz, zz; Pa) and the out-of-plane normal stress ``s_yy`` (Pa).

Update (Dunatunga & Kamrin 2015, explicit):

1. hypoelastic Jaumann trial  T* = T + dt (2 G D + lam tr(D) I + W T - T W)
2. free separation            T = 0          if rho < rho_c or P* <= 0
3. Drucker-Prager return       T' <- T' mu_s P* / tau*   if tau* > mu_s P*   (P unchanged)

Optionally (``viscosity`` eta > 0; not in the paper, a diagnostic regularisation) the return
stops at the overstress tau = mu_s P + eta dgamma/dt (Perzyna / Duvaut-Lions):
tau = (mu_s P + k tau*) / (1 + k) with k = eta / (G dt). It gives the flow a rate, and so a
length, that the rate-independent law lacks (docs/results.md, "Where the 1.25 mm difference
comes from", items 4-5).

Optionally (``mu_i``; not in the paper either) the friction grows with the inertial number:
tau = mu(I) P, mu(I) = mu_s + dmu I / (I0 + I), I = gdot d sqrt(rho_s / P), the local rheology of
Jop, Forterre & Pouliquen (2006), returned implicitly (gdot from the return itself).

with P = -tr(T)/3 (3D trace), T' = T + P I, tau = sqrt(T':T'/2), D = sym(L), W = skew(L).
Plastic flow is incompressible (pressure is kept) and coaxial (radial return).
The same law is written twice: a Taichi function for the solver and a NumPy function for the
reference step and the unit tests.
"""

from dataclasses import dataclass

import numpy as np
import taichi as ti

from .config import MaterialConfig
from .fluidity import NO_YIELD


@ti.func
def _return_rate_independent(tau, p, dt, prm):
    """Yield-surface stress of the return: tau -> mu_s P, or with a 5th parameter eta the
    overstress tau = (mu_s P + k tau*) / (1 + k), k = eta / (G dt)."""
    tau_new = prm[2] * p
    if ti.static(prm.n > 4):
        k = prm[4] / (prm[0] * dt)
        tau_new = (tau_new + k * tau) / (1.0 + k)
    return tau_new


@ti.func
def _return_mu_i(tau, p, dt, prm):
    """Yield-surface stress of the return under mu(I): tau = mu(I) P, mu(I) = mu_s + dmu I / (I0 + I),
    I = gdot d sqrt(rho_s / P), gdot = (tau* - tau) / (G dt); ``prm[4:7]`` = (dmu, I0, d sqrt(rho_s)).
    With x = tau* - tau: a x^2 + b x - c I0 = 0, a = d sqrt(rho_s/P) / (G dt), b = I0 + a (dmu P - c),
    c = tau* - mu_s P > 0; its positive root, written without cancellation (both forms are computed
    and one is selected, so that the same code runs on vectors of points)."""
    c = tau - prm[2] * p
    a = prm[6] / (ti.sqrt(p) * prm[0] * dt)
    b = prm[5] + a * (prm[4] * p - c)
    root = ti.sqrt(b * b + 4.0 * a * c * prm[5])
    x = ti.select(b > 0.0, 2.0 * c * prm[5] / (b + root), (root - b) / (2.0 * a))
    return tau - x


def _make_update(yield_return):
    """The stress update of one point with the given return target ``yield_return(tau*, P, dt, prm)``:
    a ``ti.func`` on the stress and velocity-gradient matrices, whose ``components`` attribute is the
    same update on their components.

    ``components`` has no branches (every case is computed and ``ti.select`` keeps one), so its
    arguments may be scalars (one point) or equal-length vectors (one point per lane, the CPU's
    vectorised G2P, ``transfer.g2p_kernel(..., lanes=True)``); the values it selects are those of the branches.
    It writes a negation as ``0.0 - x`` (Taichi does not compile a unary minus on an unscalarised
    vector).
    """

    @ti.func
    def components(s_xx, s_zz, s_xz, s_yy, l_xx, l_xz, l_zx, l_zz, rho, dt, prm):
        G, lam, mu_s, rho_c = prm[0], prm[1], prm[2], prm[3]
        d_xz = 0.5 * (l_xz + l_zx)
        w = 0.5 * (l_xz - l_zx)
        tr_d = l_xx + l_zz
        # Jaumann trial stress: T* = T + dt (2 G D + lam tr(D) I + W T - T W); D_yy = 0 (plane strain)
        rot = 2.0 * w * s_xz
        t_xx = s_xx + dt * (2.0 * G * l_xx + lam * tr_d + rot)
        t_zz = s_zz + dt * (2.0 * G * l_zz + lam * tr_d - rot)
        t_xz = s_xz + dt * (2.0 * G * d_xz + w * (s_zz - s_xx))
        t_yy = s_yy + dt * lam * tr_d
        p = (0.0 - (t_xx + t_zz + t_yy)) / 3.0
        # free separation: (rho - rho_c) P = 0, disconnected material carries no stress; its dgamma
        # is the total shear strain increment (3D deviator of D)
        separated = (rho < rho_c) | (p <= 0.0)
        e_xx, e_zz, e_yy = l_xx - tr_d / 3.0, l_zz - tr_d / 3.0, (0.0 - tr_d) / 3.0
        dgamma_free = dt * ti.sqrt(2.0 * (e_xx * e_xx + e_zz * e_zz + e_yy * e_yy + 2.0 * d_xz * d_xz))
        # radial return at fixed pressure: tau -> the yield stress (mu_s P, or with a rate)
        a_xx, a_zz, a_yy = t_xx + p, t_zz + p, t_yy + p  # deviator
        tau = ti.sqrt(0.5 * (a_xx * a_xx + a_zz * a_zz + a_yy * a_yy + 2.0 * t_xz * t_xz))
        yielding = (tau > mu_s * p) & (rho >= rho_c) & (p > 0.0)
        tau_new = yield_return(tau, p, dt, prm)
        scale = tau_new / tau
        dgamma = ti.select(separated, dgamma_free, ti.select(yielding, (tau - tau_new) / G, 0.0))
        t_xx = ti.select(separated, 0.0, ti.select(yielding, a_xx * scale - p, t_xx))
        t_zz = ti.select(separated, 0.0, ti.select(yielding, a_zz * scale - p, t_zz))
        t_yy = ti.select(separated, 0.0, ti.select(yielding, a_yy * scale - p, t_yy))
        t_xz = ti.select(separated, 0.0, ti.select(yielding, t_xz * scale, t_xz))
        return t_xx, t_zz, t_xz, t_yy, dgamma

    @ti.func
    def update(sigma, s_yy, L, rho, dt, prm):
        t_xx, t_zz, t_xz, t_yy, dgamma = components(
            sigma[0, 0], sigma[1, 1], sigma[0, 1], s_yy, L[0, 0], L[0, 1], L[1, 0], L[1, 1], rho, dt, prm
        )
        return ti.Matrix([[t_xx, t_xz], [t_xz, t_zz]]), t_yy, dgamma

    update.components = components
    return update


drucker_prager_update = _make_update(_return_rate_independent)
drucker_prager_update.__doc__ = """Stress update of one point; ``prm`` = (G, lam, mu_s, rho_c) or (G, lam, mu_s, rho_c, eta).
Returns (sigma, s_yy, dgamma_p).

dgamma_p is the equivalent plastic shear strain increment (tau* - tau)/G; for
disconnected material (stress-free) it is the total shear strain increment dt*sqrt(2 D':D') (3D deviator).
Written in components (xx, xz, zz, yy): in 2D, W T - T W = w [[2 T_xz, T_zz - T_xx], [., -2 T_xz]]
with w = W_xz = (L_xz - L_zx)/2.
"""
mu_i_update = _make_update(_return_mu_i)
mu_i_update.__doc__ = """Stress update of one point under mu(I); ``prm`` = (G, lam, mu_s, rho_c, dmu, I0, d sqrt(rho_s)).
Same returns as :func:`drucker_prager_update`."""


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
    prm : (G, lam, mu_s, rho_c) in Pa, Pa, -, kg/m^3, and optionally the viscosity eta, Pa s.
    """
    return _update_numpy(sigma, s_yy, L, rho, dt, prm, _return_rate_independent_numpy)


def mu_i_update_numpy(
    sigma: np.ndarray,
    s_yy: np.ndarray,
    L: np.ndarray,
    rho: np.ndarray,
    dt: float,
    prm: tuple[float, ...],
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Vectorised NumPy twin of :func:`mu_i_update`; ``prm`` = (G, lam, mu_s, rho_c, dmu, I0, d sqrt(rho_s))
    in Pa, Pa, -, kg/m^3, -, -, m sqrt(kg/m^3); the rest as :func:`drucker_prager_update_numpy`."""
    return _update_numpy(sigma, s_yy, L, rho, dt, prm, _return_mu_i_numpy)


def _return_rate_independent_numpy(tau, p, dt, prm):
    """NumPy twin of :func:`_return_rate_independent`."""
    k = prm[4] / (prm[0] * dt) if len(prm) > 4 else 0.0
    return (prm[2] * p + k * tau) / (1.0 + k)


def _return_mu_i_numpy(tau, p, dt, prm):
    """NumPy twin of :func:`_return_mu_i` (any P > 0; points below yield get c <= 0, masked later)."""
    G, mu_s, dmu, i0, d_sqrt_rho = prm[0], prm[2], prm[4], prm[5], prm[6]
    c = np.maximum(tau - mu_s * p, 0.0)
    a = d_sqrt_rho / (np.sqrt(np.maximum(p, 1e-30)) * G * dt)
    b = i0 + a * (dmu * p - c)
    root = np.sqrt(b * b + 4.0 * a * c * i0)
    with np.errstate(divide="ignore", invalid="ignore"):
        x = np.where(b > 0.0, 2.0 * c * i0 / (b + root), (root - b) / (2.0 * a))
    return tau - x


def _update_numpy(sigma, s_yy, L, rho, dt, prm, yield_return):
    """The NumPy stress update with the return target ``yield_return(tau*, P, dt, prm)``."""
    G, lam, mu_s, rho_c = prm[:4]
    D = 0.5 * (L + np.swapaxes(L, 1, 2))
    W = 0.5 * (L - np.swapaxes(L, 1, 2))
    tr_d = D[:, 0, 0] + D[:, 1, 1]
    eye = np.eye(2)
    sig = sigma + dt * (2 * G * D + lam * tr_d[:, None, None] * eye + W @ sigma - sigma @ W)
    syy = s_yy + dt * lam * tr_d
    p = -(sig[:, 0, 0] + sig[:, 1, 1] + syy) / 3.0
    dev = sig + p[:, None, None] * eye
    dev_yy = syy + p
    tau = np.sqrt(0.5 * ((dev * dev).sum(axis=(1, 2)) + dev_yy**2))
    yielding = tau > mu_s * p
    tau_new = yield_return(tau, p, dt, prm)
    scale = np.where(yielding, tau_new / np.where(tau > 0, tau, 1.0), 1.0)
    dgamma = np.where(yielding, (tau - tau_new) / G, 0.0)
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
    viscosity: float = 0.0

    taichi_update = staticmethod(drucker_prager_update)
    numpy_update = staticmethod(drucker_prager_update_numpy)

    @classmethod
    def from_config(cls, cfg: MaterialConfig) -> "DruckerPragerSeparation":
        return cls(cfg.shear_modulus, cfg.lame_lambda, cfg.mu_s, cfg.rho_c, cfg.viscosity)

    @property
    def params(self) -> tuple[float, ...]:
        """(G Pa, lam Pa, mu_s, rho_c kg/m^3) in the order the update functions expect, and the
        viscosity eta (Pa s) as a 5th only when it is not 0 (the paper's law compiles without it)."""
        base = (self.shear_modulus, self.lame_lambda, self.mu_s, self.rho_c)
        return base + (self.viscosity,) if self.viscosity > 0.0 else base


@dataclass(frozen=True)
class MuIDruckerPrager:
    """Material object: Drucker-Prager with free separation whose friction grows with the inertial
    number, mu(I) = mu_s + dmu I / (I0 + I), I = gdot d sqrt(rho_s / P) (Jop, Forterre & Pouliquen
    2006). Not in the paper, which argues I stays small under intruders; here to test that claim
    and whether a grain-scale rate makes the MPM converge in cell size."""

    shear_modulus: float
    lame_lambda: float
    mu_s: float
    rho_c: float
    delta_mu: float
    i0: float
    grain_diameter: float
    grain_density: float

    taichi_update = staticmethod(mu_i_update)
    numpy_update = staticmethod(mu_i_update_numpy)

    @property
    def params(self) -> tuple[float, ...]:
        """(G, lam, mu_s, rho_c, dmu, I0, d sqrt(rho_s)) in the order :func:`mu_i_update` expects."""
        return (
            self.shear_modulus,
            self.lame_lambda,
            self.mu_s,
            self.rho_c,
            self.delta_mu,
            self.i0,
            self.grain_diameter * self.grain_density**0.5,
        )


@dataclass(frozen=True)
class NonlocalFluidity:
    """Material object: nonlocal granular fluidity with free separation (``intrusim.mpm.fluidity``).
    Its G2P update is the elastic trial with free separation (a Drucker-Prager friction that never
    yields); the solver adds the fluidity kernels around it."""

    shear_modulus: float
    lame_lambda: float
    mu_s: float
    rho_c: float
    amplitude: float
    b: float
    grain_diameter: float
    grain_density: float
    sweep_pairs: int

    taichi_update = staticmethod(drucker_prager_update)

    @property
    def params(self) -> tuple[float, ...]:
        """(G, lam, NO_YIELD, rho_c): the elastic trial and free separation of :func:`drucker_prager_update`."""
        return (self.shear_modulus, self.lame_lambda, NO_YIELD, self.rho_c)

    @property
    def fluidity_params(self) -> tuple[float, float, float, float]:
        """(mu_s, b, d, rho_s) in the order ``fluidity_sources`` expects."""
        return (self.mu_s, self.b, self.grain_diameter, self.grain_density)

    @property
    def relax_params(self) -> tuple[float, float, float, float, float]:
        """(G, mu_s, b, d, rho_s) in the order ``fluidity_relax`` expects."""
        return (self.shear_modulus, *self.fluidity_params)


def material_from_config(cfg: MaterialConfig) -> DruckerPragerSeparation | MuIDruckerPrager | NonlocalFluidity:
    """The material object of a config: the paper's law (optionally viscous), mu(I) when
    ``cfg.mu_i`` is given, the nonlocal fluidity when ``cfg.fluidity`` is."""
    if cfg.fluidity is not None:
        f = cfg.fluidity
        return NonlocalFluidity(
            cfg.shear_modulus,
            cfg.lame_lambda,
            cfg.mu_s,
            cfg.rho_c,
            f.amplitude,
            f.b,
            f.grain_diameter,
            f.grain_density,
            f.sweep_pairs,
        )
    if cfg.mu_i is None:
        return DruckerPragerSeparation.from_config(cfg)
    m = cfg.mu_i
    return MuIDruckerPrager(
        cfg.shear_modulus, cfg.lame_lambda, cfg.mu_s, cfg.rho_c, m.delta_mu, m.i0, m.grain_diameter, m.grain_density
    )


def pressure(sigma: np.ndarray, s_yy: np.ndarray) -> np.ndarray:
    """P = -tr(sigma)/3 with the out-of-plane component, Pa."""
    return -(sigma[..., 0, 0] + sigma[..., 1, 1] + s_yy) / 3.0


_BATCH_KERNELS: dict = {}


def stress_update_kernel(n_params: int = 4, update=drucker_prager_update):
    """A kernel applying ``update`` (:func:`drucker_prager_update` by default) in place to arrays
    of points, for a parameter vector of length ``n_params`` (tests, diagnostics)."""
    if (update, n_params) not in _BATCH_KERNELS:

        @ti.kernel
        def stress_update_batch(
            sigma: ti.types.ndarray(),
            s_yy: ti.types.ndarray(),
            L: ti.types.ndarray(),
            rho: ti.types.ndarray(),
            dgamma: ti.types.ndarray(),
            dt: float,
            prm: ti.types.vector(n_params, float),
        ):
            for p in range(sigma.shape[0]):
                sig, syy, dg = update(sigma[p], s_yy[p], L[p], rho[p], dt, prm)
                sigma[p] = sig
                s_yy[p] = syy
                dgamma[p] = dg

        _BATCH_KERNELS[(update, n_params)] = stress_update_batch
    return _BATCH_KERNELS[(update, n_params)]


stress_update_batch = stress_update_kernel(4)
