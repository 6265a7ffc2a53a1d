"""Particle <-> grid transfers with quadratic B-splines and the affine momentum of APIC (MLS-MPM
form); linear (tent) shape functions as an option (``TransferConfig.shape``, one-point kernels only).

The points' velocity update is FLIP with a PIC share that falls with dt (the default,
``TransferConfig.flip = None``: v_p <- sum w v_i + s (v_p - sum w v_old_i), s = exp(-dt / tau)), so that
the damping per second, and the answers, do not depend on dt (docs/mpm.md, "The velocity transfer");
a fixed share is an option (0: APIC, Jiang et al. 2015; 1: FLIP). P2G scatters the affine momentum
m_p (v_p + C_p (x_i - x_p)) either way, and C_p is the grid's velocity gradient, which the
constitutive update needs. Internal forces use the MLS-MPM gradient (Hu et al. 2018):
grad w_ip ~ w_ip (4/h^2)(x_i - x_p), exact for quadratic B-splines.
"""

import taichi as ti

from . import backend
from .exact_sums import FIXED, PLAIN, scatter_add, sum_mode
from .grid import make_record, record_index
from .particles import (
    LANES,
    XX,
    XZ,
    ZZ,
    chunk_blocks,
    get_mat2,
    get_scalar,
    get_sym2,
    get_vec2,
    set_mat2,
    set_scalar,
    set_sym2,
    set_vec2,
)


@ti.func
def quadratic_weights(xp, inv_h: float, pad: int, n0: int, n1: int):
    """Base node, fractional offset and the 3 B-spline weights per axis of point xp (m)."""
    Xp = xp * inv_h + pad
    base = ti.cast(ti.floor(Xp - 0.5), ti.i32)
    base = ti.math.clamp(base, 0, ti.Vector([n0 - 3, n1 - 3]))
    fx = Xp - base
    w = [0.5 * (1.5 - fx) ** 2, 0.75 - (fx - 1.0) ** 2, 0.5 * (fx - 0.5) ** 2]
    return base, fx, w


@ti.func
def linear_weights(xp, inv_h: float, pad: int, n0: int, n1: int):
    """Base node, fractional offset and the 2 tent weights per axis of point xp (m): w = 1 - f, f;
    their derivatives are -1/h, +1/h (the cell's bilinear shape functions, as the mpm-2d code)."""
    Xp = xp * inv_h + pad
    base = ti.cast(ti.floor(Xp), ti.i32)
    base = ti.math.clamp(base, 0, ti.Vector([n0 - 2, n1 - 2]))
    fx = Xp - base
    w = [1.0 - fx, fx]
    return base, fx, w


@ti.func
def kept_or_marked(x: ti.template(), p, vec, mat, mode: ti.template()) -> bool:
    """Whether point p's records go into the sums. In FIXED mode integers carry no NaN, so a point
    whose ``vec`` or ``mat`` is not finite is left out and marked instead (its position set to NaN,
    for the guard); in the float modes every point is kept (a NaN then shows in the sums)."""
    kept = True
    if ti.static(mode == FIXED):
        if ti.math.isnan(vec).any() or ti.math.isinf(vec).any() or ti.math.isnan(mat).any() or ti.math.isinf(mat).any():
            set_vec2(x, p, ti.Vector([ti.math.nan, ti.math.nan]))
            kept = False
    return kept


@ti.func
def scatter_point(
    p,
    c,
    x: ti.template(),
    v: ti.template(),
    C: ti.template(),
    mass: ti.template(),
    vol: ti.template(),
    sigma: ti.template(),
    gmp: ti.template(),
    nx,
    ny,
    h,
    pad,
    dt,
    mode: ti.template(),
    scale,
    gmo: ti.template(),
    flip: ti.template(),
):
    """m_i += w m_p ;  (m v)_i += w [m_p v_p + (m_p C_p - dt V_p (4/h^2) sigma_p)(x_i - x_p)].

    With ``flip`` also (m v_old)_i += w m_p [v_p + C_p (x_i - x_p)] into ``gmo`` (the momentum before
    the stress impulse, for FLIP's old grid velocity; ``TransferConfig.flip``).

    ``gmp`` is the array of the grid copies' records (``grid.record_index``, ``grid.record_width``);
    the stencil's first record is addressed once per point and the other 8 at fixed offsets from it
    (P2G 1.2-1.6x faster on 2 threads than a 3-index address per node, same sums: docs/performance.md).
    ``mode``: PLAIN read-modify-write (one loop iteration owns copy ``c``), ATOMIC float adds
    (several threads share copy ``c``), or FIXED: atomic adds of round(value * ``scale``) into 64-bit
    integers (exact sums, the same in any order). Returns the base node of the 3 x 3 stencil.
    """
    inv_h = 1.0 / h
    base, fx, w = quadratic_weights(get_vec2(x, p), inv_h, pad, nx, ny)
    mp = get_scalar(mass, p)
    affine = mp * get_mat2(C, p) - (dt * get_scalar(vol, p) * 4.0 * inv_h * inv_h) * get_sym2(sigma, p)
    # node (a, b) of the stencil is at x_i - x_p = h ((a, b) - f): its momentum is
    # m_p v_p + affine (x_i - x_p) = q0 + a h affine[:, 0] + b h affine[:, 1]
    q0 = mp * get_vec2(v, p) - h * (affine @ fx)
    ca = h * ti.Vector([affine[0, 0], affine[1, 0]])
    cb = h * ti.Vector([affine[0, 1], affine[1, 1]])
    first = record_index(c, base[0], base[1], nx, ny)
    scattered = kept_or_marked(x, p, q0, affine, mode)
    if scattered:
        scatter_stencil(gmp, first, w, q0, ca, cb, mp, ny, mode, scale)
    if ti.static(flip):  # the same with the momentum alone: affine = m_p C_p (not for a point marked above)
        if scattered:
            mc = mp * get_mat2(C, p)
            scatter_momentum(
                gmo,
                first,
                w,
                mp * get_vec2(v, p) - h * (mc @ fx),
                h * ti.Vector([mc[0, 0], mc[1, 0]]),
                h * ti.Vector([mc[0, 1], mc[1, 1]]),
                ny,
                mode,
                scale,
            )
    return base


@ti.func
def scatter_stencil(gmp: ti.template(), first, w, q0, ca, cb, mp, ny, mode: ti.template(), scale):
    """(m v, m) += w_ab (q0 + a ca + b cb, m_p) into the 3 x 3 records from ``first`` (one vector add each)."""
    for a in ti.static(range(3)):
        qa = q0 + a * ca
        for b in ti.static(range(3)):
            weight = w[a][0] * w[b][1]
            q = qa + b * cb
            scatter_add(
                gmp, first + a * ny + b, make_record(gmp, weight * q[0], weight * q[1], weight * mp), mode, scale
            )


@ti.func
def scatter_momentum(gmo: ti.template(), first, w, q0, ca, cb, ny, mode: ti.template(), scale):
    """(m v)_old += w_ab (q0 + a ca + b cb) into the 3 x 3 momentum records from ``first`` (FLIP)."""
    for a in ti.static(range(3)):
        for b in ti.static(range(3)):
            scatter_add(gmo, first + a * ny + b, (w[a][0] * w[b][1]) * (q0 + a * ca + b * cb), mode, scale)


@ti.func
def scatter_point_linear(
    p,
    c,
    x: ti.template(),
    v: ti.template(),
    mass: ti.template(),
    vol: ti.template(),
    sigma: ti.template(),
    gmp: ti.template(),
    nx,
    ny,
    h,
    pad,
    dt,
    mode: ti.template(),
    scale,
    gmo: ti.template(),
    flip: ti.template(),
):
    """m_i += w m_p ;  (m v)_i += w m_p v_p - dt V_p sigma_p grad w  (linear shape functions, no affine part).

    With ``flip`` also (m v_old)_i += w m_p v_p into ``gmo``. The records, modes and the NaN mark as
    :func:`scatter_point`'s, on the 2 x 2 nodes of the point's cell. Returns the base node.
    """
    inv_h = 1.0 / h
    base, fx, w = linear_weights(get_vec2(x, p), inv_h, pad, nx, ny)
    mp = get_scalar(mass, p)
    q = mp * get_vec2(v, p)
    s = (dt * get_scalar(vol, p) * inv_h) * get_sym2(sigma, p)  # dt V_p sigma_p / h
    first = record_index(c, base[0], base[1], nx, ny)
    if kept_or_marked(x, p, q, s, mode):
        for a in ti.static(range(2)):
            for b in ti.static(range(2)):
                weight = w[a][0] * w[b][1]
                grad = ti.Vector([(2 * a - 1) * w[b][1], (2 * b - 1) * w[a][0]])  # h grad w_ab
                q_ab = weight * q - s @ grad
                scatter_add(gmp, first + a * ny + b, make_record(gmp, q_ab[0], q_ab[1], weight * mp), mode, scale)
                if ti.static(flip):
                    scatter_add(gmo, first + a * ny + b, weight * q, mode, scale)
    return base


@ti.func
def scatter_chunk_points(
    c,
    first,
    end,
    n,
    x: ti.template(),
    v: ti.template(),
    C: ti.template(),
    mass: ti.template(),
    vol: ti.template(),
    sigma: ti.template(),
    gmp: ti.template(),
    nx,
    ny,
    h,
    pad,
    dt,
    scale,
    gmo: ti.template(),
    flip: ti.template(),
    linear: ti.template(),
):
    """The points of blocks [first, end) (below n) into grid copy c one at a time (:func:`scatter_point`,
    or :func:`scatter_point_linear`); returns the node box (i0, i1, j0, j1)."""
    lo = ti.Vector([nx, ny])
    hi = ti.Vector([0, 0])
    for p in range(first * LANES, ti.min(end * LANES, n)):
        base = lo
        if ti.static(linear):
            base = scatter_point_linear(p, c, x, v, mass, vol, sigma, gmp, nx, ny, h, pad, dt, PLAIN, scale, gmo, flip)
        else:
            base = scatter_point(p, c, x, v, C, mass, vol, sigma, gmp, nx, ny, h, pad, dt, PLAIN, scale, gmo, flip)
        lo = ti.min(lo, base)
        hi = ti.max(hi, base + ti.static(2 if linear else 3))  # the stencil's nodes per axis
    return lo[0], hi[0], lo[1], hi[1]


CHUNK_SPREAD = 1024  # outer iterations per P2G chunk (see p2g_kernel)


def p2g_kernel(chunked: bool, fixed: bool = False, lanes: bool = False, flip: bool = False, linear: bool = False):
    """The P2G kernel, chunked (CPU), atomic (a GPU) or atomic in fixed point (a GPU, deterministic):
    one compiled kernel each. ``lanes`` (chunked only): its arithmetic vectorised over LANES points
    (:func:`scatter_chunk_lanes`; compile it unscalarised, as ``g2p_kernel(..., lanes=True)``).
    ``flip``: it also sums the momentum before forces into its last argument (``Grid.mo_parts``, FLIP's
    old grid velocity), or with ``lanes`` into the records' 5th and 6th numbers where they are 8 wide
    (``Grid.flip_in_records``); without it that argument is not touched.
    ``linear`` (one-point only): linear shape functions (:func:`scatter_point_linear`).

    A factory rather than a ``ti.template()`` flag, so that the kernel can be recorded in a
    ``ti.graph`` (see step_graph), which takes no template parameters.
    """
    mode = sum_mode(chunked, fixed)
    if lanes and mode != PLAIN:
        raise ValueError("the vectorised P2G is the chunked one (private copies, no atomics)")
    if lanes and linear:
        raise ValueError("the vectorised P2G is quadratic only: linear shape functions run the one-point kernel")
    key = (mode, lanes, flip, linear)
    if key not in _P2G_KERNELS:
        _P2G_KERNELS[key] = _make_p2g_kernel(mode, lanes, flip, linear)
    return _P2G_KERNELS[key]


def _make_p2g_kernel(mode: int, lanes: bool, flip: bool, linear: bool):
    chunked = mode == PLAIN

    @ti.kernel
    def p2g_scatter(
        x: ti.types.ndarray(),
        v: ti.types.ndarray(),
        C: ti.types.ndarray(),
        mass: ti.types.ndarray(),
        vol: ti.types.ndarray(),
        sigma: ti.types.ndarray(),
        n: int,
        gmp: ti.types.ndarray(),
        box: ti.types.ndarray(),
        nx: int,
        ny: int,
        h: float,
        pad: int,
        dt: float,
        scale: float,
        gmo: ti.types.ndarray(),
    ):
        """P2G of the n points (block arrays, see particles) into the grid copies ``gmp`` (records, see
        scatter_point; a grid of nx x ny nodes); ``box[c]`` = node box [i0, i1, j0, j1)
        copy c received.

        Chunked (CPU): one private copy per chunk of points (whole blocks, ``particles.chunk_blocks``),
        no atomics, fixed summation order. Taichi's CPU backend runs a range-for of <= 512 iterations
        as one task, so a loop over the few chunks would run on one thread: the outer loop has
        CHUNK_SPREAD iterations per chunk, and only the first of them scatters that chunk's points,
        serially in point order. The tasks spread over the threads and each copy's sums do not depend
        on the scheduling. Otherwise (GPU): one copy and atomic adds (float, or 64-bit fixed point
        times ``scale``), and the box is the whole grid.
        """
        if ti.static(chunked):
            nc = box.shape[0]
            ti.loop_config(serialize=backend.SERIAL_LOOPS)
            for q in range(nc * CHUNK_SPREAD):  # parallel over chunks, serial inside
                if q % CHUNK_SPREAD == 0:
                    c = q // CHUNK_SPREAD
                    first, end = chunk_blocks(c, nc, x.shape[0])
                    if ti.static(lanes):
                        box[c, 0], box[c, 1], box[c, 2], box[c, 3] = scatter_chunk_lanes(
                            c, first, end, n, x, v, C, mass, vol, sigma, gmp, nx, ny, h, pad, dt, gmo, flip
                        )
                    else:
                        box[c, 0], box[c, 1], box[c, 2], box[c, 3] = scatter_chunk_points(
                            c,
                            first,
                            end,
                            n,
                            x,
                            v,
                            C,
                            mass,
                            vol,
                            sigma,
                            gmp,
                            nx,
                            ny,
                            h,
                            pad,
                            dt,
                            scale,
                            gmo,
                            flip,
                            linear,
                        )
        else:
            # the whole grid: a box from per-point atomic min/max would contend on 4 addresses
            box[0, 0], box[0, 1], box[0, 2], box[0, 3] = 0, nx, 0, ny
            ti.loop_config(serialize=backend.SERIAL_LOOPS)
            for p in range(n):
                if ti.static(linear):
                    scatter_point_linear(p, 0, x, v, mass, vol, sigma, gmp, nx, ny, h, pad, dt, mode, scale, gmo, flip)
                else:
                    scatter_point(p, 0, x, v, C, mass, vol, sigma, gmp, nx, ny, h, pad, dt, mode, scale, gmo, flip)

    return p2g_scatter


_P2G_KERNELS: dict = {}  # by (mode, lanes, flip, linear), made on first use


@ti.func
def p2g_lanes_records(
    blk,
    x: ti.template(),
    v: ti.template(),
    C: ti.template(),
    mass: ti.template(),
    vol: ti.template(),
    sigma: ti.template(),
    nx,
    ny,
    h,
    pad,
    dt,
):
    """:func:`scatter_point`'s arithmetic for the LANES points of block ``blk``, each quantity a vector
    over them (one vector load per component): the stencil's base node per axis (as floats) and, per
    node (a, b) of the 3 x 3 stencil, the record (w m v_x, w m v_z, w m) it receives."""
    inv_h = 1.0 / h
    b0, f0, w0, b1, f1, w1 = stencil_lanes(x, blk, h, pad, nx, ny)
    mp = mass[blk, 0]
    kv = dt * vol[blk, 0] * 4.0 * inv_h * inv_h
    # affine = m_p C_p - dt V_p (4/h^2) sigma_p ;  q0 = m_p v_p - h affine f ;  ca, cb = h affine[:, 0], h affine[:, 1]
    a00 = mp * C[blk, 0] - kv * sigma[blk, XX]
    a01 = mp * C[blk, 1] - kv * sigma[blk, XZ]
    a10 = mp * C[blk, 2] - kv * sigma[blk, XZ]
    a11 = mp * C[blk, 3] - kv * sigma[blk, ZZ]
    q0x = mp * v[blk, 0] - h * (a00 * f0 + a01 * f1)
    q0z = mp * v[blk, 1] - h * (a10 * f0 + a11 * f1)
    cax, caz, cbx, cbz = h * a00, h * a10, h * a01, h * a11
    qa = [(q0x + a * cax, q0z + a * caz) for a in ti.static(range(3))]
    records = [
        (w0[a] * w1[b] * (qa[a][0] + b * cbx), w0[a] * w1[b] * (qa[a][1] + b * cbz), w0[a] * w1[b] * mp)
        for a in ti.static(range(3))
        for b in ti.static(range(3))
    ]
    return b0, b1, records


@ti.func
def p2g_lanes_records_flip(
    blk,
    x: ti.template(),
    v: ti.template(),
    C: ti.template(),
    mass: ti.template(),
    vol: ti.template(),
    sigma: ti.template(),
    nx,
    ny,
    h,
    pad,
    dt,
):
    """:func:`p2g_lanes_records` and, per node (a, b), FLIP's momentum before forces
    w (m_p v_p + m_p C_p (x_i - x_p)) (the records with the affine part m_p C_p alone), from one
    evaluation of the stencil."""
    inv_h = 1.0 / h
    b0, f0, w0, b1, f1, w1 = stencil_lanes(x, blk, h, pad, nx, ny)
    mp = mass[blk, 0]
    kv = dt * vol[blk, 0] * 4.0 * inv_h * inv_h
    m00, m01, m10, m11 = mp * C[blk, 0], mp * C[blk, 1], mp * C[blk, 2], mp * C[blk, 3]
    a00 = m00 - kv * sigma[blk, XX]
    a01 = m01 - kv * sigma[blk, XZ]
    a10 = m10 - kv * sigma[blk, XZ]
    a11 = m11 - kv * sigma[blk, ZZ]
    mvx, mvz = mp * v[blk, 0], mp * v[blk, 1]
    q0x = mvx - h * (a00 * f0 + a01 * f1)
    q0z = mvz - h * (a10 * f0 + a11 * f1)
    o0x = mvx - h * (m00 * f0 + m01 * f1)
    o0z = mvz - h * (m10 * f0 + m11 * f1)
    records = [
        (
            w0[a] * w1[b] * (q0x + h * (a * a00 + b * a01)),
            w0[a] * w1[b] * (q0z + h * (a * a10 + b * a11)),
            w0[a] * w1[b] * mp,
        )
        for a in ti.static(range(3))
        for b in ti.static(range(3))
    ]
    olds = [
        (w0[a] * w1[b] * (o0x + h * (a * m00 + b * m01)), w0[a] * w1[b] * (o0z + h * (a * m10 + b * m11)))
        for a in ti.static(range(3))
        for b in ti.static(range(3))
    ]
    return b0, b1, records, olds


@ti.func
def add_block_records(gmp: ti.template(), c, p0, end, b0, b1, records, nx, ny, lo0, hi0, lo1, hi1):
    """The 9 records of each lane of a block (points p0 ... p0 + LANES - 1 below ``end``), point after
    point, into copy c of ``gmp`` (one vector load, add and store per node, ``grid.record_width``) at their
    base nodes (b0, b1); returns the node box (i0, i1, j0, j1) widened to them."""
    for k in ti.static(range(LANES)):
        if p0 + k < end:  # the last block's pads (copies of the last point) are not added
            i, j = ti.cast(b0[k], ti.i32), ti.cast(b1[k], ti.i32)
            first = record_index(c, i, j, nx, ny)
            for a in ti.static(range(3)):
                for b in ti.static(range(3)):
                    r, rec = first + a * ny + b, records[a * 3 + b]
                    gmp[r] = gmp[r] + make_record(gmp, rec[0][k], rec[1][k], rec[2][k])
            lo0, lo1 = ti.min(lo0, i), ti.min(lo1, j)
            hi0, hi1 = ti.max(hi0, i + 3), ti.max(hi1, j + 3)
    return lo0, hi0, lo1, hi1


@ti.func
def add_block_records_flip(
    gmp: ti.template(), gmo: ti.template(), c, p0, end, b0, b1, records, olds, nx, ny, lo0, hi0, lo1, hi1
):
    """:func:`add_block_records`, and FLIP's momenta ``olds`` into copy c of ``gmo`` at the same nodes."""
    for k in ti.static(range(LANES)):
        if p0 + k < end:
            i, j = ti.cast(b0[k], ti.i32), ti.cast(b1[k], ti.i32)
            first = record_index(c, i, j, nx, ny)
            for a in ti.static(range(3)):
                for b in ti.static(range(3)):
                    r, rec, old = first + a * ny + b, records[a * 3 + b], olds[a * 3 + b]
                    if ti.static(gmp.element_shape()[0] == 8):  # one record (Grid.flip_in_records)
                        zero = 0.0 * rec[2][k]
                        gmp[r] = gmp[r] + ti.Vector(
                            [rec[0][k], rec[1][k], rec[2][k], zero, old[0][k], old[1][k], zero, zero]
                        )
                    else:
                        gmp[r] = gmp[r] + make_record(gmp, rec[0][k], rec[1][k], rec[2][k])
                        gmo[r] = gmo[r] + ti.Vector([old[0][k], old[1][k]])
            lo0, lo1 = ti.min(lo0, i), ti.min(lo1, j)
            hi0, hi1 = ti.max(hi0, i + 3), ti.max(hi1, j + 3)
    return lo0, hi0, lo1, hi1


@ti.func
def scatter_chunk_lanes(
    c,
    first,
    end,
    n,
    x: ti.template(),
    v: ti.template(),
    C: ti.template(),
    mass: ti.template(),
    vol: ti.template(),
    sigma: ti.template(),
    gmp: ti.template(),
    nx,
    ny,
    h,
    pad,
    dt,
    gmo: ti.template(),
    flip: ti.template(),
):
    """The points of blocks [first, end) (below n) into grid copy c, a block at a time
    (:func:`p2g_lanes_records`), each point's 9 records still added one after the other in point
    order; returns the node box (i0, i1, j0, j1)."""
    i0, i1, j0, j1 = nx, 0, ny, 0
    for blk in range(first, end):
        if ti.static(flip):
            b0, b1, records, olds = p2g_lanes_records_flip(blk, x, v, C, mass, vol, sigma, nx, ny, h, pad, dt)
            i0, i1, j0, j1 = add_block_records_flip(
                gmp, gmo, c, blk * LANES, n, b0, b1, records, olds, nx, ny, i0, i1, j0, j1
            )
        else:
            b0, b1, records = p2g_lanes_records(blk, x, v, C, mass, vol, sigma, nx, ny, h, pad, dt)
            i0, i1, j0, j1 = add_block_records(gmp, c, blk * LANES, n, b0, b1, records, nx, ny, i0, i1, j0, j1)
    return i0, i1, j0, j1


def p2g_args(particles, grid, dt: float) -> tuple:
    """Arguments of :func:`p2g_kernel` for these particles and grid."""
    p = particles
    return (
        p.x,
        p.v,
        p.C,
        p.mass,
        p.vol,
        p.sigma,
        p.n,
        grid.mp_parts,
        grid.box_parts,
        *grid.shape,
        grid.h,
        grid.pad,
        dt,
        grid.fixed_scale or 1.0,
        grid.mo_parts,
    )


@ti.func
def g2p_point(x, gv: ti.template(), h, pad):
    """v_p = sum w v_i ;  C_p = (4/h^2) sum w v_i (x_i - x_p)^T  for the point at x.

    Summed axis by axis: with x_i - x_p = h (o - f) for the stencil offset o = (a, b) and the
    fractional position f, C_p = (4/h) [sum w v_i o^T - v_p f^T], and the sums over b are done
    once per a (w = w_a w_b): about half the flops of the 9 outer products.
    """
    inv_h = 1.0 / h
    base, fx, w = quadratic_weights(x, inv_h, pad, gv.shape[0], gv.shape[1])
    s0 = ti.Vector([0.0, 0.0])  # sum w v_i
    sa = ti.Vector([0.0, 0.0])  # sum w v_i a
    sb = ti.Vector([0.0, 0.0])  # sum w v_i b
    for a in ti.static(range(3)):
        r0 = ti.Vector([0.0, 0.0])  # sum_b w_b v_ab
        rb = ti.Vector([0.0, 0.0])  # sum_b w_b v_ab b
        for b in ti.static(range(3)):
            wv = w[b][1] * gv[base[0] + a, base[1] + b]
            r0 += wv
            if ti.static(b > 0):
                rb += b * wv
        s0 += w[a][0] * r0
        if ti.static(a > 0):
            sa += (a * w[a][0]) * r0
        sb += w[a][0] * rb
    k = 4.0 * inv_h
    new_C = k * ti.Matrix(
        [[sa[0] - s0[0] * fx[0], sb[0] - s0[0] * fx[1]], [sa[1] - s0[1] * fx[0], sb[1] - s0[1] * fx[1]]]
    )
    return s0, new_C


@ti.func
def g2p_point_linear(x, gv: ti.template(), h, pad):
    """v_p = sum w v_i ;  L_p = sum v_i (grad w)^T  with the linear shape functions of the point's cell."""
    inv_h = 1.0 / h
    base, fx, w = linear_weights(x, inv_h, pad, gv.shape[0], gv.shape[1])
    s0 = ti.Vector([0.0, 0.0])
    L = ti.Matrix([[0.0, 0.0], [0.0, 0.0]])
    for a in ti.static(range(2)):
        for b in ti.static(range(2)):
            vi = gv[base[0] + a, base[1] + b]
            s0 += (w[a][0] * w[b][1]) * vi
            L += vi.outer_product(ti.Vector([(2 * a - 1) * w[b][1], (2 * b - 1) * w[a][0]]))  # h grad w_ab
    return s0, inv_h * L


@ti.func
def interpolate_point(x, g: ti.template(), h, pad, linear: ti.template()):
    """sum w_i g_i over the stencil of the point at x (a grid field of 2-vectors): the 3 x 3 nodes of
    the quadratic B-splines, or with ``linear`` the 2 x 2 of the point's cell."""
    s = ti.Vector([0.0, 0.0])
    if ti.static(linear):
        base, fx, w = linear_weights(x, 1.0 / h, pad, g.shape[0], g.shape[1])
        for a in ti.static(range(2)):
            for b in ti.static(range(2)):
                s += (w[a][0] * w[b][1]) * g[base[0] + a, base[1] + b]
    else:
        base, fx, w = quadratic_weights(x, 1.0 / h, pad, g.shape[0], g.shape[1])
        for a in ti.static(range(3)):
            for b in ti.static(range(3)):
                s += (w[a][0] * w[b][1]) * g[base[0] + a, base[1] + b]
    return s


@ti.func
def exp_near_zero(x):
    """exp(x): a degree-5 Taylor polynomial for |x| < 0.01 (relative error < 2e-15), else ti.exp.

    The volume update's dt tr(L) is ~1e-4 per step; the libm call cost ~10 % of G2P on CPU.
    """
    r = 0.0 * x
    if ti.abs(x) < 0.01:
        r = 1.0 + x * (1.0 + x * (0.5 + x * (1.0 / 6.0 + x * (1.0 / 24.0 + x * (1.0 / 120.0)))))
    else:
        r = ti.exp(x)
    return r


@ti.func
def quadratic_weights_lanes(X, n: int):
    """Base node (as a float), fractional offset and the 3 B-spline weights along one axis for the
    lanes' grid coordinates X = x / h + pad (the lane form of :func:`quadratic_weights`)."""
    base = ti.math.clamp(ti.floor(X - 0.5), 0.0, ti.cast(n - 3, float))
    f = X - base
    return base, f, [0.5 * (1.5 - f) ** 2, 0.75 - (f - 1.0) ** 2, 0.5 * (f - 0.5) ** 2]


@ti.func
def stencil_lanes(x: ti.template(), blk, h, pad, nx: int, ny: int):
    """:func:`quadratic_weights_lanes` along both axes for the positions ``x`` of the points of
    block ``blk`` on an nx x ny grid: (b0, f0, w0, b1, f1, w1)."""
    inv_h = 1.0 / h
    b0, f0, w0 = quadratic_weights_lanes(x[blk, 0] * inv_h + pad, nx)
    b1, f1, w1 = quadratic_weights_lanes(x[blk, 1] * inv_h + pad, ny)
    return b0, f0, w0, b1, f1, w1


@ti.func
def lane_nodes(base):
    """The lanes' base node indices (a list of integers) from their float base vector."""
    return [ti.cast(base[k], ti.i32) for k in ti.static(range(LANES))]


@ti.func
def g2p_lanes(x: ti.template(), blk, gv: ti.template(), h, pad, gv_old: ti.template(), flip: ti.template()):
    """:func:`g2p_point` for the LANES points of block ``blk``, each component a vector over them:
    returns (v_x, v_z), the rows of C_p = (4/h) [sum w v_i o^T - v_p f^T] (same sums, same order) and,
    with ``flip``, sum w v_old_i (else zeros). The grid is read one lane at a time (a gather);
    everything else is vector arithmetic."""
    inv_h = 1.0 / h
    b0, f0, w0, b1, f1, w1 = stencil_lanes(x, blk, h, pad, gv.shape[0], gv.shape[1])
    i0, i1 = lane_nodes(b0), lane_nodes(b1)
    zero = ti.Vector([0.0] * LANES)
    s0x, s0z, sax, saz, sbx, sbz = zero, zero, zero, zero, zero, zero
    ox, oz = zero, zero  # FLIP: sum w v_old_i
    for a in ti.static(range(3)):
        r0x, r0z, rbx, rbz = zero, zero, zero, zero  # sum_b w_b v_ab, sum_b w_b v_ab b
        for b in ti.static(range(3)):
            gx = ti.Vector([gv[i0[k] + a, i1[k] + b][0] for k in ti.static(range(LANES))])
            gz = ti.Vector([gv[i0[k] + a, i1[k] + b][1] for k in ti.static(range(LANES))])
            if ti.static(flip):
                wab = w0[a] * w1[b]
                ox += wab * ti.Vector([gv_old[i0[k] + a, i1[k] + b][0] for k in ti.static(range(LANES))])
                oz += wab * ti.Vector([gv_old[i0[k] + a, i1[k] + b][1] for k in ti.static(range(LANES))])
            wx, wz = w1[b] * gx, w1[b] * gz
            r0x += wx
            r0z += wz
            if ti.static(b > 0):
                rbx += b * wx
                rbz += b * wz
        s0x += w0[a] * r0x
        s0z += w0[a] * r0z
        if ti.static(a > 0):
            sax += (a * w0[a]) * r0x
            saz += (a * w0[a]) * r0z
        sbx += w0[a] * rbx
        sbz += w0[a] * rbz
    k = 4.0 * inv_h
    return (s0x, s0z, k * (sax - s0x * f0), k * (sbx - s0x * f1), k * (saz - s0z * f0), k * (sbz - s0z * f1), ox, oz)


@ti.func
def add_plastic_strain(eps_p: ti.template(), gdot_p: ti.template(), p, dgamma, dt):
    """Point p's plastic shear strain grows by dgamma this step; its rate is dgamma / dt."""
    set_scalar(eps_p, p, get_scalar(eps_p, p) + dgamma)
    set_scalar(gdot_p, p, dgamma / dt)


@ti.func
def add_plastic_strain_lanes(eps_p: ti.template(), gdot_p: ti.template(), blk, dgamma, dt):
    """:func:`add_plastic_strain` for the points of block ``blk`` (dgamma a vector over them)."""
    eps_p[blk, 0] = eps_p[blk, 0] + dgamma
    gdot_p[blk, 0] = dgamma / dt


@ti.func
def any_lane(mask) -> bool:
    """True if any lane of ``mask`` is set. In an unscalarised kernel (Taichi 1.7.4) a mask's
    ``.any()`` and its elements read one by one come out false whatever the lanes hold; ``ti.select``
    on the mask is right, so the mask is read through it, as a vector of 1.0 / 0.0."""
    flags = ti.select(mask, 1.0, 0.0)
    total = 0.0
    for k in ti.static(range(LANES)):
        total += flags[k]
    return total > 0.0


@ti.func
def exp_near_zero_lanes(x):
    """:func:`exp_near_zero` on a vector: the polynomial, and ti.exp only when a lane needs it."""
    r = 1.0 + x * (1.0 + x * (0.5 + x * (1.0 / 6.0 + x * (1.0 / 24.0 + x * (1.0 / 120.0)))))
    far = (x >= 0.01) | (x <= -0.01)  # |x| >= 0.01 (no ti.abs on an unscalarised vector)
    if any_lane(far):
        r = ti.select(far, ti.Vector([ti.exp(x[k]) for k in ti.static(range(LANES))]), r)  # lane by lane
    return r


_G2P_KERNELS: dict = {}


def g2p_kernel(stress_update, n_params: int = 4, lanes: bool = False, flip: bool = False, linear: bool = False):
    """G2P + density + stress kernel for a material ``ti.func`` taking ``n_params`` parameters
    (one compiled kernel per law, parameter count and form).

    The stages are fused in one pass over the points to read and write each point once:
    G2P (velocity, position, velocity gradient), density v_p *= exp(dt tr L), stress update.
    The volume stops growing at m_p / rho_floor: a point alone in its stencil gets back its own
    affine velocity field from the grid, so in flight it keeps the velocity gradient it left the
    bed with, and exp(dt tr L) would grow without bound (float overflow, then NaN; seen at 150 RPM
    on the runner, docs/mpm.md).

    ``lanes`` (the CPU's): vectorised over LANES points. Taichi's CPU backend emits scalar code for
    a loop over points (it does not vectorise across iterations: an ndarray index is linearised in
    32-bit arithmetic that LLVM cannot prove consecutive). With ``lanes`` each iteration takes LANES
    consecutive points (a block of the particle arrays, see particles) and every per-point quantity
    is a vector over them, so the arithmetic is SIMD and each component of the points is one vector
    load and store; the grid reads stay per lane, and the law is ``stress_update.components``
    (branch-free, see ``constitutive._make_update``). Such a kernel must be compiled with Taichi's
    ``real_matrix_scalarize`` off (``backend.unscalarized``; the step does it, see
    ``step_graph.Launch.unscalarized``), otherwise Taichi splits the vectors back into scalars.
    Both forms update every slot of the blocks, the last block's pads too (copies of the last point,
    they stay copies).

    ``flip``: the last two arguments, the grid velocity before forces (``Grid.v_old``)
    and FLIP's share of the new velocity (``Solver.flip``), are used; without it they are not
    touched (placeholders). ``linear`` (one-point only): linear shape functions (:func:`g2p_point_linear`).
    """
    key = (stress_update, n_params, lanes, flip, linear)
    if key in _G2P_KERNELS:
        return _G2P_KERNELS[key]
    if linear and lanes:
        raise ValueError("the vectorised G2P is quadratic only: linear shape functions run the one-point kernel")
    gather = g2p_point_linear if linear else g2p_point
    law = stress_update.components

    @ti.func
    def point_after_g2p(
        p,
        xp,
        v_point,
        v_grid,
        L,
        x: ti.template(),
        v: ti.template(),
        C: ti.template(),
        mass: ti.template(),
        vol: ti.template(),
        sigma: ti.template(),
        s_yy: ti.template(),
        eps_p: ti.template(),
        gdot_p: ti.template(),
        dt,
        prm,
        inv_rho_floor,
    ):
        """Point p's new velocity v_point, C_p = L, position moved with the grid's v_grid, density and stress."""
        set_vec2(v, p, v_point)
        set_mat2(C, p, L)
        set_vec2(x, p, xp + dt * v_grid)
        m = get_scalar(mass, p)
        vp = ti.min(
            get_scalar(vol, p) * exp_near_zero(dt * L.trace()), m * inv_rho_floor
        )  # v_p *= exp(dt tr D), <= m_p / rho_floor
        set_scalar(vol, p, vp)
        sig, syy, dgamma = stress_update(get_sym2(sigma, p), get_scalar(s_yy, p), L, m / vp, dt, prm)
        set_sym2(sigma, p, sig)
        set_scalar(s_yy, p, syy)
        add_plastic_strain(eps_p, gdot_p, p, dgamma, dt)

    @ti.kernel
    def g2p_density_stress(
        x: ti.types.ndarray(),
        v: ti.types.ndarray(),
        C: ti.types.ndarray(),
        mass: ti.types.ndarray(),
        vol: ti.types.ndarray(),
        sigma: ti.types.ndarray(),
        s_yy: ti.types.ndarray(),
        eps_p: ti.types.ndarray(),
        gdot_p: ti.types.ndarray(),
        gv: ti.types.ndarray(),
        h: float,
        pad: int,
        dt: float,
        prm: ti.types.vector(n_params, float),
        inv_rho_floor: float,
        gv_old: ti.types.ndarray(),
        share: float,
    ):
        if ti.static(not lanes):
            ti.loop_config(serialize=backend.SERIAL_LOOPS)
            for p in range(x.shape[0] * LANES):  # a range-for: a struct-for over an ndarray is ~9x slower on CPU
                xp = get_vec2(x, p)
                new_v, L = gather(xp, gv, h, pad)
                v_point = new_v
                if ti.static(flip):  # v_p <- share (v_p + sum w (v_i - v_old_i)) + (1 - share) sum w v_i
                    v_flip = get_vec2(v, p) + new_v - interpolate_point(xp, gv_old, h, pad, linear)
                    v_point = share * v_flip + (1.0 - share) * new_v
                point_after_g2p(
                    p, xp, v_point, new_v, L, x, v, C, mass, vol, sigma, s_yy, eps_p, gdot_p, dt, prm, inv_rho_floor
                )
        else:
            ti.loop_config(serialize=backend.SERIAL_LOOPS)
            for blk in range(x.shape[0]):
                v0, v1, l00, l01, l10, l11, o0, o1 = g2p_lanes(x, blk, gv, h, pad, gv_old, flip)
                m = mass[blk, 0]
                # v_p *= exp(dt tr D), <= m_p / rho_floor
                vp = ti.min(vol[blk, 0] * exp_near_zero_lanes(dt * (l00 + l11)), m * inv_rho_floor)
                t_xx, t_zz, t_xz, t_yy, dgamma = law(
                    sigma[blk, XX], sigma[blk, ZZ], sigma[blk, XZ], s_yy[blk, 0], l00, l01, l10, l11, m / vp, dt, prm
                )
                if ti.static(flip):  # v_p <- sum w v_i + share (v_p - sum w v_old_i)
                    v[blk, 0], v[blk, 1] = v0 + share * (v[blk, 0] - o0), v1 + share * (v[blk, 1] - o1)
                else:
                    v[blk, 0], v[blk, 1] = v0, v1
                C[blk, 0], C[blk, 1], C[blk, 2], C[blk, 3] = l00, l01, l10, l11
                x[blk, 0], x[blk, 1] = x[blk, 0] + dt * v0, x[blk, 1] + dt * v1
                vol[blk, 0] = vp
                sigma[blk, XX], sigma[blk, ZZ], sigma[blk, XZ] = t_xx, t_zz, t_xz
                s_yy[blk, 0] = t_yy
                add_plastic_strain_lanes(eps_p, gdot_p, blk, dgamma, dt)

    _G2P_KERNELS[key] = g2p_density_stress
    return g2p_density_stress
