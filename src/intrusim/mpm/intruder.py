"""Rigid intruder kinematics: prescribed motion or driven omega with free x and z.

Conventions (shared across intrusim): x horizontal forward, z vertical up, theta and omega
counter-clockwise (a wheel rolling forward in +x has omega < 0). Forces reaching the body are
per unit width from the 2D solver and are multiplied by ``width`` to give 3D forces (N).
Coupled bodies: m_x dvx/dt = Fx + F_ext,x ; m_z dvz/dt = Fz + F_ext,z - m_z g (weight m_z g),
integrated by semi-implicit Euler (velocity first, then position with the new velocity).

A coupled body's dynamics run on the host (``Intruder.after_step``: the step's impulse read back)
or, with ``on_device``, in a kernel at the end of the step (``advance_coupled``): the pose then
stays on the device between steps, and ``Intruder.state`` reads it back only when asked.
"""

from dataclasses import asdict, dataclass

import numpy as np
import taichi as ti

from intrusim.geometry import posed_polygon

from .config import CoupledMotion, IntruderConfig, PrescribedMotion
from .contact import POSE_FIELDS, BodyPose, PolygonContact
from .step_graph import Launch, Var


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


@ti.kernel
def advance_coupled(
    pose: ti.types.ndarray(),
    impulse: ti.types.ndarray(),
    impulse_prev: ti.types.ndarray(),
    dt: ti.f64,
    width: ti.f64,
    fx_ext: ti.f64,
    fz_ext: ti.f64,
    weight: ti.f64,
    mass_x: ti.f64,
    mass_z: ti.f64,
    free_x: ti.i32,
    free_z: ti.i32,
    omega_next: ti.f64,
):
    """m dv/dt = F width + F_ext (semi-implicit Euler) on the device; F = this step's impulse / dt.

    ``pose`` = (x, z, theta, vx, vz, omega); ``impulse[0]`` the cumulative contact impulse per unit
    width, ``impulse_prev`` its value one step earlier (updated here); ``weight`` = m_z g_z (N);
    ``omega_next`` the driven omega at the new time. As ``Intruder.advance`` on the host."""
    j = impulse[0]
    fx = (j[0] - impulse_prev[0]) / dt * width + fx_ext
    fz = (j[1] - impulse_prev[1]) / dt * width + fz_ext + weight
    impulse_prev[0], impulse_prev[1], impulse_prev[2] = j[0], j[1], j[2]
    if free_x:
        pose[3] += dt * fx / mass_x
    if free_z:
        pose[4] += dt * fz / mass_z
    pose[0] += dt * pose[3]
    pose[1] += dt * pose[4]
    pose[2] += dt * pose[5]
    pose[5] = omega_next


class Intruder:
    """A rigid polygon with its contact law and kinematics.

    ``on_device``: a coupled body's dynamics run in a kernel of the step (``advance_coupled``) and
    its pose stays on the device; :attr:`state` reads it back when asked, and a state handed out
    (and perhaps changed) is written back before the next step. Otherwise the host reads the
    step's impulse back, advances the body and hands the pose to the next step.
    """

    def __init__(
        self,
        cfg: IntruderConfig,
        band: float,
        gravity: tuple[float, float],
        fixed_scale: float | None = None,
        on_device: bool = False,
        point_gap: float | None = None,
        nodes: bool = False,
    ):
        self.cfg = cfg
        self.width = cfg.width
        self.contact = PolygonContact(np.asarray(cfg.vertices), cfg.mu_w, band, fixed_scale, point_gap, nodes)
        self.gravity = gravity
        self.x0 = (cfg.x, cfg.z, cfg.theta)
        self.on_device = bool(on_device) and self.coupled
        self._state = IntruderState(cfg.x, cfg.z, cfg.theta)
        self._device_newer = False  # the device holds a later pose than self._state
        self._handed_out = True  # self._state may differ from the device's: write it before a step
        self._impulse_prev = np.zeros(3)  # the cumulative impulse one step back (host dynamics)
        self._impulse_prev_nd = None
        if self.on_device:
            self._impulse_prev_nd = ti.ndarray(ti.f64, shape=3)
            self._impulse_prev_nd.fill(0.0)
        self.set_time(0.0)

    @property
    def coupled(self) -> bool:
        return isinstance(self.cfg.motion, CoupledMotion)

    @property
    def state(self) -> IntruderState:
        """The body's pose and velocity now (read back from the device if its dynamics run there)."""
        if self._device_newer:
            pose = self.contact.read_pose()
            for name in POSE_FIELDS:
                setattr(self._state, name, getattr(pose, name))
            self._device_newer = False
        self._handed_out = True
        return self._state

    @state.setter
    def state(self, value: IntruderState) -> None:
        self._state = value
        self._device_newer = False
        self._handed_out = True

    @property
    def impulse_prev(self) -> np.ndarray:
        """The cumulative contact impulse one step back (the next step's force is the difference)."""
        if self._impulse_prev_nd is not None:
            return self._impulse_prev_nd.to_numpy()
        return self._impulse_prev.copy()

    @impulse_prev.setter
    def impulse_prev(self, value) -> None:
        self._impulse_prev = np.asarray(value, np.float64).reshape(3).copy()
        if self._impulse_prev_nd is not None:
            self._impulse_prev_nd.from_numpy(self._impulse_prev)

    def world_vertices(self) -> np.ndarray:
        """Polygon in the world frame at the current pose, m."""
        st = self.state
        return posed_polygon(self.contact.vertices, st.x, st.z, st.theta)

    def set_time(self, t: float) -> None:
        """Set prescribed velocities (and pose) at time t; for coupled bodies only omega."""
        m = self.cfg.motion
        if isinstance(m, PrescribedMotion):
            f, s = ramp(t, m.ramp_time), ramp_integral(t, m.ramp_time)
            x0, z0, th0 = self.x0
            self.state = IntruderState(x0 + m.vx * s, z0 + m.vz * s, th0 + m.omega * s, m.vx * f, m.vz * f, m.omega * f)
        else:
            self.state.omega = m.omega * ramp(t, m.ramp_time)

    # ------------------------------------------------------------------ in the MPM step
    def launches(self, grid, dt: float, prefix: str, particles=None) -> list[Launch]:
        """The body's contact kernels on the grid in a step (posed by the host unless ``on_device``)."""
        return self.contact.launches(grid, dt, prefix, posed_by_host=not self.on_device, particles=particles)

    def point_launches(self, particles, dt: float) -> list[Launch]:
        """The contact at the points after G2P (``PolygonContact.point_launches``), the body at the
        step's end (its pose on the device is still the step's start: the dynamics come last)."""
        return self.contact.point_launches(particles, dt, dt)

    def dynamics_launches(self, dt: float, prefix: str) -> list[Launch]:
        """At the step's end, on the device, the body's dynamics from the step's whole impulse
        (``Var`` ``prefix + "omega_next"``), as the host's ``after_step`` does otherwise."""
        if not self.on_device:
            return []
        m = self.cfg.motion
        return [
            Launch(
                advance_coupled,
                (
                    self.contact.pose,
                    self.contact.impulse,
                    self._impulse_prev_nd,
                    dt,
                    self.width,
                    float(m.external_force[0]),
                    float(m.external_force[1]),
                    m.mass_z * self.gravity[1],
                    m.mass_x,
                    m.mass_z,
                    int(m.free_x),
                    int(m.free_z),
                    Var(prefix + "omega_next"),
                ),
            )
        ]

    def launch_values(self, t_next: float, prefix: str) -> dict[str, float]:
        """The ``Var`` values of :meth:`launches` for the step that ends at ``t_next``; writes a
        state handed out since the last step back to the device first."""
        if not self.on_device:
            return self.contact.launch_values(self._state.pose(), prefix)
        if self._handed_out:
            self.contact.write_pose(self._state.pose())
            self._handed_out = False
        m = self.cfg.motion
        return {prefix + "omega_next": float(m.omega * ramp(t_next, m.ramp_time))}

    def after_step(self, t_new: float, dt: float) -> None:
        """The host's part once the step's kernels have run: move the body to ``t_new``."""
        if self.on_device:
            self._device_newer = True
        elif self.coupled:
            impulse = self.contact.read_impulse()
            force = (impulse - self._impulse_prev) / dt
            self._impulse_prev = impulse
            self.advance(t_new, dt, force[:2])
        else:
            self.set_time(t_new)

    def advance(self, t_new: float, dt: float, force_2d: np.ndarray) -> None:
        """Move the body to time t_new = t + dt given the 2D contact force (Fx, Fz) N/m."""
        m = self.cfg.motion
        if isinstance(m, PrescribedMotion):
            self.set_time(t_new)
            return
        st = self._state
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
