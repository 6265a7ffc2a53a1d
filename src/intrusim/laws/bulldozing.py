"""Bulldozing resistance: the grains ahead of a sunken body resist its advance (an extension of DRFT).

    F_b = -k_b (1/2) K_p rho g W d^2  tanh(v_x / v_reg),      K_p = (1 + sin phi) / (1 - sin phi)

with d the depth of the body's lowest point below the undisturbed free surface (a wheel's or a
runner's outer circle: ``surface - (z - R)``), W the out-of-plane width, K_p Rankine's passive
earth-pressure coefficient of a medium of internal friction mu = tan phi, and k_b a dimensionless
coefficient (k_b = 1: Rankine's passive wall of height d; Bekker's bulldozing term of
terramechanics, Wong, *Theory of Ground Vehicles*, ch. 2). It acts horizontally, against the
body's travel, through the point 2/3 d below the surface (the resultant of a pressure that grows
linearly with depth).

This term is NOT in the paper. RFT sums forces that each surface element would feel alone, from
its own velocity; our MPM wheel is held back by grains that resist the advance of the whole body
while its lower rim slides backward, which no element's velocity carries (research/notes/results_log.md, "The
MPM medium's own RFT map"). F_b is the simplest body-level form of that resistance; k_b is fitted
on MPM runs (:mod:`intrusim.analysis.calibration`, parameter ``bulldozing``). The sign uses
tanh(v_x / v_reg), a rate-independent Coulomb-like resistance smoothed over |v_x| < ~v_reg so the
implicit integrator's Newton iteration sees a continuous force through v_x = 0.
"""

from __future__ import annotations

import math

import numba
import numpy as np

from intrusim._checks import finite_array, non_negative, positive

V_REG = 0.01
"""m/s: the speed over which the resistance's sign is smoothed (tanh(v_x / V_REG) = 0.76 at V_REG)."""


def passive_coefficient(mu: float) -> float:
    """Rankine's passive earth-pressure coefficient K_p = (1 + sin phi) / (1 - sin phi), phi = atan(mu)."""
    s = math.sin(math.atan(non_negative("mu", mu)))
    return (1.0 + s) / (1.0 - s)


def bulldozing_scale(coefficient: float, mu: float, rho: float, gravity: float, width: float) -> float:
    """k_b (1/2) K_p rho g W, N/m^2: the resistance per squared depth (F_b = scale d^2).

    Parameters
    ----------
    coefficient : k_b, dimensionless (0: no bulldozing; 1: Rankine's passive wall).
    mu : internal friction coefficient of the medium (tan of the friction angle).
    rho : bulk density of the medium, kg/m^3.
    gravity : m/s^2.
    width : out-of-plane width of the body, m.
    """
    k = non_negative("bulldozing coefficient", coefficient)
    return (
        k
        * 0.5
        * passive_coefficient(mu)
        * non_negative("rho", rho)
        * positive("gravity", gravity)
        * positive("width", width)
    )


@numba.njit(cache=True)
def bulldozing_wrench(scale: float, radius: float, surface_z: float, z: float, vx: float) -> tuple[float, float]:
    """(fx, moment) of F_b on a body centred at height z with outer radius ``radius``.

    fx = -scale d^2 tanh(vx / V_REG) with d = max(0, surface_z - (z - radius)); it acts at the
    height surface_z - 2 d / 3, so its moment about the centre is -(surface_z - 2 d / 3 - z) fx
    (the moment convention of the element sums: r_x f_z - r_z f_x).
    """
    d = surface_z - (z - radius)
    if scale == 0.0 or d <= 0.0:
        return 0.0, 0.0
    fx = -scale * d * d * np.tanh(vx / V_REG)
    rz = surface_z - 2.0 * d / 3.0 - z
    return fx, -rz * fx


def bulldozing_force(scale: float, depth, vx) -> np.ndarray:
    """Vectorised F_b = -scale d^2 tanh(vx / V_REG), N, for arrays of depth d (m; <= 0: no contact)
    and travel speed vx (m/s); ``scale`` from :func:`bulldozing_scale`, N/m^2."""
    d = np.maximum(finite_array("depth", depth), 0.0)
    return -non_negative("scale", scale) * d * d * np.tanh(finite_array("vx", vx) / V_REG)
