"""Background grid: node mass and momentum/velocity, with a padding of ``pad`` cells.

Node (i, j) sits at ((i - pad) h, (j - pad) h); the physical domain is [0, Lx] x [0, Lz].
"""


import numpy as np
import taichi as ti

from .backend import info

PAD = 3  # cells of padding around the domain, enough for the quadratic stencil of escaping points


class Grid:
    """Grid arrays for a domain of ``cells`` cells of size ``h`` (m)."""

    def __init__(self, size: tuple[float, float], cells: tuple[int, int]):
        real = info().real
        self.size = (float(size[0]), float(size[1]))
        self.cells = (int(cells[0]), int(cells[1]))
        self.h = self.size[0] / self.cells[0]
        self.pad = PAD
        self.shape = (self.cells[0] + 2 * PAD + 1, self.cells[1] + 2 * PAD + 1)
        self.m = ti.ndarray(real, shape=self.shape)  # kg/m
        self.v = ti.Vector.ndarray(2, real, shape=self.shape)  # momentum in P2G, then velocity

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
def clear_grid(m: ti.types.ndarray(), v: ti.types.ndarray()):
    """m_i = 0, (m v)_i = 0."""
    for I in ti.grouped(m):
        m[I] = 0.0
        v[I] = ti.Vector([0.0, 0.0])


@ti.kernel
def grid_momentum_update(
    m: ti.types.ndarray(), v: ti.types.ndarray(), dt: float, gx: float, gz: float
):
    """v_i = (m v)_i / m_i + dt g   (momentum balance on the grid, internal force already in (m v)_i)."""
    for I in ti.grouped(m):
        if m[I] > 0.0:
            v[I] = v[I] / m[I] + dt * ti.Vector([gx, gz])
