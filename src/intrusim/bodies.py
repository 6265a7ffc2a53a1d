"""Rigid-body locomotion dynamics: a driven body free to translate in x and z .

The body turns at a PRESCRIBED angular velocity omega(t) (ramped linearly from rest to the
target over ``ramp_time``), and its centre moves under

    m_x dvx/dt = F_x(state) + F_ext,x
    m_z dvz/dt = F_z(state) + F_ext,z - m_z g

with F the granular force of any force model (``wrench_tuple`` or ``wrench``). The weight is
taken as m_z g: the paper's rig has separate effective horizontal and vertical inertias (Table S1:
23.0 kg and 6.3 kg for the wheel) and its vertical load is set by weights and pulleys, so the
vertical inertia is also the mass that gravity acts on.

Integrator ("implicit iterative scheme", paper, Methods): BDF2 (default, ``scheme="bdf2"``) or
backward Euler (``scheme="implicit"``) on the velocity. Both solve, each step,

    G(v) = v - v_b - c dt M^-1 (F(x_b + c dt v_x, z_b + c dt v_z, theta_{n+1}, v, omega_{n+1}) + F_ext + W) = 0,

backward Euler with the base state y_b = y_n and c = 1, BDF2 with y_b = (4 y_n - y_{n-1}) / 3 and
c = 2/3 (y = x, z, vx, vz; the first step, and the sub-steps of a step whose Newton iteration
failed, are backward Euler). G is solved by a damped Newton iteration with a finite-difference
2 x 2 Jacobian dF/dv (which, through x = x_b + c dt v, also carries dF/dz). theta follows the
prescribed omega exactly (trapezoidal rule on the piecewise-linear ramp). RFT forces are stiff in
depth and strongly damping in the velocity direction; both schemes are A-stable for that
linearised system, so the time step is set by accuracy, not stability. Backward Euler is first
order: at the paper's ~100 steps a revolution it moves a four-flap runner's steady speed by up to
1 % and its sinkage by up to 2.8 %; BDF2, second order, by up to 0.15 % and 0.8 % (docs/locomotion.md). A plain
explicit Euler scheme is kept as the reference (and to show what instability looks like).

The implicit scheme runs in a compiled (Numba) step loop (``intrusim._implicit_jit``) when the
force model offers a compiled form (``compiled_spec()``: the RFT/DRFT models); the Python loop
below is the reference and the fallback (``IntegratorSettings(compiled=False)``). Both take the
same steps and raise the same errors; they agree to rounding. Why two: Numba compiles only a
force model it can see whole (the RFT/DRFT kernel with a flat or affine-psi free surface), while
the integrator also drives any Python force model (``wrench_tuple`` or ``wrench``: a user-defined
free-surface law, a measured force table); the Python loop serves those and is the oracle the
compiled loop is tested against. Both use the same element law (``intrusim._traction``).

Failures (non-finite state, runaway speed or depth, Newton not converging) raise
:class:`IntegratorError` with the time, the step and the advice to reduce ``dt``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, Callable, Literal

import numpy as np

from intrusim._checks import InputError, finite, finite_array, non_negative, positive, positive_int
from intrusim.kinematics import BodyState, bdf2_base, unbalanced_impulse
from intrusim.params import GRAVITY

ElementBound = Callable[[float, float, float, float, float, float], float]  # the largest element force, N
ForceFn = Callable[[float, float, float, float, float, float], tuple[float, float, float]]


class IntegratorError(RuntimeError):
    """The time integration failed (non-finite values, divergence, Newton not converged)."""


class NewtonNotConverged(IntegratorError):
    """The Newton iteration of one implicit step did not converge (the step is retried in halves)."""


@dataclass(frozen=True)
class Drive:
    """Prescribed angular velocity: a linear ramp from rest to ``omega`` over ``ramp_time``.

    Attributes
    ----------
    omega : float, rad/s. Target angular velocity, counter-clockwise (< 0 rolls towards +x).
    ramp_time : float, s. Duration of the ramp (0 = instantaneous start).
    """

    omega: float
    ramp_time: float = 0.5

    def __post_init__(self) -> None:
        finite("omega", self.omega)
        non_negative("ramp_time", self.ramp_time)

    def omega_at(self, t: float) -> float:
        """omega(t), rad/s."""
        if self.ramp_time <= 0.0 or t >= self.ramp_time:
            return self.omega
        return self.omega * max(t, 0.0) / self.ramp_time

    def angle_at(self, t: float) -> float:
        """Exact integral of omega from 0 to t, rad."""
        if self.ramp_time <= 0.0:
            return self.omega * t
        if t <= self.ramp_time:
            return 0.5 * self.omega * max(t, 0.0) ** 2 / self.ramp_time
        return self.omega * (t - 0.5 * self.ramp_time)


@dataclass(frozen=True)
class RigidBody:
    """Effective inertias and loads of a body free to translate in x and z.

    Attributes
    ----------
    mass_x : float, kg. Effective horizontal inertia.
    mass_z : float, kg. Effective vertical inertia; the weight is mass_z * gravity.
    gravity : float, m/s^2.
    external_fx, external_fz : float, N. Constant external force (e.g. the MPM wheel's 4 N push).
    """

    mass_x: float
    mass_z: float
    gravity: float = GRAVITY
    external_fx: float = 0.0
    external_fz: float = 0.0

    def __post_init__(self) -> None:
        positive("mass_x", self.mass_x)
        positive("mass_z", self.mass_z)
        non_negative("gravity", self.gravity)
        finite("external_fx", self.external_fx)
        finite("external_fz", self.external_fz)

    @property
    def weight(self) -> float:
        """m_z g, N."""
        return self.mass_z * self.gravity


SCHEMES = ("bdf2", "implicit", "explicit")
IMPLICIT = ("bdf2", "implicit")  # the schemes solved by Newton (and run in the compiled loop)


@dataclass(frozen=True)
class IntegratorSettings:
    """Time-stepping controls.

    Attributes
    ----------
    dt : float, s. Time step.
    scheme : "bdf2" (BDF2 + Newton, second order; default), "implicit" (backward Euler + Newton,
        first order) or "explicit" (forward Euler).
    max_iter : int. Newton iterations per step before giving up.
    velocity_tol : float, m/s. Newton stops when the velocity update is below this.
    fd_step : float, m/s. Finite-difference step of the Jacobian dF/dv.
    max_speed : float, m/s. A centre speed above this is treated as divergence.
    max_depth : float, m. The reference point sinking more than this below the surface is
        treated as divergence (the medium cannot carry the body, or dt is far too large).
    force_tol_rel : float. RFT forces jump where an element switches on or off (leading-edge
        rule), so a step may have no exact root. A Newton iteration that stalls is accepted if
        its force imbalance is below force_tol_rel * max(weight, |F_ext|, 1 N).
    stall_iter : int. Successive poorly contracting iterations that count as a stall.
    contraction : float. An iteration that does not reduce |G| by this factor contracts poorly
        (the reused Jacobian is then refreshed).
    max_backtrack : int. Step halvings of the damped Newton update.
    max_halvings : int. A step whose Newton iteration fails is retried in 2, 4, ..., 2^max_halvings
        equal sub-steps before the integration is declared failed.
    compiled : bool. Run the implicit scheme in the compiled (Numba) step loop when the force
        model offers a compiled form (``compiled_spec()``: the RFT/DRFT models); False forces
        the Python loop, which is the reference and the fallback for any other force model.
        Both take the same steps; they agree to rounding.
    """

    dt: float = 2e-3
    scheme: Literal["bdf2", "implicit", "explicit"] = "bdf2"
    max_iter: int = 40
    velocity_tol: float = 1e-7
    fd_step: float = 1e-6
    max_speed: float = 50.0
    max_depth: float = 2.0
    force_tol_rel: float = 5e-2
    stall_iter: int = 3
    contraction: float = 0.5
    max_backtrack: int = 12
    max_halvings: int = 3
    compiled: bool = True

    def __post_init__(self) -> None:
        positive("dt", self.dt)
        if self.scheme not in SCHEMES:
            raise InputError(f"scheme must be one of {list(SCHEMES)}, got {self.scheme!r}")
        positive_int("max_iter", self.max_iter)
        positive("velocity_tol", self.velocity_tol)
        positive("fd_step", self.fd_step)
        positive("max_speed", self.max_speed)
        positive("max_depth", self.max_depth)
        positive("force_tol_rel", self.force_tol_rel)
        positive_int("stall_iter", self.stall_iter)
        if not 0.0 < self.contraction < 1.0:
            raise InputError(f"contraction must be in (0, 1), got {self.contraction!r}")
        positive_int("max_backtrack", self.max_backtrack)
        if int(self.max_halvings) != self.max_halvings or self.max_halvings < 0:
            raise InputError(f"max_halvings must be an integer >= 0, got {self.max_halvings!r}")
        if not isinstance(self.compiled, bool):
            raise InputError(f"compiled must be True or False, got {self.compiled!r}")


@dataclass(frozen=True)
class Carry:
    """What an implicit run hands to the run that continues it (``Trajectory.meta["carry"]``).

    Attributes
    ----------
    impulse : (x, z) impulse per unit mass, m/s, that the last step left unbalanced. A step whose
        Newton iteration stalls at a force jump is accepted with a residual (``force_tol_rel``);
        the next step makes that impulse up, so the accepted residuals do not add up to a bias of
        the mean force (with forces that hardly depend on speed, such a bias moves the mean speed a
        lot: 1.1 % for the bulldozing wheel at 60 RPM, docs/locomotion.md).
    jacobian : the Newton Jacobian [j11, j12, j21, j22] the next step would reuse (None: none yet).
    """

    impulse: tuple[float, float] = (0.0, 0.0)
    jacobian: tuple[float, float, float, float] | None = None

    def __post_init__(self) -> None:
        finite_array("impulse", np.asarray(self.impulse, dtype=float))
        if self.jacobian is not None:
            finite_array("jacobian", np.asarray(self.jacobian, dtype=float))


@dataclass(frozen=True)
class Trajectory:
    """Time series of a simulation, one entry per step (arrays of length n_steps + 1).

    Units: t s; x, z m; theta rad; vx, vz m/s; omega rad/s; fx, fz N (granular force only);
    moment N m (granular, about the centre); iterations: Newton iterations of the step.
    """

    t: np.ndarray
    x: np.ndarray
    z: np.ndarray
    theta: np.ndarray
    vx: np.ndarray
    vz: np.ndarray
    omega: np.ndarray
    fx: np.ndarray
    fz: np.ndarray
    moment: np.ndarray
    iterations: np.ndarray
    meta: dict[str, Any] = field(default_factory=dict)

    def concatenate(self, other: "Trajectory") -> "Trajectory":
        """This trajectory followed by ``other`` (which starts at this one's last state)."""
        names = ("t", "x", "z", "theta", "vx", "vz", "omega", "fx", "fz", "moment", "iterations")
        joined = {k: np.concatenate([getattr(self, k), getattr(other, k)[1:]]) for k in names}
        meta = dict(self.meta)
        if "carry" in other.meta:  # the integrator's state at the end (Carry)
            meta["carry"] = other.meta["carry"]
        return Trajectory(meta=meta, **joined)

    def state(self, i: int) -> BodyState:
        return BodyState(self.x[i], self.z[i], self.theta[i], self.vx[i], self.vz[i], self.omega[i])


def force_function(model: Any) -> ForceFn:
    """The fastest (fx, fz, moment) callable a force model offers (``wrench_tuple`` or ``wrench``)."""
    if hasattr(model, "wrench_tuple"):
        return model.wrench_tuple
    if hasattr(model, "wrench"):

        def fn(x: float, z: float, th: float, vx: float, vz: float, om: float) -> tuple[float, float, float]:
            w = model.wrench(BodyState(x, z, th, vx, vz, om))
            return w.fx, w.fz, w.moment

        return fn
    if callable(model):
        return model
    raise InputError("force model must have wrench_tuple(...) or wrench(state), or be a callable")


def _implicit_advance(
    force: ForceFn, drive: Drive, th_base: float, x: float, z: float, vx: float, vz: float, t0: float, dt: float,
    ax_ext: float, az_ext: float, inv_mx: float, inv_mz: float, s: IntegratorSettings, g_tol_rate: float,
    jac: list[float], bound: ElementBound | None = None, impulse: tuple[float, float] = (0.0, 0.0),
) -> tuple[float, float, float, float, float, float, float, int, float, float]:  # fmt: skip
    """Advance by ``dt`` with backward Euler; if Newton fails, retry in 2, 4, ... equal sub-steps.

    ``th_base`` is theta minus the drive angle (theta(t) = th_base + drive.angle_at(t)); ``impulse``
    the impulse per unit mass the former step left unbalanced (:class:`Carry`).
    Returns (x, z, vx, vz, fx, fz, moment, Newton iterations summed over sub-steps, and the
    impulse per unit mass this step leaves, x and z).
    """
    last: NewtonNotConverged | None = None
    for halvings in range(s.max_halvings + 1):
        k = 2**halvings
        h = dt / k
        xs, zs, vxs, vzs, total = x, z, vx, vz, 0
        qx, qz = impulse
        try:
            for j in range(1, k + 1):
                tj = t0 + j * h
                vx1, vz1, fx, fz, m, it = _implicit_step(
                    force, xs, zs, th_base + drive.angle_at(tj), vxs - qx, vzs - qz, drive.omega_at(tj), h,
                    ax_ext, az_ext, inv_mx, inv_mz, s, tj, g_tol_rate * h, jac, bound,
                )  # fmt: skip
                qx = unbalanced_impulse(vx1, vxs, qx, 1.0, h, fx * inv_mx + ax_ext)
                qz = unbalanced_impulse(vz1, vzs, qz, 1.0, h, fz * inv_mz + az_ext)
                xs, zs, vxs, vzs, total = xs + h * vx1, zs + h * vz1, vx1, vz1, total + it
            return xs, zs, vxs, vzs, fx, fz, m, total, qx, qz
        except NewtonNotConverged as err:
            last = err
            jac.clear()
    raise _fail(f"{last} (also in {2**s.max_halvings} sub-steps)", t0 + dt, s)


def _fail(msg: str, t: float, settings: IntegratorSettings) -> IntegratorError:
    return IntegratorError(
        f"{msg} at t = {t:.4g} s with dt = {settings.dt:g} s ({settings.scheme} scheme); "
        f"try a smaller time step (e.g. dt = {settings.dt / 4:g} s)"
    )


def _implicit_step(
    force: ForceFn, x0: float, z0: float, th1: float, vx0: float, vz0: float, om1: float,
    dt: float, ax_ext: float, az_ext: float, inv_mx: float, inv_mz: float, s: IntegratorSettings, t: float,
    g_tol: float, jac: list[float], bound: ElementBound | None = None,
) -> tuple[float, float, float, float, float, int]:  # fmt: skip
    """One implicit step from the base state (x0, z0, vx0, vz0) of length dt; returns (vx1, vz1, fx, fz,
    moment, iterations). Backward Euler as it stands; a BDF2 step passes its base state and (2/3) dt.

    Modified Newton: the finite-difference Jacobian ``jac`` = [j11, j12, j21, j22] of G is kept
    from step to step (updated in place) and recomputed only when an iteration contracts poorly.
    """
    vx, vz = vx0, vz0
    h = s.fd_step

    def residual(vx: float, vz: float) -> tuple[float, float, float, float, float]:
        fx, fz, m = force(x0 + dt * vx, z0 + dt * vz, th1, vx, vz, om1)
        return vx - vx0 - dt * (fx * inv_mx + ax_ext), vz - vz0 - dt * (fz * inv_mz + az_ext), fx, fz, m

    gx, gz, fx, fz, m = residual(vx, vz)
    norm = math.hypot(gx, gz)
    best = (norm, vx, vz, fx, fz, m)
    stall = 0
    refreshed = -1  # iteration of the last Jacobian refresh
    for it in range(1, s.max_iter + 1):
        if not jac or (stall > 0 and refreshed < it - 1):
            # Jacobian of G by forward differences (G is piecewise smooth: elements switch on/off).
            gx1, gz1, *_ = residual(vx + h, vz)
            gx2, gz2, *_ = residual(vx, vz + h)
            jac[:] = [(gx1 - gx) / h, (gx2 - gx) / h, (gz1 - gz) / h, (gz2 - gz) / h]
            refreshed = it
        j11, j12, j21, j22 = jac
        det = j11 * j22 - j12 * j21
        if not math.isfinite(det) or det == 0.0:
            raise _fail("singular Newton Jacobian", t, s)
        dvx = -(j22 * gx - j12 * gz) / det
        dvz = -(-j21 * gx + j11 * gz) / det
        norm0 = norm
        step = 1.0
        for _ in range(s.max_backtrack):  # backtracking: accept the first step that reduces |G|
            nx, nz = vx + step * dvx, vz + step * dvz
            ngx, ngz, nfx, nfz, nm = residual(nx, nz)
            if math.hypot(ngx, ngz) < norm0:
                break
            step *= 0.5
        if not (math.isfinite(nx) and math.isfinite(nz) and math.isfinite(ngx) and math.isfinite(ngz)):
            raise _fail("non-finite velocity in the Newton iteration", t, s)
        update = math.hypot(dvx, dvz)  # the full Newton update: a damped step is not convergence
        vx, vz, gx, gz, fx, fz, m = nx, nz, ngx, ngz, nfx, nfz, nm
        norm = math.hypot(gx, gz)
        if update <= s.velocity_tol:
            return vx, vz, fx, fz, m, it
        if norm < best[0]:
            best = (norm, vx, vz, fx, fz, m)
        if norm > s.contraction * norm0 or step < 1.0:
            stall += 1  # poor contraction or damped step: refresh the Jacobian, then count stalls
        else:
            stall = 0
        # The force is discontinuous where an element switches (leading-edge rule), so G may have
        # no exact root: accept the best iterate once it stalls within the residual tolerance.
        if stall >= s.stall_iter and best[0] <= g_tol:
            return best[1], best[2], best[3], best[4], best[5], it
    if best[0] <= g_tol:
        return best[1], best[2], best[3], best[4], best[5], s.max_iter
    # No root within the tolerance: one element switching on or off moves the force by that element's
    # force, so an imbalance below the largest one is the law's own resolution (a flat face whose
    # elements switch one after the other as its normal velocity crosses zero makes G a staircase).
    if bound is not None and best[0] <= dt * max(inv_mx, inv_mz) * bound(
        x0 + dt * best[1], z0 + dt * best[2], th1, best[1], best[2], om1
    ):
        return best[1], best[2], best[3], best[4], best[5], s.max_iter
    raise NewtonNotConverged(
        f"Newton iteration did not converge in {s.max_iter} iterations (|G| = {best[0]:.3g} m/s, "
        f"tolerance {g_tol:.3g} m/s) at t = {t:.4g} s with a step of {dt:g} s"
    )


def simulate(
    model: Any,
    body: RigidBody,
    drive: Drive,
    initial: BodyState,
    duration: float,
    settings: IntegratorSettings | None = None,
    t0: float = 0.0,
    previous: BodyState | None = None,
    carry: Carry | None = None,
) -> Trajectory:
    """Integrate the driven body for ``duration`` seconds from ``initial`` at time ``t0``.

    Parameters
    ----------
    model : force model with ``wrench_tuple(x, z, theta, vx, vz, omega)`` or ``wrench(state)``,
        or a callable with the signature of ``wrench_tuple``.
    body : effective inertias, gravity and external force.
    drive : prescribed omega(t); ``initial.omega`` is ignored (omega(0) comes from the drive).
    initial : state at t = 0 (x, z of the reference point, m; theta, rad; vx, vz, m/s).
    duration : float, s.
    settings : time step and scheme.
    t0 : float, s. Start time (the drive's clock), to continue a run from its last state.
    previous : the state one step (dt) before ``initial``, when continuing a run with the same dt
        (``traj.state(-2)``): BDF2 then takes its first step from both, and the continued run is
        the uninterrupted one's; without it the first step is backward Euler.
    carry : :class:`Carry`, the integrator's state at the end of the run being continued
        (``traj.meta["carry"]``): with ``previous`` and ``t0`` the continued run is the
        uninterrupted one's, step for step.

    Returns
    -------
    Trajectory with n = ceil(duration / dt) steps.

    Raises
    ------
    IntegratorError if the integration diverges or the Newton iteration fails.
    """
    s = settings or IntegratorSettings()
    duration = positive("duration", duration)
    spec = _compiled_spec(model) if (s.scheme in IMPLICIT and s.compiled) else None
    if spec is not None:
        return _simulate_compiled(spec, model, body, drive, initial, duration, s, t0, previous, carry)
    force = force_function(model)
    bound = getattr(model, "largest_element_force", None)  # the law's force resolution (see _implicit_step)
    dt = s.dt
    n = int(math.ceil(duration / dt - 1e-9))
    t0 = finite("t0", t0)
    t = t0 + np.arange(n + 1) * dt
    out = {k: np.empty(n + 1) for k in ("x", "z", "theta", "vx", "vz", "omega", "fx", "fz", "moment")}
    iters = np.zeros(n + 1, dtype=np.int32)
    inv_mx, inv_mz = 1.0 / body.mass_x, 1.0 / body.mass_z
    ax_ext = body.external_fx * inv_mx
    az_ext = body.external_fz * inv_mz - body.gravity
    x, z, vx, vz = float(initial.x), float(initial.z), float(initial.vx), float(initial.vz)
    th0 = float(initial.theta)
    om = drive.omega_at(t0)
    angle0 = drive.angle_at(t0)
    fx, fz, m = force(x, z, th0, vx, vz, om)
    surface = getattr(model, "surface_z", 0.0)
    # residual tolerance of a stalled Newton iteration, as a velocity: dt * force_tol / m
    g_rate = s.force_tol_rel * max(body.weight, abs(body.external_fx), abs(body.external_fz), 1.0) * max(inv_mx, inv_mz)
    cols = (out["x"], out["z"], out["theta"], out["vx"], out["vz"], out["omega"], out["fx"], out["fz"], out["moment"])
    for c, v in zip(cols, (x, z, th0, vx, vz, om, fx, fz, m)):
        c[0] = v
    carry = carry or Carry()
    jac: list[float] = [] if carry.jacobian is None else list(carry.jacobian)  # Newton Jacobian, reused across steps
    # the state one step back (BDF2; none at the start of a run)
    back = None if previous is None else (float(previous.x), float(previous.z), float(previous.vx), float(previous.vz))
    px, pz = carry.impulse  # the impulse per unit mass left unbalanced, made up by the next step
    for i in range(1, n + 1):
        ti = float(t[i])
        om1 = drive.omega_at(ti)
        th1 = th0 + (drive.angle_at(ti) - angle0)
        if s.scheme in IMPLICIT:
            now = (x, z, vx, vz)
            step = None
            if s.scheme == "bdf2" and back is not None:
                xb, zb, vxb, vzb, c = bdf2_base(*now, *back)
                try:
                    vx1, vz1, fx, fz, m, it = _implicit_step(
                        force, xb, zb, th1, vxb - c * px, vzb - c * pz, om1, c * dt, ax_ext, az_ext, inv_mx, inv_mz,
                        s, ti, g_rate * c * dt, jac, bound,
                    )  # fmt: skip
                    step = (xb + c * dt * vx1, zb + c * dt * vz1, vx1, vz1, fx, fz, m, it)
                    px = unbalanced_impulse(vx1, vxb, px, c, dt, fx * inv_mx + ax_ext)
                    pz = unbalanced_impulse(vz1, vzb, pz, c, dt, fz * inv_mz + az_ext)
                except NewtonNotConverged:
                    jac.clear()  # then backward Euler, in sub-steps if need be
            if step is None:
                *step, px, pz = _implicit_advance(
                    force, drive, th0 - angle0, x, z, vx, vz, float(t[i - 1]), dt, ax_ext, az_ext, inv_mx, inv_mz, s, g_rate,
                    jac, bound, (px, pz),
                )  # fmt: skip
            back = now
            x, z, vx, vz, fx, fz, m, it = step
        else:
            vx1 = vx + dt * (fx * inv_mx + ax_ext)
            vz1 = vz + dt * (fz * inv_mz + az_ext)
            x, z, vx, vz = x + dt * vx, z + dt * vz, vx1, vz1
            fx, fz, m = force(x, z, th1, vx, vz, om1)
            it = 0
        if not (math.isfinite(x) and math.isfinite(z) and math.isfinite(vx) and math.isfinite(vz)):
            raise _fail("non-finite state", ti, s)
        if math.hypot(vx, vz) > s.max_speed:
            raise _fail(
                f"speed {math.hypot(vx, vz):.3g} m/s exceeds max_speed = {s.max_speed:g} m/s (divergence)", ti, s
            )
        if z < surface - s.max_depth:
            raise _fail(
                f"body sank {surface - z:.3g} m below the surface (max_depth = {s.max_depth:g} m): the medium "
                "does not carry the body, or the integration diverged",
                ti,
                s,
            )
        for c, v in zip(cols, (x, z, th1, vx, vz, om1, fx, fz, m)):
            c[i] = v
        iters[i] = it
    return Trajectory(
        t=t, iterations=iters, meta={"dt": dt, "scheme": s.scheme, "carry": Carry((px, pz), tuple(jac) or None)}, **out
    )


def _compiled_spec(model: Any) -> tuple | None:
    fn = getattr(model, "compiled_spec", None)
    return fn() if callable(fn) else None


def _simulate_compiled(
    spec: tuple, model: Any, body: RigidBody, drive: Drive, initial: BodyState, duration: float,
    s: IntegratorSettings, t0: float, previous: BodyState | None, carry: Carry | None,
) -> Trajectory:  # fmt: skip
    """The implicit scheme of :func:`simulate` in the compiled loop (``intrusim._implicit_jit``)."""
    import intrusim._implicit_jit as jit

    dt = s.dt
    n = int(math.ceil(duration / dt - 1e-9))
    t0 = finite("t0", t0)
    t = t0 + np.arange(n + 1) * dt
    out = np.empty((9, n + 1))
    iters = np.zeros(n + 1, dtype=np.int32)
    info = np.zeros(5)
    inv_mx, inv_mz = 1.0 / body.mass_x, 1.0 / body.mass_z
    ax_ext = body.external_fx * inv_mx
    az_ext = body.external_fz * inv_mz - body.gravity
    g_rate = s.force_tol_rel * max(body.weight, abs(body.external_fx), abs(body.external_fz), 1.0) * max(inv_mx, inv_mz)
    surface = float(getattr(model, "surface_z", 0.0))
    carry = carry or Carry()
    state = np.array([*carry.impulse, carry.jacobian is not None, *(carry.jacobian or (0.0,) * 4)], dtype=np.float64)
    status, i = jit.simulate_implicit(
        spec, float(drive.omega), float(drive.ramp_time), t0, float(dt), n,
        float(initial.x), float(initial.z), float(initial.theta), float(initial.vx), float(initial.vz),
        ax_ext, az_ext, inv_mx, inv_mz, int(s.max_iter), float(s.velocity_tol), float(s.fd_step), int(s.stall_iter),
        float(s.contraction), int(s.max_backtrack), int(s.max_halvings), g_rate, float(s.max_speed),
        float(s.max_depth), surface, out, iters, info, 2 if s.scheme == "bdf2" else 1,
        *(np.nan,) * 4 if previous is None else (float(previous.x), float(previous.z), float(previous.vx), float(previous.vz)),
        state,
    )  # fmt: skip
    if status != jit.OK:
        raise _compiled_failure(status, info, s)
    names = ("x", "z", "theta", "vx", "vz", "omega", "fx", "fz", "moment")
    cols = {k: out[j] for j, k in enumerate(names)}
    jac = tuple(float(j) for j in state[3:]) if state[2] else None
    meta = {"dt": dt, "scheme": s.scheme, "carry": Carry((float(state[0]), float(state[1])), jac)}
    return Trajectory(t=t, iterations=iters, meta=meta, **cols)


def _compiled_failure(status: int, info: np.ndarray, s: IntegratorSettings) -> IntegratorError:
    """The IntegratorError the Python loop raises for the same failure."""
    import intrusim._implicit_jit as jit

    if status == jit.SINGULAR:
        return _fail("singular Newton Jacobian", info[0], s)
    if status == jit.NEWTON_NONFINITE:
        return _fail("non-finite velocity in the Newton iteration", info[0], s)
    if status == jit.NOT_CONVERGED:
        last = (
            f"Newton iteration did not converge in {s.max_iter} iterations (|G| = {info[1]:.3g} m/s, "
            f"tolerance {info[2]:.3g} m/s) at t = {info[3]:.4g} s with a step of {info[4]:g} s"
        )
        return _fail(f"{last} (also in {2**s.max_halvings} sub-steps)", info[0], s)
    if status == jit.STATE_NONFINITE:
        return _fail("non-finite state", info[0], s)
    if status == jit.TOO_FAST:
        return _fail(f"speed {info[1]:.3g} m/s exceeds max_speed = {s.max_speed:g} m/s (divergence)", info[0], s)
    if status == jit.TOO_DEEP:
        return _fail(
            f"body sank {info[1]:.3g} m below the surface (max_depth = {s.max_depth:g} m): the medium "
            "does not carry the body, or the integration diverged",
            info[0],
            s,
        )
    return IntegratorError(f"compiled integrator failed with unknown status {status}")  # pragma: no cover


__all__ = [
    "Carry",
    "Drive",
    "RigidBody",
    "IntegratorSettings",
    "IntegratorError",
    "NewtonNotConverged",
    "Trajectory",
    "simulate",
    "force_function",
]
