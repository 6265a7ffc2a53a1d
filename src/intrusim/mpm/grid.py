"""Background grid: node mass and momentum/velocity, with a padding of ``pad`` cells.

Node (i, j) sits at ((i - pad) h, (j - pad) h); the physical domain is [0, Lx] x [0, Lz].
"""


import numpy as np
import taichi as ti

from .backend import info

PAD = 3  # cells of padding around the domain, enough for the quadratic stencil of escaping points


class Grid:
    """Grid arrays for a domain of ``cells`` cells of size ``h`` (m)."""

    def __init__(self, size: tuple[float, float], cells: tuple[int, int], chunks: int = 1):
        real = info().real
        self.size = (float(size[0]), float(size[1]))
        self.cells = (int(cells[0]), int(cells[1]))
        self.h = self.size[0] / self.cells[0]
        self.pad = PAD
        self.shape = (self.cells[0] + 2 * PAD + 1, self.cells[1] + 2 * PAD + 1)
        self.chunks = int(chunks)
        # P2G targets: one private copy per chunk of points (CPU), summed in the grid update
        self.m_parts = ti.ndarray(real, shape=(self.chunks, *self.shape))  # kg/m
        self.p_parts = ti.Vector.ndarray(2, real, shape=(self.chunks, *self.shape))  # kg/s
        self.m = ti.ndarray(real, shape=self.shape)  # node mass, kg/m
        self.v = ti.Vector.ndarray(2, real, shape=self.shape)  # node velocity, m/s

    def node_positions(self) -> np.ndarray:
        """(nx, nz, 2) node coordinates, m."""
        i = (np.arange(self.shape[0]) - self.pad) * self.h
        j = (np.arange(self.shape[1]) - self.pad) * self.h
        return np.stack(np.meshgrid(i, j, indexing="ij"), axis=-1)

    def index_box(self, center: tuple[float, float], radius: float) -> tuple[int, int, int, int]:
        """Node index range [i0, i1) x [j0, j1) covering a disc (clipped to the grid)."""
        cx, cz = center
        i0 = max(int(np.floor((cx - radius) / self.h)) + self.pad, 0)
        i1 = min(int(np.ceil((cx + radius) / self.h)) + self.pad + 1, self.shape[0])
        j0 = max(int(np.floor((cz - radius) / self.h)) + self.pad, 0)
        j1 = min(int(np.ceil((cz + radius) / self.h)) + self.pad + 1, self.shape[1])
        return i0, max(i1, i0), j0, max(j1, j0)


@ti.kernel
def clear_grid(m_parts: ti.types.ndarray(), p_parts: ti.types.ndarray()):
    """m_i = 0, (m v)_i = 0 in every P2G copy."""
    for I in ti.grouped(ti.ndrange(*m_parts.shape)):
        m_parts[I] = 0.0
        p_parts[I] = ti.Vector([0.0, 0.0])


@ti.kernel
def grid_momentum_update(
    m_parts: ti.types.ndarray(), p_parts: ti.types.ndarray(), m: ti.types.ndarray(),
    v: ti.types.ndarray(), dt: float, gx: float, gz: float,
):
    """m_i = sum of copies ;  v_i = (m v)_i / m_i + dt g   (internal force is already in (m v)_i).

    The P2G copies are zeroed as they are read, ready for the next step.
    """
    for i, j in ti.ndrange(m.shape[0], m.shape[1]):  # range-for: struct-fors over ndarrays are slow on CPU
        mi = 0.0
        pi = ti.Vector([0.0, 0.0])
        for c in range(m_parts.shape[0]):
            mi += m_parts[c, i, j]
            pi += p_parts[c, i, j]
            m_parts[c, i, j] = 0.0
            p_parts[c, i, j] = ti.Vector([0.0, 0.0])
        m[i, j] = mi
        v[i, j] = ti.Vector([0.0, 0.0])
        if mi > 0.0:
            v[i, j] = pi / mi + dt * ti.Vector([gx, gz])
