"""Coulomb contact of a velocity on a surface: no penetration, no tension, friction mu (SPEC 1).

The one law both contacts of the grid apply: the domain walls (``boundaries.wall_velocity``) and
the rigid bodies (``contact``), each to the velocity relative to its surface.
"""

import taichi as ti


@ti.func
def coulomb_project(v_rel, n, mu):
    """Velocity after a no-penetration, Coulomb-friction contact with unit normal n (no tension)."""
    vn = v_rel.dot(n)
    out = v_rel
    if vn < 0.0:
        vt = v_rel - vn * n
        vt_norm = vt.norm()
        # |dv_t| <= mu |dv_n| with |dv_n| = -vn
        if vt_norm > -mu * vn:
            out = vt * (1.0 + mu * vn / vt_norm)
        else:
            out = vt * 0.0
    return out
