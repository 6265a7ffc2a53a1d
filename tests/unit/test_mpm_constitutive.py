"""Drucker-Prager with separation against hand formulas (Taichi and NumPy versions)."""

import numpy as np
import pytest

from intrusim.mpm.backend import ensure_initialized
from intrusim.mpm.config import MaterialConfig, MuIConfig
from intrusim.mpm.constitutive import (
    DruckerPragerSeparation,
    MuIDruckerPrager,
    drucker_prager_update,
    drucker_prager_update_numpy,
    material_from_config,
    mu_i_update,
    mu_i_update_numpy,
    pressure,
    stress_update_batch,
    stress_update_kernel,
)

MAT = DruckerPragerSeparation.from_config(MaterialConfig(rho_c=900.0, mu_s=0.5, youngs_modulus=1e6, poisson_ratio=0.3))
DT = 1e-4


def taichi_update(sigma, s_yy, L, rho, dt=DT, prm=MAT.params, update=drucker_prager_update):
    """:func:`drucker_prager_update` (or ``update``) through a batch kernel, called as the NumPy twin is."""
    import taichi as ti

    ensure_initialized(precision="f32")
    n = len(sigma)
    arrs = [
        ti.Matrix.ndarray(2, 2, ti.f32, shape=n),
        ti.ndarray(ti.f32, shape=n),
        ti.Matrix.ndarray(2, 2, ti.f32, shape=n),
        ti.ndarray(ti.f32, shape=n),
        ti.ndarray(ti.f32, shape=n),
    ]
    for a, d in zip(arrs, (sigma, s_yy, L, rho, np.zeros(n))):
        a.from_numpy(np.asarray(d, np.float32))
    stress_update_kernel(len(prm), update)(*arrs, dt, prm)
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
    MaterialConfig(rho_c=900.0, mu_s=0.5, youngs_modulus=1e6, poisson_ratio=0.3, viscosity=20.0)
)


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

    def dev(sig, s_yy):
        return np.sqrt(0.5 * (((sig[0] + 1000.0 * np.eye(2)) ** 2).sum() + (s_yy[0] + 1000.0) ** 2))

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


MU_I_CFG = MaterialConfig(
    rho_c=900.0,
    mu_s=0.5,
    youngs_modulus=1e6,
    poisson_ratio=0.3,
    mu_i=MuIConfig(grain_diameter=1e-3, grain_density=1100.0, delta_mu=0.26, i0=0.279),
)
MU_I = material_from_config(MU_I_CFG)


def taichi_mu_i_update(sigma, s_yy, L, rho, dt, prm):
    return taichi_update(sigma, s_yy, L, rho, dt, prm, update=mu_i_update)


MU_I_BOTH = [mu_i_update_numpy, taichi_mu_i_update]


def _tau(sig, s_yy, p):
    return np.sqrt(0.5 * (((sig + p[:, None, None] * np.eye(2)) ** 2).sum(axis=(1, 2)) + (s_yy + p) ** 2))


def test_mu_i_config_builds_its_material_and_excludes_the_viscosity():
    assert isinstance(MU_I, MuIDruckerPrager)
    assert MU_I.params[:4] == MAT.params and MU_I.params[6] == pytest.approx(1e-3 * 1100.0**0.5)
    assert isinstance(material_from_config(MaterialConfig()), DruckerPragerSeparation)
    with pytest.raises(ValueError, match="one rate law of viscosity, mu_i and fluidity, not viscosity and mu_i"):
        MaterialConfig(viscosity=1.0, mu_i=MuIConfig())
    with pytest.raises(ValueError, match="grain_diameter"):
        MuIConfig(grain_diameter=0.0)


@pytest.mark.parametrize("update", MU_I_BOTH)
@pytest.mark.parametrize("rate", [20.0, 100.0, 400.0])
def test_mu_i_return_stops_at_mu_of_its_own_inertial_number(update, rate):
    """tau = (mu_s + dmu I / (I0 + I)) P with I = (dgamma/dt) d sqrt(rho_s / P), pressure kept."""
    sigma, syy, rho = _state()
    L = np.array([[[0.0, rate], [0.0, 0.0]]])  # simple shear: tau* above mu_s P
    sig, s_out, dg = update(sigma, syy, L, rho, DT, MU_I.params)
    p = pressure(sig, s_out)
    assert p[0] == pytest.approx(1000.0, rel=1e-5)
    inertial = dg[0] / DT * 1e-3 * np.sqrt(1100.0 / p[0])
    assert inertial > 0
    mu = 0.5 + 0.26 * inertial / (0.279 + inertial)
    assert _tau(sig, s_out, p)[0] == pytest.approx(mu * p[0], rel=2e-4)
    # the trial stress is that of the paper's law: tau* = tau + G dgamma in both
    sig_0, syy_0, dg_0 = update(sigma, syy, L, rho, DT, MU_I.params[:4] + (0.0,) + MU_I.params[5:])
    tau_0 = _tau(sig_0, syy_0, pressure(sig_0, syy_0))[0]
    assert tau_0 == pytest.approx(0.5 * 1000.0, rel=1e-5)  # delta_mu = 0: the rate-independent return
    assert _tau(sig, s_out, p)[0] + MU_I.shear_modulus * dg[0] == pytest.approx(
        tau_0 + MU_I.shear_modulus * dg_0[0], rel=1e-5
    )


def test_mu_i_friction_stays_between_mu_s_and_mu_2_and_taichi_matches_numpy():
    sigma, syy, L, rho = _random_state(2, n=400)
    L = L * np.geomspace(1e-2, 1e3, 400)[:, None, None]  # rates over five decades
    a = mu_i_update_numpy(sigma, syy, L, rho, DT, MU_I.params)
    b = taichi_mu_i_update(sigma, syy, L, rho, DT, MU_I.params)
    for x, y in zip(a, b):
        np.testing.assert_allclose(y, x, rtol=5e-4, atol=2e-2)
    sig, s_out, dg = a
    p = pressure(sig, s_out)
    yielded = (dg > 0) & (rho >= 900.0) & (p > 0)
    assert yielded.sum() > 50
    ratio = _tau(sig, s_out, p)[yielded] / p[yielded]
    assert np.all(ratio >= 0.5 * (1 - 1e-5)) and np.all(ratio <= 0.76 * (1 + 1e-5))
    assert ratio.max() > 0.55  # the fast points carry a friction well above mu_s
