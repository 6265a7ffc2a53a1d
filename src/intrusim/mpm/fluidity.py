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

1. ``fluidity_sources_kernel``: each point's |mu - mu_s| and |mu - mu_s| g_loc (from its stress at the
   start of the step) to the grid with the quadratic B-spline weights, mass-weighted;
2. ``fluidity_jacobi_kernel``: Jacobi sweeps of the discrete nonlocal equation on the nodes that hold mass,
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
from .exact_sums import ATOMIC, FIXED, PLAIN, scatter_add, sum_mode
from .grid import make_record, record_index, record_width, union_box, zero_record
from .particles import LANES, XX, XZ, ZZ, chunk_blocks, get_scalar, get_sym2, get_vec2, set_scalar, set_sym2
from .transfer import (
    CHUNK_SPREAD,
    add_block_records,
    add_plastic_strain,
    any_lane,
    lane_nodes,
    quadratic_weights,
    stencil_lanes,
)

#: Drucker-Prager friction that never yields: the G2P trial of a nonlocal material stays elastic
NO_YIELD = 1.0e20
ROW_GRAIN = 8  # grid rows per task of the node loops (a loop of a few hundred rows would otherwise run as one task)
SOURCE_CHUNKS = 4  # private grid copies of the fluidity sources: a fixed summation order (no atomics)


@ti.func
def _pressure_and_tau(sig, syy):
    """P = -tr(T)/3 (3D trace) and tau = sqrt(T':T'/2) of a plane-strain stress."""
    return pressure_and_tau(sig[0, 0], sig[1, 1], sig[0, 1], syy)


@ti.func
def pressure_and_tau(s_xx, s_zz, s_xz, s_yy):
    """:func:`_pressure_and_tau` on the components (scalars, or vectors over points: ``0.0 - x``, as
    Taichi does not compile a unary minus on an unscalarised vector)."""
    p = (0.0 - (s_xx + s_zz + s_yy)) / 3.0
    a_xx, a_zz, a_yy = s_xx + p, s_zz + p, s_yy + p
    tau = ti.sqrt(0.5 * (a_xx * a_xx + a_zz * a_zz + a_yy * a_yy + 2.0 * s_xz * s_xz))
    return p, tau


@ti.func
def _point_source(
    p, x: ti.template(), mass: ti.template(), sigma: ti.template(), s_yy: ti.template(), nx, ny, h, pad, prm
):
    """Base node, weights and m_p (|mu - mu_s|, |mu - mu_s| g_loc, 1) of point p; ``prm`` = (mu_s, b, d, rho_s)."""
    mu_s, b, d, rho_s = prm[0], prm[1], prm[2], prm[3]
    P, tau = _pressure_and_tau(get_sym2(sigma, p), get_scalar(s_yy, p))
    dmu, gloc = 0.0 * P, 0.0 * P
    if P > 0.0:
        mu = tau / P
        dmu = ti.abs(mu - mu_s)
        if mu > mu_s:
            gloc = ti.sqrt(P / rho_s) / d * (mu - mu_s) / (b * mu)  # g_loc = sqrt(P/(rho_s d^2)) (mu - mu_s)/(b mu)
    base, fx, w = quadratic_weights(get_vec2(x, p), 1.0 / h, pad, nx, ny)
    return base, w, get_scalar(mass, p) * ti.Vector([dmu, dmu * gloc, 1.0])


@ti.func
def _scatter_source(
    p,
    c,
    x: ti.template(),
    mass: ti.template(),
    sigma: ti.template(),
    s_yy: ti.template(),
    parts: ti.template(),
    nx,
    ny,
    h,
    pad,
    prm,
    mode: ti.template(),
    scale,
):
    """Point p's sources into copy c of ``parts`` (records, ``grid.record_index``, ``grid.record_width``: the stencil's
    first node addressed once, the other 8 at fixed offsets), by ``exact_sums.scatter_add`` (PLAIN: one
    loop iteration owns copy c; ATOMIC; FIXED: 64-bit fixed point). Returns the stencil's base node."""
    base, w, val = _point_source(p, x, mass, sigma, s_yy, nx, ny, h, pad, prm)
    first = record_index(c, base[0], base[1], nx, ny)
    for a, e in ti.static(ti.ndrange(3, 3)):
        r = w[a][0] * w[e][1] * val
        scatter_add(parts, first + a * ny + e, make_record(parts, r[0], r[1], r[2]), mode, scale)
    return base


@ti.func
def _source_lanes(
    blk, x: ti.template(), mass: ti.template(), sigma: ti.template(), s_yy: ti.template(), nx, ny, h, pad, prm
):
    """:func:`_point_source` for the LANES points of block ``blk``, each quantity a vector over them
    (branch-free): the stencil's base node per axis (floats) and, per node (a, e), the record
    w m_p (|dmu|, |dmu| g_loc, 1) it receives."""
    mu_s, b, d, rho_s = prm[0], prm[1], prm[2], prm[3]
    P, tau = pressure_and_tau(sigma[blk, XX], sigma[blk, ZZ], sigma[blk, XZ], s_yy[blk, 0])
    mu = tau / P
    dmu = ti.select(P > 0.0, ti.max(mu - mu_s, mu_s - mu), 0.0)  # |mu - mu_s| (no ti.abs on such a vector)
    gloc = ti.select((P > 0.0) & (mu > mu_s), ti.sqrt(P / rho_s) / d * (mu - mu_s) / (b * mu), 0.0)
    m = mass[blk, 0]
    val = (m * dmu, m * (dmu * gloc), m * 1.0)
    b0, f0, w0, b1, f1, w1 = stencil_lanes(x, blk, h, pad, nx, ny)
    records = [
        (w0[a] * w1[e] * val[0], w0[a] * w1[e] * val[1], w0[a] * w1[e] * val[2])
        for a in ti.static(range(3))
        for e in ti.static(range(3))
    ]
    return b0, b1, records


@ti.func
def _sum_copies(parts: ti.template(), src: ti.template(), i, j, nc, nx, ny, inv_scale):
    """src[i, j] = the sum of node (i, j)'s records over the copies, in order (fixed-point records
    times ``inv_scale``, else 1); the records are zeroed."""
    total = ti.Vector([0.0, 0.0, 0.0])
    for c in range(nc):
        k = record_index(c, i, j, nx, ny)
        rec = parts[k]  # float: the backend's real type (a no-op on real copies)
        total += ti.Vector([ti.cast(rec[0], float), ti.cast(rec[1], float), ti.cast(rec[2], float)]) * inv_scale
        zero_record(parts, k)
    src[i, j] = total


def fluidity_sources_kernel(chunked: bool, fixed: bool = False, lanes: bool = False):
    """The sources' kernel, chunked (CPU: private copies, deterministic) or atomic (GPU: one copy,
    atomic adds, float or 64-bit fixed point, the box is the whole grid), as ``transfer.p2g_kernel``;
    ``lanes`` (chunked only): vectorised over LANES points (:func:`_source_lanes`), compiled unscalarised."""
    mode = sum_mode(chunked, fixed)
    if lanes and mode != PLAIN:
        raise ValueError("the vectorised sources' kernel is the chunked one (private copies, no atomics)")
    return _SOURCE_KERNELS[(mode, lanes)]


def _make_sources_kernel(mode: int, lanes: bool):
    chunked = mode == PLAIN

    @ti.kernel
    def fluidity_sources(
        x: ti.types.ndarray(),
        mass: ti.types.ndarray(),
        sigma: ti.types.ndarray(),
        s_yy: ti.types.ndarray(),
        n: int,
        parts: ti.types.ndarray(),
        box_parts: ti.types.ndarray(),
        box: ti.types.ndarray(),
        src: ti.types.ndarray(),
        h: float,
        pad: int,
        prm: ti.types.vector(4, float),
        scale: float,
    ):
        """src[i, j] = sum_p w_ip m_p (|mu - mu_s|, |mu - mu_s| g_loc, 1) over the n points (block arrays,
        see particles); ``prm`` = (mu_s, b, d, rho_s).

        Chunked (CPU): each chunk of points (whole blocks, ``particles.chunk_blocks``) scatters
        serially into its own copy of ``parts`` (as the momentum P2G does), and the copies are summed
        in order: the sums do not depend on the threads' schedule, so a run and its restart give the
        same numbers. Atomic (GPU): one copy.
        The copies are zeroed as they are read, ready for the next step (they start at zero:
        ``FluidityField``). Only the nodes in the box the points reach this step or reached the
        last one are summed (``box``: [0:4] this step's node box [i0, i1, j0, j1), [4:8] its union
        with the last step's, which the sweeps visit); elsewhere the sources, g and the excess are
        zero already.
        """
        nc, nx, ny = box_parts.shape[0], src.shape[0], src.shape[1]
        if ti.static(chunked):
            ti.loop_config(serialize=backend.SERIAL_LOOPS)
            for q in range(nc * CHUNK_SPREAD):  # parallel over chunks, serial inside
                if q % CHUNK_SPREAD == 0:
                    c = q // CHUNK_SPREAD
                    first, end = chunk_blocks(c, nc, x.shape[0])
                    if ti.static(lanes):
                        i0, i1, j0, j1 = nx, 0, ny, 0
                        for blk in range(first, end):
                            b0, b1, records = _source_lanes(blk, x, mass, sigma, s_yy, nx, ny, h, pad, prm)
                            i0, i1, j0, j1 = add_block_records(
                                parts, c, blk * LANES, n, b0, b1, records, nx, ny, i0, i1, j0, j1
                            )
                        box_parts[c, 0], box_parts[c, 1], box_parts[c, 2], box_parts[c, 3] = i0, i1, j0, j1
                    else:
                        lo = ti.Vector([nx, ny])
                        hi = ti.Vector([0, 0])
                        for p in range(first * LANES, ti.min(end * LANES, n)):
                            base = _scatter_source(p, c, x, mass, sigma, s_yy, parts, nx, ny, h, pad, prm, PLAIN, scale)
                            lo, hi = ti.min(lo, base), ti.max(hi, base + 3)
                        box_parts[c, 0], box_parts[c, 1], box_parts[c, 2], box_parts[c, 3] = lo[0], hi[0], lo[1], hi[1]
        else:
            box_parts[0, 0], box_parts[0, 1], box_parts[0, 2], box_parts[0, 3] = 0, nx, 0, ny
            for p in range(n):
                _scatter_source(p, 0, x, mass, sigma, s_yy, parts, nx, ny, h, pad, prm, mode, scale)
        b0, b1, b2, b3 = union_box(box_parts, nx, ny)
        u0, u1, u2, u3 = ti.min(box[0], b0), ti.max(box[1], b1), ti.min(box[2], b2), ti.max(box[3], b3)
        box[0], box[1], box[2], box[3] = b0, b1, b2, b3
        box[4], box[5], box[6], box[7] = u0, u1, u2, u3
        if ti.static(chunked):
            ti.loop_config(serialize=backend.SERIAL_LOOPS, block_dim=ROW_GRAIN)
            for i in range(u0, u1):  # parallel over rows, serial along each (no integer division per node)
                for j in range(u2, u3):
                    _sum_copies(parts, src, i, j, nc, nx, ny, 1.0 / scale)
        else:
            nj = ti.max(u3 - u2, 0)
            for q in range(ti.max(u1 - u0, 0) * nj):  # one thread per node
                _sum_copies(parts, src, u0 + q // nj, u2 + q % nj, nc, nx, ny, 1.0 / scale)

    return fluidity_sources


_SOURCE_KERNELS = {(mode, False): _make_sources_kernel(mode, False) for mode in (PLAIN, ATOMIC, FIXED)}
_SOURCE_KERNELS[(PLAIN, True)] = _make_sources_kernel(PLAIN, True)


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


def fluidity_jacobi_kernel(rows: bool):
    """The sweeps' kernel: by rows of nodes (CPU: serial along a row, no integer division per
    node) or one thread per node (GPU)."""
    return _JACOBI_KERNELS[bool(rows)]


@ti.func
def _sweep_node(
    src: ti.template(),
    g_in: ti.template(),
    g_out: ti.template(),
    excess: ti.template(),
    i,
    j,
    kappa,
    last: ti.template(),
):
    """g_out[i, j] from g_in (:func:`_jacobi_node`); in the ``last`` sweep also the node's excess g - g_loc."""
    gn = _jacobi_node(src, g_in, i, j, kappa)
    g_out[i, j] = gn
    if ti.static(last):
        s = src[i, j]
        excess[i, j] = gn - (s[1] / s[0] if s[0] > 0.0 else 0.0 * kappa)


def _make_jacobi_kernel(rows: bool):
    @ti.kernel
    def fluidity_jacobi(
        src: ti.types.ndarray(),
        g: ti.types.ndarray(),
        g_tmp: ti.types.ndarray(),
        excess: ti.types.ndarray(),
        box: ti.types.ndarray(),
        kappa: float,
    ):
        """Two Jacobi sweeps, g -> g_tmp -> g, and the nonlocal excess g - g_loc of each node (g_loc:
        its |dmu|-weighted local fluidity, 0 where no point has |dmu| > 0) for ``fluidity_relax``, on
        the nodes of the box ``box[4:8]`` of the sources' kernel (outside it all three are zero)."""
        u0, u1, u2, u3 = box[4], box[5], box[6], box[7]
        nj = ti.max(u3 - u2, 0)
        for sweep in ti.static(range(2)):
            g_in, g_out = ti.static((g, g_tmp) if sweep == 0 else (g_tmp, g))
            if ti.static(rows):
                ti.loop_config(block_dim=ROW_GRAIN)
                for i in range(u0, u1):
                    for j in range(u2, u3):
                        _sweep_node(src, g_in, g_out, excess, i, j, kappa, sweep == 1)
            else:
                for q in range(ti.max(u1 - u0, 0) * nj):
                    _sweep_node(src, g_in, g_out, excess, u0 + q // nj, u2 + q % nj, kappa, sweep == 1)

    return fluidity_jacobi


_JACOBI_KERNELS = {flag: _make_jacobi_kernel(flag) for flag in (False, True)}


@ti.func
def relaxed_tau(tau_t, p, excess, dt, prm):
    """tau from tau = tau* - G dt gdot_p with gdot_p = g mu, g = max(g_loc(mu) + excess, 0), mu = tau / P,
    g_loc implicit (its mu is the updated one) and the nonlocal excess explicit; ``prm`` = (G, mu_s, b, d, rho_s).

    With k = G dt / P, a = k sqrt(P / rho_s) / (d b), e = k excess: below mu_s P the point creeps,
    tau = tau* / (1 + max(e, 0)); above, k gdot_p = a (tau - mu_s P) + e tau, so
    tau = (tau* + a mu_s P) / (1 + a + e), flowing only if that is below tau*.
    Both cases are computed and ``ti.select`` keeps one, so the arguments may be scalars or vectors over
    points (``fluidity_relax_kernel(lanes=True)``).
    """
    shear_modulus, mu_s, b, d, rho_s = prm[0], prm[1], prm[2], prm[3], prm[4]
    k = shear_modulus * dt / p
    e = k * excess
    a = k * ti.sqrt(p / rho_s) / (d * b)
    creep = tau_t / (1.0 + ti.max(e, 0.0))
    flow = ti.min((tau_t + a * mu_s * p) / (1.0 + a + e), tau_t)
    return ti.select(tau_t <= mu_s * p * (1.0 + ti.max(e, 0.0)), creep, ti.select(1.0 + a + e > 0.0, flow, tau_t))


def fluidity_relax_kernel(lanes: bool = False):
    """The relaxation kernel: one point per loop iteration, or (``lanes``, the CPU's) LANES points as
    vectors, compiled unscalarised as ``transfer.g2p_kernel(..., lanes=True)``."""
    return _RELAX_KERNELS[bool(lanes)]


def _make_relax_kernel(lanes: bool):
    @ti.kernel
    def fluidity_relax(
        x: ti.types.ndarray(),
        sigma: ti.types.ndarray(),
        s_yy: ti.types.ndarray(),
        eps_p: ti.types.ndarray(),
        gdot_p: ti.types.ndarray(),
        excess: ti.types.ndarray(),
        h: float,
        pad: int,
        dt: float,
        prm: ti.types.vector(5, float),
    ):
        """The flow of each stressed point at fixed pressure (:func:`relaxed_tau`), with the nonlocal
        excess g - g_loc of the nodes (the sweeps' kernel writes it) interpolated at it;
        dgamma = (tau* - tau) / G. ``prm`` = (G, mu_s, b, d, rho_s). A point with P <= 0 or tau = 0 is
        left as it is."""
        if ti.static(not lanes):
            ti.loop_config(serialize=backend.SERIAL_LOOPS)
            for p in range(x.shape[0] * LANES):  # every slot of the blocks, as the G2P
                sig, syy = get_sym2(sigma, p), get_scalar(s_yy, p)
                P, tau = _pressure_and_tau(sig, syy)
                if P > 0.0 and tau > 0.0:
                    base, fx, w = quadratic_weights(get_vec2(x, p), 1.0 / h, pad, excess.shape[0], excess.shape[1])
                    ex = 0.0 * P
                    for a, c in ti.static(ti.ndrange(3, 3)):
                        ex += w[a][0] * w[c][1] * excess[base[0] + a, base[1] + c]
                    scale = relaxed_tau(tau, P, ex, dt, prm) / tau
                    a_xx, a_zz, a_yy = sig[0, 0] + P, sig[1, 1] + P, syy + P
                    set_sym2(
                        sigma,
                        p,
                        ti.Matrix([[a_xx * scale - P, sig[0, 1] * scale], [sig[0, 1] * scale, a_zz * scale - P]]),
                    )
                    set_scalar(s_yy, p, a_yy * scale - P)
                    add_plastic_strain(eps_p, gdot_p, p, tau * (1.0 - scale) / prm[0], dt)
        else:
            ti.loop_config(serialize=backend.SERIAL_LOOPS)
            for blk in range(x.shape[0]):
                s_xx, s_zz, s_xz, syy = sigma[blk, XX], sigma[blk, ZZ], sigma[blk, XZ], s_yy[blk, 0]
                P, tau = pressure_and_tau(s_xx, s_zz, s_xz, syy)
                stressed = (P > 0.0) & (tau > 0.0)
                if any_lane(stressed):
                    b0, f0, w0, b1, f1, w1 = stencil_lanes(x, blk, h, pad, excess.shape[0], excess.shape[1])
                    i0, i1 = lane_nodes(b0), lane_nodes(b1)
                    ex = 0.0 * P
                    for a, c in ti.static(ti.ndrange(3, 3)):
                        ex += w0[a] * w1[c] * ti.Vector([excess[i0[k] + a, i1[k] + c] for k in ti.static(range(LANES))])
                    scale = relaxed_tau(tau, P, ex, dt, prm) / tau
                    dgamma = tau * (1.0 - scale) / prm[0]
                    # the stressed lanes flow; the others keep their state (ti.select: their NaN scale is dropped)
                    sigma[blk, XX] = ti.select(stressed, (s_xx + P) * scale - P, s_xx)
                    sigma[blk, ZZ] = ti.select(stressed, (s_zz + P) * scale - P, s_zz)
                    sigma[blk, XZ] = ti.select(stressed, s_xz * scale, s_xz)
                    s_yy[blk, 0] = ti.select(stressed, (syy + P) * scale - P, syy)
                    eps_p[blk, 0] = ti.select(stressed, eps_p[blk, 0] + dgamma, eps_p[blk, 0])
                    gdot_p[blk, 0] = ti.select(stressed, dgamma / dt, gdot_p[blk, 0])

    return fluidity_relax


_RELAX_KERNELS = {flag: _make_relax_kernel(flag) for flag in (False, True)}


class FluidityField:
    """The grid arrays of the nonlocal fluidity: the sources' chunk copies (flat) and sum (nx, ny, 3), the
    field g and its nonlocal excess g - g_loc, 1/s, and the node boxes of ``fluidity_sources``."""

    def __init__(self, shape, chunked: bool = True, fixed_scale: float | None = None):
        real = backend.info().real
        self.shape = tuple(shape)
        self.chunked = bool(chunked)
        if self.chunked and fixed_scale is not None:
            raise ValueError("chunked sources sum in a fixed order already: no fixed point")
        self.fixed_scale = None if fixed_scale is None else float(fixed_scale)  # one copy of 64-bit integers
        copies = SOURCE_CHUNKS if self.chunked else 1  # private copies (CPU) or one with atomic adds (GPU)
        # one (|dmu|, |dmu| g_loc, 1)-record per node and copy (grid.record_index, grid.record_width)
        dtype = real if self.fixed_scale is None else ti.i64
        self.parts = ti.Vector.ndarray(record_width(self.chunked), dtype, shape=copies * self.shape[0] * self.shape[1])
        self.parts.fill(0)  # the sources' kernel leaves them zeroed after each step
        self.box_parts = ti.ndarray(ti.i32, shape=(copies, 4))
        self.box = ti.ndarray(ti.i32, shape=8)
        self.src = ti.Vector.ndarray(3, real, shape=shape)
        self.g = ti.ndarray(real, shape=shape)
        self.g_tmp = ti.ndarray(real, shape=shape)
        self.excess = ti.ndarray(real, shape=shape)
        for a in (self.src, self.g, self.g_tmp, self.excess):
            a.fill(0.0)
        self._whole_grid_next()

    def _whole_grid_next(self) -> None:
        """The next step visits every node (after a start or a load, g may be non-zero anywhere)."""
        self.box.from_numpy(np.array([0, self.shape[0], 0, self.shape[1], 0, 0, 0, 0], dtype=np.int32))

    def to_numpy(self) -> np.ndarray:
        return self.g.to_numpy()

    def load(self, g: np.ndarray) -> None:
        self.g.from_numpy(np.ascontiguousarray(g, dtype=backend.info().np_real))
        self._whole_grid_next()


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
