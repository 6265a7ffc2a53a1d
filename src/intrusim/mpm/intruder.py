"""Rigid intruder kinematics: prescribed motion or driven omega with free x and z.

Conventions (shared across intrusim): x horizontal forward, z vertical up, theta and omega
counter-clockwise (a wheel rolling forward in +x has omega < 0). Forces reaching the body are
per unit width from the 2D solver and are multiplied by ``width`` to give 3D forces (N).
Coupled bodies: m_x dvx/dt = Fx + F_ext,x ; m_z dvz/dt = Fz + F_ext,z - m_z g (weight m_z g),
integrated by semi-implicit Euler (velocity first, then position with the new velocity).
"""

from __future__ import annotations

from dataclasses import asdict, dataclass

import numpy as np

from intrusim.geometry import posed_polygon

from .config import CoupledMotion, IntruderConfig, PrescribedMotion
from .contact import BodyPose, PolygonContact


@dataclass
class IntruderState:
    """Pose (m, rad) and velocity (m/s, rad/s) of a rigid body's reference point."""

    x: float
    z: float
    theta: float
    vx: float = 0.0
    vz: float = 0.0
    omega: float = 0.0

    def pose(self) -> BodyPose:
        return BodyPose(self.x, self.z, self.theta, self.vx, self.vz, self.omega)

    def as_dict(self) -> dict[str, float]:
        return asdict(self)


def ramp(t: float, ramp_time: float) -> float:
    """Linear ramp factor min(t / ramp_time, 1) (1 if ramp_time == 0)."""
    return 1.0 if ramp_time <= 0 else min(max(t / ramp_time, 0.0), 1.0)


def ramp_integral(t: float, ramp_time: float) -> float:
    """Integral of :func:`ramp` from 0 to t, s."""
    if ramp_time <= 0:
        return t
    if t <= ramp_time:
        return 0.5 * t * t / ramp_time
    return t - 0.5 * ramp_time


class Intruder:
    """A rigid polygon with its contact law and kinematics."""

    def __init__(self, cfg: IntruderConfig, band: float, gravity: tuple[float, float],
                 fixed_scale: float | None = None):
        self.cfg = cfg
        self.width = cfg.width
        self.contact = PolygonContact(np.asarray(cfg.vertices), cfg.mu_w, band, fixed_scale)
        self.gravity = gravity
        self.x0 = (cfg.x, cfg.z, cfg.theta)
        self.state = IntruderState(cfg.x, cfg.z, cfg.theta)
        self.set_time(0.0)

    @property
    def coupled(self) -> bool:
        return isinstance(self.cfg.motion, CoupledMotion)

    def world_vertices(self) -> np.ndarray:
        """Polygon in the world frame at the current pose, m."""
        return posed_polygon(self.contact.vertices, self.state.x, self.state.z, self.state.theta)

    def set_time(self, t: float) -> None:
        """Set prescribed velocities (and pose) at time t; for coupled bodies only omega."""
        m = self.cfg.motion
        if isinstance(m, PrescribedMotion):
            f, s = ramp(t, m.ramp_time), ramp_integral(t, m.ramp_time)
            x0, z0, th0 = self.x0
            self.state = IntruderState(
                x0 + m.vx * s, z0 + m.vz * s, th0 + m.omega * s, m.vx * f, m.vz * f, m.omega * f
            )
        else:
            self.state.omega = m.omega * ramp(t, m.ramp_time)

    def advance(self, t_new: float, dt: float, force_2d: np.ndarray) -> None:
        """Move the body to time t_new = t + dt given the 2D contact force (Fx, Fz) N/m."""
        m = self.cfg.motion
        if isinstance(m, PrescribedMotion):
            self.set_time(t_new)
            return
        st = self.state
        fx = force_2d[0] * self.width + m.external_force[0]
        fz = force_2d[1] * self.width + m.external_force[1] + m.mass_z * self.gravity[1]
        if m.free_x:
            st.vx += dt * fx / m.mass_x
        if m.free_z:
            st.vz += dt * fz / m.mass_z
        st.x += dt * st.vx
        st.z += dt * st.vz
        st.theta += dt * st.omega
        st.omega = m.omega * ramp(t_new, m.ramp_time)
