"""Nonlocal granular fluidity (Kamrin & Koval 2012; Henann & Kamrin 2013). Not the paper's law.

The rate-independent Drucker-Prager law has no length, so in the MPM the grid sets the width of a
shear band and refining the cells approaches no limit (docs/results.md). The nonlocal rheology
gives the flow the grain size d as its length:

* flow rule                gdot_p = g mu,  mu = tau / P  (g: the fluidity, 1/s; no yield surface)
* local fluidity           g_loc = sqrt(P / (rho_s d^2)) (mu - mu_s) / (b mu)  for mu > mu_s, else 0
* nonlocal equation        A^2 d^2 lap(g) = |mu - mu_s| (g - g_loc)
  (the steady form g - xi^2 lap g = g_loc with the cooperativity length xi = A d / sqrt(|mu - mu_s|)).

In homogeneous flow g = g_loc, i.e. mu = mu_s + b I with I = gdot d sqrt(rho_s / P): the linear
part of mu(I). Where mu < mu_s the fluidity of flowing neighbours spreads over ~xi (creep), and a
band cannot be thinner than a few xi.

In the step (explicit MPM):

1. ``fluidity_sources``: each point's |mu - mu_s| and |mu - mu_s| g_loc (from its stress at the
   start of the step) to the grid with the quadratic B-spline weights, mass-weighted;
2. ``fluidity_jacobi``: Jacobi sweeps of the discrete nonlocal equation on the nodes that hold mass,
   warm-started from the last step's field; a node without mass stands in for its neighbour by the
   neighbour's own value (no flux through a free surface);
3. G2P with the elastic trial stress and free separation (no Drucker-Prager return);
4. ``fluidity_relax``: tau = tau* - G dt gdot_p with gdot_p = g mu, where g is the point's own
   local fluidity at the updated mu (implicit: a fluidity taken from the step's first stress would
   relax the stress far below mu_s P within a step, since P / (G g) is shorter than dt) plus the
   nonlocal excess g - g_loc of the grid field (explicit).
"""


import numpy as np
import taichi as ti

from . import backend
from .transfer import CHUNK_SPREAD, quadratic_weights

#: Drucker-Prager friction that never yields: the G2P trial of a nonlocal material stays elastic
NO_YIELD = 1.0e20
SOURCE_CHUNKS = 4  # private grid copies of the fluidity sources: a fixed summation order (no atomics)


@ti.func
def _pressure_and_tau(sig, syy):
    """P = -tr(T)/3 (3D trace) and tau = sqrt(T':T'/2) of a plane-strain stress."""
    p = -(sig[0, 0] + sig[1, 1] + syy) / 3.0
    a_xx, a_zz, a_yy = sig[0, 0] + p, sig[1, 1] + p, syy + p
    tau = ti.sqrt(0.5 * (a_xx * a_xx + a_zz * a_zz + a_yy * a_yy + 2.0 * sig[0, 1] * sig[0, 1]))
    return p, tau


@ti.func
def _point_source(p, x: ti.template(), mass: ti.template(), sigma: ti.template(), s_yy: ti.template(), nx, ny, h, pad, prm):
    """Base node, weights and m_p (|mu - mu_s|, |mu - mu_s| g_loc, 1) of point p; ``prm`` = (mu_s, b, d, rho_s)."""
    mu_s, b, d, rho_s = prm[0], prm[1], prm[2], prm[3]
    P, tau = _pressure_and_tau(sigma[p], s_yy[p])
    dmu, gloc = 0.0 * P, 0.0 * P
    if P > 0.0:
        mu = tau / P
        dmu = ti.abs(mu - mu_s)
        if mu > mu_s:
            gloc = ti.sqrt(P / rho_s) / d * (mu - mu_s) / (b * mu)  # g_loc = sqrt(P/(rho_s d^2)) (mu - mu_s)/(b mu)
    base, fx, w = quadratic_weights(x[p], 1.0 / h, pad, nx, ny)
    return base, w, mass[p] * ti.Vector([dmu, dmu * gloc, 1.0])


@ti.kernel
def fluidity_sources(
    x: ti.types.ndarray(), mass: ti.types.ndarray(), sigma: ti.types.ndarray(), s_yy: ti.types.ndarray(),
    parts: ti.types.ndarray(), src: ti.types.ndarray(), h: float, pad: int, prm: ti.types.vector(4, float),
):
    """src[i, j] = sum_p w_ip m_p (|mu - mu_s|, |mu - mu_s| g_loc, 1); ``prm`` = (mu_s, b, d, rho_s).

    Each chunk of points scatters serially into its own copy ``parts[c]`` (as the momentum P2G
    does), and the copies are summed in order: the sums do not depend on the threads' schedule,
    so a run and its restart give the same numbers.
    """
    nc, nx, ny = parts.shape[0], src.shape[0], src.shape[1]
    n = x.shape[0]
    for c, i, j in ti.ndrange(nc, nx, ny):
        parts[c, i, j] = ti.Vector([0.0, 0.0, 0.0])
    ti.loop_config(serialize=backend.SERIAL_LOOPS)
    for q in range(nc * CHUNK_SPREAD):  # parallel over chunks, serial inside
        if q % CHUNK_SPREAD == 0:
            c = q // CHUNK_SPREAD
            for p in range(c * n // nc, (c + 1) * n // nc):
                base, w, val = _point_source(p, x, mass, sigma, s_yy, nx, ny, h, pad, prm)
                for a, e in ti.static(ti.ndrange(3, 3)):
                    i, j = base[0] + a, base[1] + e
                    parts[c, i, j] = parts[c, i, j] + w[a][0] * w[e][1] * val
    for i, j in ti.ndrange(nx, ny):
        total = ti.Vector([0.0, 0.0, 0.0])
        for c in range(nc):
            total += parts[c, i, j]
        src[i, j] = total


@ti.func
def _jacobi_node(src: ti.template(), g: ti.template(), i, j, kappa):
    """One Jacobi update of A^2 d^2 lap g = |dmu| (g - g_loc) at node (i, j), kappa = A^2 d^2 / h^2."""
    out = 0.0 * kappa
    m = src[i, j][2]
    if m > 0.0:
        gc = g[i, j]
        nb = 0.0 * kappa
        for e in ti.static(range(4)):
            di, dj = ti.static([(1, 0), (-1, 0), (0, 1), (0, -1)][e])
            ii = ti.math.clamp(i + di, 0, src.shape[0] - 1)
            jj = ti.math.clamp(j + dj, 0, src.shape[1] - 1)
            nb += g[ii, jj] if src[ii, jj][2] > 0.0 else gc  # no flux into a node without mass
        a = src[i, j][0] / m
        out = ti.max((src[i, j][1] / m + kappa * nb) / (a + 4.0 * kappa), 0.0)
    return out


@ti.kernel
def fluidity_jacobi(src: ti.types.ndarray(), g: ti.types.ndarray(), g_tmp: ti.types.ndarray(), kappa: float):
    """Two Jacobi sweeps, g -> g_tmp -> g."""
    for i, j in ti.ndrange(g.shape[0], g.shape[1]):
        g_tmp[i, j] = _jacobi_node(src, g, i, j, kappa)
    for i, j in ti.ndrange(g.shape[0], g.shape[1]):
        g[i, j] = _jacobi_node(src, g_tmp, i, j, kappa)


@ti.func
def relaxed_tau(tau_t, p, excess, dt, prm):
    """tau from tau = tau* - G dt gdot_p with gdot_p = g mu, g = max(g_loc(mu) + excess, 0), mu = tau / P,
    g_loc implicit (its mu is the updated one) and the nonlocal excess explicit; ``prm`` = (G, mu_s, b, d, rho_s).

    With k = G dt / P, a = k sqrt(P / rho_s) / (d b), e = k excess: below mu_s P the point creeps,
    tau = tau* / (1 + max(e, 0)); above, k gdot_p = a (tau - mu_s P) + e tau, so
    tau = (tau* + a mu_s P) / (1 + a + e), flowing only if that is below tau*.
    """
    shear_modulus, mu_s, b, d, rho_s = prm[0], prm[1], prm[2], prm[3], prm[4]
    k = shear_modulus * dt / p
    e = k * excess
    a = k * ti.sqrt(p / rho_s) / (d * b)
    out = tau_t
    if tau_t <= mu_s * p * (1.0 + ti.max(e, 0.0)):
        out = tau_t / (1.0 + ti.max(e, 0.0))
    elif 1.0 + a + e > 0.0:
        out = ti.min((tau_t + a * mu_s * p) / (1.0 + a + e), tau_t)
    return out


@ti.kernel
def fluidity_relax(
    x: ti.types.ndarray(), sigma: ti.types.ndarray(), s_yy: ti.types.ndarray(), eps_p: ti.types.ndarray(),
    gdot_p: ti.types.ndarray(), src: ti.types.ndarray(), g: ti.types.ndarray(), h: float, pad: int, dt: float,
    prm: ti.types.vector(5, float),
):
    """The flow of each stressed point at fixed pressure (:func:`relaxed_tau`), with the nonlocal
    excess g - g_loc of the nodes (g_loc: their |dmu|-weighted local fluidity) interpolated at it;
    dgamma = (tau* - tau) / G. ``prm`` = (G, mu_s, b, d, rho_s)."""
    ti.loop_config(serialize=backend.SERIAL_LOOPS)
    for p in range(x.shape[0]):
        sig, syy = sigma[p], s_yy[p]
        P, tau = _pressure_and_tau(sig, syy)
        if P > 0.0 and tau > 0.0:
            base, fx, w = quadratic_weights(x[p], 1.0 / h, pad, g.shape[0], g.shape[1])
            excess = 0.0 * P
            for a, c in ti.static(ti.ndrange(3, 3)):
                i, j = base[0] + a, base[1] + c
                s = src[i, j]
                local = s[1] / s[0] if s[0] > 0.0 else 0.0 * P
                excess += w[a][0] * w[c][1] * (g[i, j] - local)
            scale = relaxed_tau(tau, P, excess, dt, prm) / tau
            a_xx, a_zz, a_yy = sig[0, 0] + P, sig[1, 1] + P, syy + P
            sigma[p] = ti.Matrix([[a_xx * scale - P, sig[0, 1] * scale], [sig[0, 1] * scale, a_zz * scale - P]])
            s_yy[p] = a_yy * scale - P
            dgamma = tau * (1.0 - scale) / prm[0]
            eps_p[p] += dgamma
            gdot_p[p] = dgamma / dt


class FluidityField:
    """The grid arrays of the nonlocal fluidity: the sources' chunk copies and sum (nx, ny, 3) and the field g, 1/s."""

    def __init__(self, shape):
        real = backend.info().real
        self.parts = ti.Vector.ndarray(3, real, shape=(SOURCE_CHUNKS, *shape))
        self.src = ti.Vector.ndarray(3, real, shape=shape)
        self.g = ti.ndarray(real, shape=shape)
        self.g_tmp = ti.ndarray(real, shape=shape)

    def to_numpy(self) -> np.ndarray:
        return self.g.to_numpy()

    def load(self, g: np.ndarray) -> None:
        self.g.from_numpy(np.ascontiguousarray(g, dtype=backend.info().np_real))


def steady_fluidity_numpy(dmu: np.ndarray, gloc: np.ndarray, mass: np.ndarray, kappa: float) -> np.ndarray:
    """The exact solution of the discrete nonlocal equation that ``fluidity_jacobi`` iterates
    towards (node-averaged |dmu| and g_loc, node mass), by a sparse solve (tests)."""
    import scipy.sparse as sp
    import scipy.sparse.linalg as spla

    nx, ny = dmu.shape
    idx = -np.ones((nx, ny), int)
    active = mass > 0
    idx[active] = np.arange(active.sum())
    rows, cols, vals, rhs = [], [], [], np.zeros(active.sum())
    for i, j in zip(*np.nonzero(active)):
        k = idx[i, j]
        diag = dmu[i, j] + 4.0 * kappa
        for di, dj in ((1, 0), (-1, 0), (0, 1), (0, -1)):
            ii, jj = min(max(i + di, 0), nx - 1), min(max(j + dj, 0), ny - 1)
            if active[ii, jj] and (ii, jj) != (i, j):
                rows.append(k), cols.append(idx[ii, jj]), vals.append(-kappa)
            else:
                diag -= kappa  # the node stands in for its missing neighbour
        rows.append(k), cols.append(k), vals.append(diag)
        rhs[k] = dmu[i, j] * gloc[i, j]
    a = sp.csr_matrix((vals, (rows, cols)), shape=(len(rhs), len(rhs)))
    out = np.zeros((nx, ny))
    out[active] = spla.spsolve(a.tocsc(), rhs)
    return out
