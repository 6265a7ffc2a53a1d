"""Nonlocal granular fluidity (intrusim.mpm.fluidity) against its equations: the grid sweeps
against a direct solve and the 1D creep profile, the flow of a point against mu = mu_s + b I."""

import numpy as np
import pytest

from intrusim.mpm.backend import ensure_initialized
from intrusim.mpm.fluidity import steady_fluidity_numpy

G, MU_S, B, D, RHO_S, DT = 3.85e5, 0.56, 0.9375, 1e-3, 1100.0, 4e-5


def _sweep(dmu, gloc, mass, kappa, pairs, box=None, excess=False, rows=True):
    """``pairs`` calls of the sweeps' kernel (by rows, or one thread per node) from g = 0 on node
    arrays (the sources as the P2G leaves them), on the node box (i0, i1, j0, j1) (default: every
    node); g, or g and the excess."""
    import taichi as ti

    from intrusim.mpm.fluidity import FluidityField, fluidity_jacobi_kernel

    ensure_initialized()
    f = FluidityField(dmu.shape)
    f.src.from_numpy(np.stack([mass * dmu, mass * dmu * gloc, mass], axis=-1).astype(ensure_initialized().np_real))
    nx, ny = dmu.shape
    f.box.from_numpy(np.array([0, nx, 0, ny, *(box or (0, nx, 0, ny))], dtype=np.int32))
    for _ in range(pairs):
        fluidity_jacobi_kernel(rows)(f.src, f.g, f.g_tmp, f.excess, f.box, kappa)
    ti.sync()
    return (f.to_numpy(), f.excess.to_numpy()) if excess else f.to_numpy()


def test_sweeps_on_the_box_of_the_material_equal_sweeps_on_every_node():
    """The sweeps visit only the node box the points reach; outside it g and the excess stay 0."""
    rng = np.random.default_rng(5)
    shape, box = (20, 14), (3, 15, 2, 9)
    inside = np.zeros(shape, bool)
    inside[box[0] : box[1], box[2] : box[3]] = True
    dmu = np.where(inside, rng.uniform(0.0, 0.2, shape), 0.0)
    gloc = np.where(inside, rng.uniform(0.0, 20.0, shape), 0.0)
    mass = np.where(inside & (rng.uniform(size=shape) < 0.9), 1.0, 0.0)
    g_all, ex_all = _sweep(dmu, gloc, mass, 0.3, 30, excess=True)
    g_box, ex_box = _sweep(dmu, gloc, mass, 0.3, 30, box=box, excess=True)
    np.testing.assert_array_equal(g_box, g_all)
    np.testing.assert_array_equal(ex_box, ex_all)
    g_flat, ex_flat = _sweep(dmu, gloc, mass, 0.3, 30, box=box, excess=True, rows=False)  # the GPU's loop
    np.testing.assert_array_equal(g_flat, g_all)
    np.testing.assert_array_equal(ex_flat, ex_all)
    assert g_all.max() > 1.0 and not g_box[~inside].any() and not ex_box[~inside].any()
    local = np.where(mass * dmu > 0, gloc, 0.0)
    np.testing.assert_allclose(ex_all, g_all - local, rtol=1e-6, atol=1e-5)  # excess = g - g_loc


def test_uniform_flow_has_the_local_fluidity():
    dmu, gloc, mass = np.full((12, 9), 0.1), np.full((12, 9), 7.0), np.ones((12, 9))
    np.testing.assert_allclose(_sweep(dmu, gloc, mass, 0.5, 200), 7.0, rtol=1e-5)


def test_sweeps_converge_to_the_direct_solve_with_free_nodes_and_neumann_edges():
    rng = np.random.default_rng(3)
    dmu = rng.uniform(0.0, 0.2, (16, 12))
    gloc = np.where(rng.uniform(size=dmu.shape) < 0.5, rng.uniform(0, 20, dmu.shape), 0.0)
    mass = np.where(rng.uniform(size=dmu.shape) < 0.85, 1.0, 0.0)  # some nodes without material
    exact = steady_fluidity_numpy(dmu, gloc, mass, 0.3)
    np.testing.assert_allclose(_sweep(dmu, gloc, mass, 0.3, 2000), exact, rtol=1e-4, atol=1e-4)
    assert np.all(exact[mass == 0] == 0.0) and exact.max() > 1.0


def test_fluidity_creeps_into_the_static_side_over_the_cooperativity_length():
    """Flowing (g_loc = G0) for x < 0, static for x > 0, |mu - mu_s| = delta on both sides:
    g = G0 (1 - exp(x/xi)/2) and G0 exp(-x/xi)/2 with xi = A d / sqrt(delta)."""
    h, amp, delta, g0 = 0.1e-3, 0.48, 0.04, 10.0
    xi = amp * D / np.sqrt(delta)  # 2.4 mm
    n = 400
    x = (np.arange(n) - n / 2 + 0.5) * h
    dmu = np.full((n, 1), delta)
    gloc = np.where(x < 0, g0, 0.0)[:, None]
    g = steady_fluidity_numpy(dmu, gloc, np.ones((n, 1)), (amp * D / h) ** 2)[:, 0]
    expect = np.where(x < 0, g0 * (1 - 0.5 * np.exp(x / xi)), 0.5 * g0 * np.exp(-x / xi))
    far = np.abs(x) < 0.015  # away from the strip's ends
    np.testing.assert_allclose(g[far], expect[far], atol=0.01 * g0)
    assert g[np.argmin(np.abs(x - 2 * xi))] == pytest.approx(0.5 * g0 * np.exp(-2), rel=0.05)


def _relaxed(tau_t, p, excess):
    import taichi as ti

    from intrusim.mpm.fluidity import relaxed_tau

    ensure_initialized()
    real = ensure_initialized().np_real
    tau_t, p, excess = (
        np.ascontiguousarray(a, real) for a in np.broadcast_arrays(*map(np.atleast_1d, (tau_t, p, excess)))
    )
    out = np.zeros_like(tau_t)

    @ti.kernel
    def run(
        t: ti.types.ndarray(),
        pp: ti.types.ndarray(),
        e: ti.types.ndarray(),
        o: ti.types.ndarray(),
        prm: ti.types.vector(5, float),
    ):
        for k in range(t.shape[0]):
            o[k] = relaxed_tau(t[k], pp[k], e[k], DT, prm)

    run(tau_t, p, excess, out, ti.Vector([G, MU_S, B, D, RHO_S]))
    return out


@pytest.mark.parametrize("p", [50.0, 500.0])
def test_local_flow_lands_on_mu_s_plus_b_times_its_own_inertial_number(p):
    tau_t = np.array([0.7, 1.0, 2.0]) * p  # trial stress ratios 0.7, 1, 2
    tau = _relaxed(tau_t, p, 0.0)
    gdot = (tau_t - tau) / (G * DT)
    inertial = gdot * D * np.sqrt(RHO_S / p)
    np.testing.assert_allclose(tau / p, MU_S + B * inertial, rtol=1e-4)
    assert np.all(tau > MU_S * p) and np.all(tau < tau_t)


def test_below_yield_the_point_creeps_only_with_a_nonlocal_excess():
    p, tau_t = 200.0, 0.4 * 200.0
    assert _relaxed(tau_t, p, 0.0)[0] == pytest.approx(tau_t, rel=1e-7)  # static without flowing neighbours
    excess = 3.0
    tau = _relaxed(tau_t, p, excess)[0]
    assert tau == pytest.approx(tau_t / (1 + G * DT * excess / p), rel=1e-6)
    gdot = (tau_t - tau) / (G * DT)
    assert gdot == pytest.approx(excess * tau / p, rel=1e-4)  # gdot_p = g mu with g = the excess
    # a negative excess (nonlocal strengthening) large enough stops the flow above mu_s
    assert _relaxed(0.8 * p, p, -1e4)[0] == pytest.approx(0.8 * p, rel=1e-7)


def test_fluidity_config_builds_its_material_and_excludes_the_other_rate_laws():
    from intrusim.mpm.config import FluidityConfig, MaterialConfig, MuIConfig
    from intrusim.mpm.constitutive import NonlocalFluidity, material_from_config
    from intrusim.mpm.fluidity import NO_YIELD

    m = material_from_config(MaterialConfig(mu_s=MU_S, fluidity=FluidityConfig(grain_diameter=2e-3)))
    assert isinstance(m, NonlocalFluidity)
    assert m.params[2] == NO_YIELD  # the G2P trial stays elastic; the fluidity kernels do the flow
    assert m.relax_params == (m.shear_modulus, MU_S, B, 2e-3, RHO_S)
    with pytest.raises(ValueError, match="not mu_i and fluidity"):
        MaterialConfig(mu_i=MuIConfig(), fluidity=FluidityConfig())
    with pytest.raises(ValueError, match="sweep_pairs"):
        FluidityConfig(sweep_pairs=0)
