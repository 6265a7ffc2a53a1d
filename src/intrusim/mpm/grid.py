"""Background grid: node mass and momentum/velocity, with a padding of ``pad`` cells, and its update.

Node (i, j) sits at ((i - pad) h, (j - pad) h); the physical domain is [0, Lx] x [0, Lz].
"""

import numpy as np
import taichi as ti

from . import backend
from .backend import info
from .boundaries import wall_velocity
from .exact_sums import fixed_point_scale

PAD = 3  # cells of padding around the domain, enough for the quadratic stencil of escaping points


class Grid:
    """Grid arrays for a domain of ``cells`` cells of size ``h`` (m)."""

    def __init__(
        self,
        size: tuple[float, float],
        cells: tuple[int, int],
        chunks: int = 1,
        fixed_density: float | None = None,
        flip: bool = False,
        pad: int = PAD,
        flip_in_records: bool = False,
    ):
        real = info().real
        self.size = (float(size[0]), float(size[1]))
        self.cells = (int(cells[0]), int(cells[1]))
        self.h = self.size[0] / self.cells[0]
        self.pad = int(pad)  # >= PAD; more where points leave through open sides (Solver)
        if self.pad < PAD:
            raise ValueError(f"grid padding must be at least {PAD} cells, got {pad}")
        self.shape = (self.cells[0] + 2 * self.pad + 1, self.cells[1] + 2 * self.pad + 1)
        self.chunks = int(chunks)
        if not 1 <= self.chunks <= 31:
            raise ValueError(f"P2G chunks must be 1-31 (a bit each in a column mask), got {chunks}")
        # P2G targets: one private copy per chunk of points (CPU), summed in the grid update
        # (momentum x, momentum z, mass) per node: one record per scatter target, all copies in one
        # array (see record_index); a record is read and written as one vector (record_width)
        # fixed_density (one copy, atomic adds): the records are 64-bit integers, value * fixed_scale
        # with the scale of a node's mass fixed_density h^2, so that atomic sums are exact and do not
        # depend on their order (see fixed_point_scale)
        self.fixed_scale = None
        if fixed_density is not None:
            if self.chunks != 1:
                raise ValueError("fixed-point P2G sums use one grid copy (chunks = 1)")
            self.fixed_scale = fixed_point_scale(fixed_density * self.h * self.h)
        self.inv_scale = 1.0 if self.fixed_scale is None else 1.0 / self.fixed_scale
        dtype = real if self.fixed_scale is None else ti.i64
        # flip_in_records (FLIP with the vectorised P2G, private copies): FLIP's momentum before forces in
        # the same records, (m v_x, m v_z, m, 0, (m v_x)_old, (m v_z)_old, 0, 0): one 32-byte add per node
        # instead of a second array (P2G 1.25 -> 1.11 ms at 64k points on 2 threads, docs/mpm.md)
        self.flip_in_records = bool(flip_in_records and flip and self.chunks > 1)
        width = 8 if self.flip_in_records else record_width(self.chunks > 1)
        self.mp_parts = ti.Vector.ndarray(
            width,
            dtype,  # kg/s, kg/m
            shape=self.chunks * self.shape[0] * self.shape[1],
        )
        self.m = ti.ndarray(real, shape=self.shape)  # node mass, kg/m
        self.v = ti.Vector.ndarray(2, real, shape=self.shape)  # node velocity, m/s
        # FLIP (TransferConfig.flip): the momentum before forces in copies as mp_parts', and the grid
        # velocity it gives; one-element placeholders otherwise (the kernels take them, and skip them)
        self.flip = bool(flip)
        n_old = self.chunks * self.shape[0] * self.shape[1] if self.flip and not self.flip_in_records else 1
        self.mo_parts = ti.Vector.ndarray(2, dtype, shape=n_old)  # kg/s per m
        self.v_old = ti.Vector.ndarray(2, real, shape=self.shape if self.flip else (1, 1))  # m/s
        # node index box [i0, i1) x [j0, j1) each P2G chunk touched, and the box of the last update
        self.box_parts = ti.ndarray(ti.i32, shape=(self.chunks, 4))
        self.box = ti.ndarray(ti.i32, shape=4)  # zeros: an empty box
        # per column i: bit c set if chunk c's box spans it, and the lowest and highest such c
        self.col_mask = ti.ndarray(ti.i32, shape=(self.shape[0], 3))

    def node_positions(self) -> np.ndarray:
        """(nx, nz, 2) node coordinates, m."""
        i = (np.arange(self.shape[0]) - self.pad) * self.h
        j = (np.arange(self.shape[1]) - self.pad) * self.h
        return np.stack(np.meshgrid(i, j, indexing="ij"), axis=-1)


def record_width(private_copies: bool) -> int:
    """Numbers per scatter record, (m v_x, m v_z, m) or a fluidity source: padded with a zero to 4 in
    private copies (the CPU's chunked scatters: a node's read-modify-write is one aligned 16-byte
    vector load, add and store; P2G ~20 % faster than with 3, docs/performance.md), 3 where threads
    add atomically (a GPU: no fourth atomic add per node)."""
    return 4 if private_copies else 3


@ti.func
def make_record(parts: ti.template(), x, z, m):
    """The record (x, z, m) in the width of ``parts``' records (see record_width; 8: FLIP's records,
    ``Grid.flip_in_records``, here with no FLIP momentum)."""
    if ti.static(parts.element_shape()[0] == 8):
        return ti.Vector([x, z, m, 0.0 * m, 0.0 * m, 0.0 * m, 0.0 * m, 0.0 * m])
    elif ti.static(parts.element_shape()[0] == 4):
        return ti.Vector([x, z, m, 0.0 * m])
    else:
        return ti.Vector([x, z, m])


@ti.func
def zero_record(parts: ti.template(), k):
    """parts[k] = 0, component by component (a product by zero would keep a NaN)."""
    for e in ti.static(range(parts.element_shape()[0])):
        parts[k][e] = 0


@ti.func
def record_index(c, i, j, nx, ny):
    """Index in ``Grid.mp_parts`` of node (i, j)'s record (m v_x, m v_z, m) in P2G copy c (nx x ny nodes)."""
    return (c * nx + i) * ny + j


@ti.func
def union_box(box_parts: ti.template(), nx, ny):
    """The node box [i0, i1, j0, j1) holding every copy's box ``box_parts[c]`` (a serial reduction)."""
    b0, b1, b2, b3 = nx, 0, ny, 0
    ti.loop_config(serialize=True)
    for c in range(box_parts.shape[0]):
        b0 = ti.min(b0, box_parts[c, 0])
        b1 = ti.max(b1, box_parts[c, 1])
        b2 = ti.min(b2, box_parts[c, 2])
        b3 = ti.max(b3, box_parts[c, 3])
    return b0, b1, b2, b3


@ti.func
def wall_node_velocity(v, xi, zj, h, lx, kinds, mus):
    """Velocity of a node at (xi, zj) after the walls it lies on or beyond (left, right, floor)."""
    if xi <= 0.0:
        v = wall_velocity(v, ti.Vector([1.0, 0.0]), kinds[0], mus[0])
    if xi >= lx - 1e-6 * h:
        v = wall_velocity(v, ti.Vector([-1.0, 0.0]), kinds[1], mus[1])
    if zj <= 0.0:
        v = wall_velocity(v, ti.Vector([0.0, 1.0]), kinds[2], mus[2])
    return v


def _make_grid_update(flip: bool):
    @ti.kernel
    def grid_update(
        mp_parts: ti.types.ndarray(),
        box_parts: ti.types.ndarray(),
        box: ti.types.ndarray(),
        col_mask: ti.types.ndarray(),
        m: ti.types.ndarray(),
        v: ti.types.ndarray(),
        dt: float,
        gx: float,
        gz: float,
        h: float,
        pad: int,
        lx: float,
        kinds: ti.types.vector(3, int),
        mus: ti.types.vector(3, float),
        inv_scale: float,
        mo_parts: ti.types.ndarray(),
        v_old: ti.types.ndarray(),
    ):
        """m_i = sum of copies ;  v_i = (m v)_i / m_i + dt g, then the walls (left, right, floor).

        With ``flip`` also v_old_i = (m v)_old_i / m_i from the copies ``mo_parts``
        (FLIP's grid velocity before forces, see ``TransferConfig.flip``), zeroed as they are read.

        ``inv_scale``: 1 for copies of real numbers, 1 / scale for one copy of fixed-point integers.

        Only the nodes P2G touched this step (the union of the chunks' boxes) or last step (``box``)
        are visited, and of the P2G copies only those whose chunk's box holds the node (``col_mask``:
        a bit per chunk whose box spans the column, and the lowest and highest such chunk):
        elsewhere m and the copies are already zero.
        The copies are zeroed as they are read, ready for the next step; ``box`` becomes this step's box.
        """
        nc = box_parts.shape[0]
        nx, ny = m.shape[0], m.shape[1]
        i0, i1, j0, j1 = box[0], box[1], box[2], box[3]  # last step's box: reset it
        b0, b1, b2, b3 = union_box(box_parts, nx, ny)  # this step's box
        u0, u1, u2, u3 = ti.min(i0, b0), ti.max(i1, b1), ti.min(j0, b2), ti.max(j1, b3)
        ti.loop_config(serialize=backend.SERIAL_LOOPS)
        for i in range(u0, u1):
            mask, c_lo, c_hi = 0, nc, -1
            for c in range(nc):
                if box_parts[c, 0] <= i < box_parts[c, 1]:
                    mask |= 1 << c
                    c_lo = ti.min(c_lo, c)
                    c_hi = c
            col_mask[i, 0], col_mask[i, 1], col_mask[i, 2] = mask, c_lo, c_hi
        nj = ti.max(u3 - u2, 0)
        ti.loop_config(serialize=backend.SERIAL_LOOPS)
        for q in range(ti.max(u1 - u0, 0) * nj):  # range-for: struct-fors over ndarrays are slow on CPU
            i = u0 + q // nj
            j = u2 + q % nj
            mi = 0.0
            pi = ti.Vector([0.0, 0.0])
            po = ti.Vector([0.0, 0.0])  # FLIP: the momentum before forces
            mask = col_mask[i, 0]
            for c in range(
                col_mask[i, 1], col_mask[i, 2] + 1
            ):  # the copies whose chunk touched this node, in chunk order
                if (mask >> c) & 1 and box_parts[c, 2] <= j < box_parts[c, 3]:
                    k = record_index(c, i, j, nx, ny)
                    rec = mp_parts[k]  # float: the backend's real type (a no-op on real copies)
                    pi += ti.Vector([ti.cast(rec[0], float), ti.cast(rec[1], float)]) * inv_scale
                    mi += ti.cast(rec[2], float) * inv_scale
                    zero_record(mp_parts, k)
                    if ti.static(flip and mp_parts.element_shape()[0] == 8):  # in the records (flip_in_records)
                        po += ti.Vector([ti.cast(rec[4], float), ti.cast(rec[5], float)]) * inv_scale
                    elif ti.static(flip):
                        po += ti.Vector([ti.cast(mo_parts[k][0], float), ti.cast(mo_parts[k][1], float)]) * inv_scale
                        zero_record(mo_parts, k)
            m[i, j] = mi
            vi = ti.Vector([0.0, 0.0])
            if mi > 0.0:
                vi = wall_node_velocity(
                    pi / mi + dt * ti.Vector([gx, gz]), (i - pad) * h, (j - pad) * h, h, lx, kinds, mus
                )
            v[i, j] = vi
            if ti.static(flip):
                vo = ti.Vector([0.0, 0.0])
                if mi > 0.0:
                    vo = po / mi
                v_old[i, j] = vo
        box[0], box[1], box[2], box[3] = b0, b1, b2, b3

    return grid_update


_GRID_UPDATES = {flip: _make_grid_update(flip) for flip in (False, True)}


def grid_update_kernel(flip: bool = False):
    """The grid update kernel (``grid_update``), with or without FLIP's old grid velocity: a factory
    rather than a template flag, so that the kernel can be recorded in a ``ti.graph`` (see step_graph)."""
    return _GRID_UPDATES[bool(flip)]
