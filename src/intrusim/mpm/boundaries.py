"""Domain walls on the grid: left (x = 0), right (x = Lx), floor (z = 0); top is open.

Each wall is frictionless, sticky (v = 0) or Coulomb (friction mu); a non-sticky wall only acts
on approaching nodes, so material may leave it (no tension).
"""


import taichi as ti

from .config import BoundaryConfig
from .contact import coulomb_project
from .grid import Grid

KIND_CODE = {"frictionless": 0, "sticky": 1, "coulomb": 2}


@ti.func
def wall_velocity(v, n, kind: int, mu: float):
    """Grid velocity after a static wall with inward normal n."""
    out = v
    if kind == 1:
        out = v * 0.0
    else:
        mu_eff = mu if kind == 2 else 0.0
        out = coulomb_project(v, n, mu_eff)
    return out


@ti.func
def wall_node(gm: ti.template(), gv: ti.template(), i, j, h, pad, lx, kinds, mus):
    """Wall condition of node (i, j) if it lies on or beyond a wall (left, right, floor)."""
    if gm[i, j] > 0.0:
        xi = (i - pad) * h
        zj = (j - pad) * h
        v = gv[i, j]
        if xi <= 0.0:
            v = wall_velocity(v, ti.Vector([1.0, 0.0]), kinds[0], mus[0])
        if xi >= lx - 1e-6 * h:
            v = wall_velocity(v, ti.Vector([-1.0, 0.0]), kinds[1], mus[1])
        if zj <= 0.0:
            v = wall_velocity(v, ti.Vector([0.0, 1.0]), kinds[2], mus[2])
        gv[i, j] = v


@ti.kernel
def apply_walls(
    gm: ti.types.ndarray(), gv: ti.types.ndarray(), h: float, pad: int, lx: float,
    kinds: ti.types.vector(3, int), mus: ti.types.vector(3, float),
):
    """Walls on the boundary strips only (the nodes at or beyond x = 0, x = Lx, z = 0)."""
    n0, n1 = gm.shape[0], gm.shape[1]
    i_right = n0 - pad - 1  # node at x = Lx
    for i, j in ti.ndrange(pad + 1, n1):
        wall_node(gm, gv, i, j, h, pad, lx, kinds, mus)
    for i, j in ti.ndrange((i_right, n0), n1):
        wall_node(gm, gv, i, j, h, pad, lx, kinds, mus)
    for i, j in ti.ndrange((pad + 1, i_right), pad + 1):
        wall_node(gm, gv, i, j, h, pad, lx, kinds, mus)


class Walls:
    """Boundary-condition object built from :class:`BoundaryConfig`."""

    def __init__(self, cfg: BoundaryConfig):
        walls = (cfg.left, cfg.right, cfg.floor)
        self.kinds = tuple(KIND_CODE[w.kind] for w in walls)
        self.mus = tuple(float(w.mu) for w in walls)

    def apply(self, grid: Grid) -> None:
        apply_walls(grid.m, grid.v, grid.h, grid.pad, grid.size[0], self.kinds, self.mus)
