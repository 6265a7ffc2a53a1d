"""Rigid-body kinematics in the plane: body state, wrench, and world-frame element motion.

Frame: x horizontal (forward), z vertical (up). theta and omega are counter-clockwise
(rotating +x towards +z), so a wheel rolling forward in +x has omega < 0.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from intrusim._checks import finite
from intrusim.geometry import SurfaceElements


@dataclass(frozen=True)
class BodyState:
    """Position (m), orientation (rad), velocity (m/s) and angular velocity (rad/s) of a body."""

    x: float = 0.0
    z: float = 0.0
    theta: float = 0.0
    vx: float = 0.0
    vz: float = 0.0
    omega: float = 0.0

    def __post_init__(self) -> None:
        for name in ("x", "z", "theta", "vx", "vz", "omega"):
            object.__setattr__(self, name, finite(name, getattr(self, name)))

    def mirrored(self) -> "BodyState":
        """The mirror image under x -> -x."""
        return BodyState(-self.x, self.z, -self.theta, -self.vx, self.vz, -self.omega)


@dataclass(frozen=True)
class Wrench:
    """Force (N) and moment about the body reference point (N m, counter-clockwise) on a body."""

    fx: float
    fz: float
    moment: float

    def as_array(self) -> np.ndarray:
        return np.array([self.fx, self.fz, self.moment])


@dataclass(frozen=True)
class ElementMotion:
    """World-frame element data for one body state (arrays of length N)."""

    offset: np.ndarray  # (N, 2) midpoint relative to the body reference point, m
    position: np.ndarray  # (N, 2) m
    normal: np.ndarray  # (N, 2)
    velocity: np.ndarray  # (N, 2) m/s


def element_motion(elements: SurfaceElements, state: BodyState) -> ElementMotion:
    """Rotate and translate body-frame elements; rigid velocity v = v_cm + omega x r."""
    c, s = np.cos(state.theta), np.sin(state.theta)
    rot = np.array([[c, -s], [s, c]])
    offset = elements.midpoint @ rot.T
    normal = elements.normal @ rot.T
    position = offset + np.array([state.x, state.z])
    velocity = np.column_stack([state.vx - state.omega * offset[:, 1], state.vz + state.omega * offset[:, 0]])
    return ElementMotion(offset, position, normal, velocity)


def bdf2_base(x, z, vx, vz, xm, zm, vxm, vzm):
    """(x_b, z_b, vx_b, vz_b, c) of a BDF2 step from the state now (x, ...) and one step back (xm, ...).

    BDF2, y_{n+1} = (4 y_n - y_{n-1}) / 3 + (2/3) dt f(y_{n+1}), is a backward-Euler step of length
    c dt = (2/3) dt from the base state (4 y_n - y_{n-1}) / 3, so it takes the same Newton solve.
    Plain Python: the compiled step loop (``intrusim._implicit_jit``) compiles this same function.
    """
    return (4.0 * x - xm) / 3.0, (4.0 * z - zm) / 3.0, (4.0 * vx - vxm) / 3.0, (4.0 * vz - vzm) / 3.0, 2.0 / 3.0


def unbalanced_impulse(v1, v_base, carried, c, dt, accel):
    """The impulse per unit mass (m/s) that an implicit step leaves unbalanced: the step ran from the
    base velocity ``v_base`` less ``c`` x the impulse ``carried`` from the step before, over c dt
    (BDF2: c = 2/3; backward Euler: c = 1), to ``v1`` with the acceleration ``accel`` at ``v1``.
    Zero for a converged step; the next step makes it up (``bodies.Carry``). Plain Python: the
    compiled step loop compiles this same function.
    """
    return (v1 - (v_base - c * carried) - c * dt * accel) / c
