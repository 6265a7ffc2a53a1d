"""Exact sums in any order: 64-bit fixed point for the atomic adds of a GPU.

Float atomic adds round at each addition, in whatever order the threads take, so two runs of the
same state drift apart at round-off. Integer adds are exact in any order: a value is added as
round(value * 2^k), with 2^k chosen for the size of the values (``fixed_point_scale``), and the
sum is turned back into a float once.
"""

import numpy as np
import taichi as ti

FIXED_POINT_HEADROOM = 2.0**20  # fixed-point sums hold values up to ~1e6 times the reference


def fixed_point_scale(reference: float) -> float:
    """Scale of the 64-bit fixed-point atomic sums for values of size ``reference`` (a node's mass
    rho_c h^2, kg/m, and momenta of it times 1 m/s): the power of two 2^k with the largest k for which a
    sum up to ``FIXED_POINT_HEADROOM`` x ``reference`` still fits in 2^62. A value is stored as
    round(value * 2^k), so each term is exact to ~2e-13 x ``reference`` and the sum is exact,
    whatever order the threads add in (float atomic adds round at each addition, in the order
    the threads happen to take)."""
    if not reference > 0 or not np.isfinite(reference):
        raise ValueError(f"fixed-point reference must be a positive number, got {reference!r}")
    return float(2.0 ** np.floor(np.log2(2.0**62 / (FIXED_POINT_HEADROOM * reference))))


@ti.func
def to_fixed(value, scale):
    """round(value * scale) as 64-bit integers: a term of an exact fixed-point sum."""
    return ti.cast(ti.round(value * scale), ti.i64)
