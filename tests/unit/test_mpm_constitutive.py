"""Drucker-Prager with separation against hand formulas (Taichi and NumPy versions)."""

import numpy as np
import pytest

from intrusim.mpm.backend import ensure_initialized
from intrusim.mpm.config import MaterialConfig
from intrusim.mpm.constitutive import (
    DruckerPragerSeparation, drucker_prager_update_numpy, pressure, stress_update_batch, stress_update_kernel,
)

MAT = DruckerPragerSeparation.from_config(MaterialConfig(rho_c=900.0, mu_s=0.5, youngs_modulus=1e6, poisson_ratio=0.3))
DT = 1e-4


def taichi_update(sigma, s_yy, L, rho, dt=DT, prm=MAT.params):
    """:func:`drucker_prager_update` through a batch kernel, called as the NumPy twin is."""
    import taichi as ti

    ensure_initialized(precision="f32")
    n = len(sigma)
    arrs = [ti.Matrix.ndarray(2, 2, ti.f32, shape=n), ti.ndarray(ti.f32, shape=n),
            ti.Matrix.ndarray(2, 2, ti.f32, shape=n), ti.ndarray(ti.f32, shape=n), ti.ndarray(ti.f32, shape=n)]
    for a, d in zip(arrs, (sigma, s_yy, L, rho, np.zeros(n))):
        a.from_numpy(np.asarray(d, np.float32))
    stress_update_kernel(len(prm))(*arrs, dt, prm)
    return arrs[0].to_numpy(), arrs[1].to_numpy(), arrs[4].to_numpy()


BOTH = [drucker_prager_update_numpy, taichi_update]


def _state(p0=1000.0, n=1):
    sigma = np.tile(-p0 * np.eye(2), (n, 1, 1))
    return sigma, np.full(n, -p0), np.full(n, 950.0)


@pytest.mark.parametrize("update", BOTH)
def test_elastic_step_matches_hooke(update):
    sigma, syy, rho = _state()
    D = np.array([[[2e-3, 1e-3], [1e-3, -1e-3]]])  # small symmetric rate, 1/s
    sig, s_out, dg = update(sigma, syy, D, rho, DT, MAT.params)
    G, lam = MAT.shear_modulus, MAT.lame_lambda
    tr = np.trace(D[0])
    expect = sigma[0] + DT * (2 * G * D[0] + lam * tr * np.eye(2))
    np.testing.assert_allclose(sig[0], expect, rtol=1e-5)
    np.testing.assert_allclose(s_out[0], syy[0] + DT * lam * tr, rtol=1e-5)
    assert dg[0] == 0.0


@pytest.mark.parametrize("update", BOTH)
def test_radial_return_keeps_pressure_and_reaches_yield(update):
    sigma, syy, rho = _state()
    L = np.array([[[0.0, 50.0], [50.0, 0.0]]])  # large pure shear: trial far above yield
    sig, s_out, dg = update(sigma, syy, L, rho, DT, MAT.params)
    p = pressure(sig, s_out)[0]
    # pressure unchanged by the return (trial pressure = initial, tr D = 0)
    assert p == pytest.approx(1000.0, rel=1e-5)
    dev = sig[0] + p * np.eye(2)
    tau = np.sqrt(0.5 * ((dev**2).sum() + (s_out[0] + p) ** 2))
    assert tau == pytest.approx(MAT.mu_s * p, rel=1e-5)
    tau_trial = 2 * MAT.shear_modulus * 50.0 * DT
    assert dg[0] == pytest.approx((tau_trial - MAT.mu_s * p) / MAT.shear_modulus, rel=1e-4)
    assert sig[0, 0, 1] > 0  # coaxial with the shear rate


@pytest.mark.parametrize("update", BOTH)
def test_tension_and_low_density_give_zero_stress(update):
    sigma, syy, rho = _state(p0=10.0, n=2)
    L = np.zeros((2, 2, 2))
    L[0] = np.eye(2) * 100.0  # strong expansion: trial pressure < 0
    rho = np.array([950.0, 800.0])  # second point below rho_c = 900
    sig, s_out, _ = update(sigma, syy, L, rho, DT, MAT.params)
    assert np.all(sig == 0.0) and np.all(s_out == 0.0)


@pytest.mark.parametrize("update", BOTH)
def test_jaumann_spin_rotates_stress(update):
    sigma = np.array([[[-2000.0, 0.0], [0.0, -1000.0]]])
    syy, rho = np.array([-1500.0]), np.array([950.0])
    w = 10.0
    L = np.array([[[0.0, -w], [w, 0.0]]])  # rigid spin, no strain
    sig, s_out, _ = update(sigma, syy, L, rho, DT, MAT.params)
    W = L[0]
    expect = sigma[0] + DT * (W @ sigma[0] - sigma[0] @ W)
    np.testing.assert_allclose(sig[0], expect, rtol=1e-5, atol=1e-3)
    assert np.trace(sig[0]) == pytest.approx(np.trace(sigma[0]), rel=1e-6)


def _random_state(seed, n=200):
    """n points near P = 1000 Pa with random stress, velocity gradient and density."""
    rng = np.random.default_rng(seed)
    sigma, syy, _ = _state(n=n)
    sigma = sigma + rng.normal(0, 300, (n, 2, 2))
    sigma = 0.5 * (sigma + np.swapaxes(sigma, 1, 2))
    return sigma, syy, rng.normal(0, 5.0, (n, 2, 2)), rng.uniform(850, 1000, n)


def test_taichi_matches_numpy_random():
    sigma, syy, L, rho = _random_state(0)
    a = drucker_prager_update_numpy(sigma, syy, L, rho, DT, MAT.params)
    b = taichi_update(sigma, syy, L, rho)
    for x, y in zip(a, b):
        np.testing.assert_allclose(y, x, rtol=2e-4, atol=1e-2)


VISCOUS = DruckerPragerSeparation.from_config(
    MaterialConfig(rho_c=900.0, mu_s=0.5, youngs_modulus=1e6, poisson_ratio=0.3, viscosity=20.0))


def test_the_paper_law_has_four_parameters_and_the_viscosity_a_fifth():
    assert len(MAT.params) == 4 and MAT.viscosity == 0.0
    assert VISCOUS.params == MAT.params + (20.0,)
    assert stress_update_kernel(4) is stress_update_batch


@pytest.mark.parametrize("update", BOTH)
def test_viscous_return_stops_at_the_overstress(update):
    """tau = mu_s P + eta dgamma/dt at a yielding point, pressure kept; eta = 0 is the plain return."""
    sigma, syy, rho = _state()
    L = np.array([[[0.0, 400.0], [0.0, 0.0]]])  # a fast shear: tau* far above mu_s P
    G = VISCOUS.shear_modulus
    out_v = update(sigma, syy, L, rho, DT, VISCOUS.params)
    out_0 = update(sigma, syy, L, rho, DT, MAT.params)
    for sig, s_yy, dg in (out_v, out_0):
        p = pressure(sig, s_yy)[0]
        assert p == pytest.approx(1000.0, rel=1e-5)  # tr D = 0: the pressure is unchanged
    (sig_v, syy_v, dg_v), (sig_0, syy_0, dg_0) = out_v, out_0
    dev = lambda sig, s_yy: np.sqrt(0.5 * (((sig[0] + 1000.0 * np.eye(2)) ** 2).sum() + (s_yy[0] + 1000.0) ** 2))
    tau_v, tau_0 = dev(sig_v, syy_v), dev(sig_0, syy_0)
    assert tau_0 == pytest.approx(0.5 * 1000.0, rel=1e-5)
    assert tau_v - 0.5 * 1000.0 == pytest.approx(20.0 * dg_v[0] / DT, rel=1e-4)  # the overstress is eta gdot
    assert tau_v > tau_0 and dg_v[0] < dg_0[0]
    # the trial stress is the same, so tau* = tau + G dgamma in both
    assert tau_v + G * dg_v[0] == pytest.approx(tau_0 + G * dg_0[0], rel=1e-5)


def test_viscous_taichi_matches_numpy_random():
    sigma, syy, L, rho = _random_state(1)
    a = drucker_prager_update_numpy(sigma, syy, L, rho, DT, VISCOUS.params)
    b = taichi_update(sigma, syy, L, rho, prm=VISCOUS.params)
    c = drucker_prager_update_numpy(sigma, syy, L, rho, DT, MAT.params)
    for x, y in zip(a, b):
        np.testing.assert_allclose(y, x, rtol=2e-4, atol=1e-2)
    assert np.max(np.abs(a[2] - c[2])) > 1e-4  # the viscosity changes the plastic increments
