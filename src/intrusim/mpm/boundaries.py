"""Domain walls on the grid: left (x = 0), right (x = Lx), floor (z = 0); the top has no wall.

Each wall is frictionless, sticky (v = 0) or Coulomb (friction mu); a non-sticky wall only acts
on approaching nodes, so material may leave it (no tension). An "open" side has no wall: the nodes
on and beyond it keep their velocity, and the points that leave through it are removed as outflow
(``Solver.check_guards``).
"""

import taichi as ti

from .config import BoundaryConfig
from .coulomb import coulomb_project

KIND_CODE = {"frictionless": 0, "sticky": 1, "coulomb": 2, "open": 3}
SIDES = ("left", "right", "floor", "top")


@ti.func
def wall_velocity(v, n, kind: int, mu: float):
    """Grid velocity after a static wall with inward normal n."""
    out = v
    if kind == 1:
        out = v * 0.0
    elif kind != 3:  # 3: open, no wall
        mu_eff = mu if kind == 2 else 0.0
        out = coulomb_project(v, n, mu_eff)
    return out


class Walls:
    """Boundary-condition object built from :class:`BoundaryConfig` (applied by ``grid.grid_update``)."""

    def __init__(self, cfg: BoundaryConfig):
        walls = (cfg.left, cfg.right, cfg.floor)
        self.kinds = tuple(KIND_CODE[w.kind] for w in walls)
        self.mus = tuple(float(w.mu) for w in walls)
        # the sides points leave through as outflow, of SIDES
        self.open_sides = tuple(name for name, w in zip(SIDES, walls) if w.kind == "open")
        self.open_sides += ("top",) if cfg.top == "open" else ()
