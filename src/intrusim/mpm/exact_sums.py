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


PLAIN, ATOMIC, FIXED = 0, 1, 2  # how a scatter adds into its target (scatter_add)


def sum_mode(private_copies: bool, fixed: bool) -> int:
    """The ``scatter_add`` mode of a kernel whose threads add into private copies (PLAIN, summed in
    a fixed order) or into one shared target (ATOMIC floats, or FIXED: 64-bit fixed point)."""
    if private_copies and fixed:
        raise ValueError("private copies sum in a fixed order already: no fixed point")
    return PLAIN if private_copies else FIXED if fixed else ATOMIC


@ti.func
def scatter_add(target: ti.template(), k, value, mode: ti.template(), scale):
    """target[k] += value: PLAIN (one thread owns the target), ATOMIC (a float atomic add: the sum's
    rounding depends on the threads' order) or FIXED (a 64-bit integer atomic add of
    round(value * scale): exact, so the sum is the same in any order)."""
    if ti.static(mode == FIXED):
        ti.atomic_add(target[k], to_fixed(value, scale))
    elif ti.static(mode == ATOMIC):
        ti.atomic_add(target[k], value)
    else:
        target[k] = target[k] + value
