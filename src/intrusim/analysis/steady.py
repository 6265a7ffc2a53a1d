"""Steady-state locomotion: run a scenario, average over whole revolutions, report v, sinkage, slip.

Definitions (SI):

* translation velocity v: mean of vx over the averaging window, m/s;
* sinkage: depth of the lowest point of the TRUE outline polygon (grousers / flaps at their real
  height, not the shadowed RFT height) below the undisturbed free surface z = surface_z, at each
  recorded step; the steady value is its mean over the window, m (negative = above the surface);
* slip = 1 - v / (r |omega|), r = the body's nominal (outer) radius ``shape.radius``.

Window: the last ``average_revolutions`` WHOLE revolutions of the run (after the ramp and a
settling time), so a non-round body (runner: a limit cycle, not a steady state) is averaged over
complete cycles. ``drift`` compares the means of the first and second half of the window
(relative to the mean speed); a large drift means the run was too short to settle.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from typing import Any

import numba
import numpy as np

from intrusim._checks import InputError, finite
from intrusim.bodies import IntegratorError, IntegratorSettings, Trajectory, simulate
from intrusim.geometry import Shape


class NoContactError(RuntimeError):
    """The body never touched the medium during the averaging window."""


@dataclass(frozen=True)
class SteadyState:
    """Window averages of one run, plus the time series it came from.

    Attributes
    ----------
    omega : rad/s, |omega| at steady state.
    velocity : m/s, mean forward speed.
    velocity_z : m/s, mean vertical speed (should be ~0).
    sinkage : m, mean depth of the lowest true-outline point below the surface.
    slip : 1 - velocity / (radius * omega).
    velocity_std, sinkage_std : standard deviations over the window (limit-cycle amplitude).
    drift : max of the relative change of the mean speed and the change of the mean sinkage
        over r, between the two halves of the window.
    settled : drift <= the scenario's run.drift_tol (always True for a bare steady_state call).
    window : (t_start, t_end), s.
    revolutions : whole revolutions averaged over.
    radius : m, r used for slip.
    trajectory : the full time series; ``sinkage_series`` (m) per recorded step.
    """

    omega: float
    velocity: float
    velocity_z: float
    sinkage: float
    slip: float
    velocity_std: float
    sinkage_std: float
    drift: float
    settled: bool
    window: tuple[float, float]
    revolutions: int
    radius: float
    trajectory: Trajectory = field(repr=False)
    sinkage_series: np.ndarray = field(repr=False)
    meta: dict[str, Any] = field(default_factory=dict, repr=False)

    def summary(self) -> dict[str, float]:
        """Scalars only (for tables, CSV and sweeps)."""
        return {
            "omega": self.omega, "velocity": self.velocity, "sinkage": self.sinkage, "slip": self.slip,
            "velocity_std": self.velocity_std, "sinkage_std": self.sinkage_std, "drift": self.drift,
            "velocity_z": self.velocity_z, "settled": float(self.settled),
        }  # fmt: skip


def outline_sinkage(polygon: np.ndarray, z: np.ndarray, theta: np.ndarray, surface_z: float = 0.0) -> np.ndarray:
    """Depth below ``surface_z`` of the lowest outline vertex, for each (z, theta), m.

    polygon : (M, 2) body-frame outline; z : (T,) reference-point height, m; theta : (T,) rad.
    World height of vertex p: z + sin(theta) p_x + cos(theta) p_z.
    """
    p = np.asarray(polygon, float)
    zz, th = np.broadcast_arrays(np.atleast_1d(np.asarray(z, float)), np.atleast_1d(np.asarray(theta, float)))
    zz, th = np.ascontiguousarray(zz), np.ascontiguousarray(th)
    low = _lowest_height(np.ascontiguousarray(p[:, 0]), np.ascontiguousarray(p[:, 1]), zz, np.sin(th), np.cos(th))
    return surface_z - low


@numba.njit(cache=True)
def _lowest_height(px: np.ndarray, pz: np.ndarray, z: np.ndarray, s: np.ndarray, c: np.ndarray) -> np.ndarray:
    """min over vertices j of z_t + s_t px_j + c_t pz_j for each t (NaN propagates, as np.min)."""
    out = np.empty(z.shape[0])
    for t in range(z.shape[0]):
        m = np.inf
        for j in range(px.shape[0]):
            h = z[t] + s[t] * px[j] + c[t] * pz[j]
            if h < m or h != h:
                m = h
                if h != h:
                    break
        out[t] = m
    return out


def whole_windows(time: Any, every: float, *, origin: float = 0.0) -> int:
    """How many consecutive windows of ``every`` seconds from ``origin`` the series covers whole:
    to within one record interval (the median spacing) of its last sample."""
    t = np.asarray(time, float)
    if not t.size:
        return 0
    gap = float(np.median(np.diff(t))) if t.size > 1 else 0.0
    count = 0
    while origin + (count + 1) * every <= t[-1] + gap:
        count += 1
    return count


def window_means(
    time: Any,
    columns: dict[str, Any],
    every: float,
    *,
    origin: float = 0.0,
    right_closed: bool = False,
    whole_only: bool = False,
    tol: float = 1e-9,
) -> list[dict[str, float]]:
    """Means of ``columns`` over consecutive windows of ``every`` seconds from ``origin``.

    The history of a run at a glance (has it settled? does it dig in?): one row per window that
    holds samples, with ``t_start``, ``t_end`` (seconds since ``origin``) and the mean of each
    column. Empty windows are skipped.

    * ``right_closed`` False: windows [t0, t1) (a sample on a boundary opens the next window);
      True: (t0 + tol, t1 + tol] (it closes the window that ends there, as a held run's record at
      the switch belongs to the motion before it; ``tol`` absorbs the rounding of sample times:
      0.30000000000000004 closes the window that ends at 0.3).
    * ``whole_only`` False: the last window may be partial (it ends after the last sample); True:
      only windows that the series covers to within one record interval (the median spacing).
    """
    t = np.asarray(time, float)
    cols = {name: np.asarray(c, float) for name, c in columns.items()}
    if not every > 0.0:
        raise InputError(f"window length must be positive, got {every}")
    if t.ndim != 1 or any(c.shape != t.shape for c in cols.values()):
        raise InputError("time and every column must be 1-D arrays of one length")
    if not t.size:
        return []
    if whole_only:
        count = whole_windows(t, every, origin=origin)
    else:
        count = int(np.ceil((t[-1] - origin) / every))
    rows: list[dict[str, float]] = []
    for k in range(max(count, 0)):
        t0, t1 = origin + k * every, origin + (k + 1) * every
        sel = (t > t0 + tol) & (t <= t1 + tol) if right_closed else (t >= t0) & (t < t1)
        if sel.any():
            rows.append({"t_start": round(k * every, 9), "t_end": round((k + 1) * every, 9),
                         **{name: float(c[sel].mean()) for name, c in cols.items()}})  # fmt: skip
    return rows


def interval_means(time: Any, columns: dict[str, Any], t0: float, t1: float, tol: float = 1e-9) -> dict[str, float]:
    """Means of ``columns`` over the samples with t0 - tol <= time <= t1 + tol (sample times carry
    rounding: 0.30000000000000004 belongs to a window that starts at 0.3)."""
    t = np.asarray(time, float)
    sel = (t >= t0 - tol) & (t <= t1 + tol)
    if not sel.any():
        raise InputError(f"no sample in the window [{t0:g}, {t1:g}] s (the series spans {t.min():g}-{t.max():g} s)")
    return {name: float(np.mean(np.asarray(c, float)[sel])) for name, c in columns.items()}


def window_drift(velocity: Any, sinkage: Any, radius: float) -> float:
    """How far a steady-state window is from steady: the larger of the change of the mean velocity
    between its two halves, relative to the window's mean velocity, and the change of the mean
    sinkage, relative to the body's radius (0 for a window of one sample)."""
    v, sk = np.asarray(velocity, float), np.asarray(sinkage, float)
    half = len(v) // 2
    if half == 0:
        return 0.0
    return max(
        abs(v[half:].mean() - v[:half].mean()) / max(abs(float(v.mean())), 1e-12),
        abs(sk[half:].mean() - sk[:half].mean()) / radius,
    )


def steady_state(traj: Trajectory, shape: Shape, revolutions: int, surface_z: float = 0.0) -> SteadyState:
    """Average ``traj`` over its last ``revolutions`` whole revolutions (see module docstring).

    Raises
    ------
    InputError if the run is shorter than the window or the body does not turn;
    NoContactError if the granular force vanishes throughout the window.
    """
    omega = abs(float(traj.omega[-1]))
    if omega <= 0.0:
        raise InputError("steady state needs a turning body (omega = 0 at the end of the run)")
    period = 2.0 * math.pi / omega
    t_end = float(traj.t[-1])
    t_start = t_end - revolutions * period
    if t_start < 0.0:
        raise InputError(
            f"run of {t_end:.3g} s is shorter than {revolutions} revolution(s) ({revolutions * period:.3g} s)"
        )
    sel = traj.t > t_start + 1e-12  # steps (t_start, t_end]: one sample per dt, whole revolutions
    if not np.any(np.abs(traj.fx[sel]) + np.abs(traj.fz[sel]) > 0.0):
        depth = surface_z - float(
            np.min(outline_sinkage(shape.polygon, traj.z[-1:], traj.theta[-1:], 0.0) * -1 + traj.z[-1])
        )
        raise NoContactError(
            f"the body never touched the medium in the averaging window (t = {t_start:.3g}-{t_end:.3g} s); "
            f"its lowest point ended {abs(depth):.3g} m from the surface. Start it lower "
            "(run.initial_sinkage) or check its weight and external force."
        )
    sink = outline_sinkage(shape.polygon, traj.z, traj.theta, surface_z)
    v = traj.vx[sel]
    v_mean = float(v.mean())
    r = float(shape.radius)
    drift = window_drift(v, sink[sel], r)
    return SteadyState(
        omega=omega, velocity=v_mean, velocity_z=float(traj.vz[sel].mean()), sinkage=float(sink[sel].mean()),
        slip=1.0 - v_mean / (r * omega), velocity_std=float(v.std()), sinkage_std=float(sink[sel].std()),
        drift=drift, settled=True, window=(t_start, t_end), revolutions=revolutions, radius=r, trajectory=traj,
        sinkage_series=sink,
    )  # fmt: skip


def run_until_steady(
    model: Any, shape: Shape, body: Any, drive: Any, initial: Any, run: Any, *, compiled: bool = True,
    settings: IntegratorSettings | None = None,
) -> SteadyState:  # fmt: skip
    """Simulate, then extend the run a few revolutions at a time until the window stops drifting.

    Parameters
    ----------
    model : force model; shape : Shape (its TRUE outline gives the sinkage, its radius the slip);
    body : RigidBody; drive : Drive; initial : BodyState at t = 0;
    run : RunConfig (ramp/settle time, averaging revolutions, dt, drift_tol, max_extensions).
    compiled : use the compiled step loop when the model has one (False: the Python reference
        loop; same scheme, same result, ~5x slower).
    settings : the integrator's settings, in place of the default ones (BDF2 at
        ``run.dt(omega, shape.symmetry)``; ``compiled`` is then ignored).
    """
    if settings is None:
        settings = IntegratorSettings(dt=run.dt(drive.omega, getattr(shape, "symmetry", 1)), compiled=compiled)
    surface = getattr(model, "surface_z", 0.0)
    traj = simulate(model, body, drive, initial, run.duration(drive.omega), settings)
    st = steady_state(traj, shape, run.average_revolutions, surface)
    extensions = 0
    while st.drift > run.drift_tol and extensions < run.max_extensions:  # running means still drifting
        more = simulate(
            model, body, drive, traj.state(-1), run.average_revolutions * run.period(drive.omega), settings,
            t0=float(traj.t[-1]), previous=traj.state(-2), carry=traj.meta.get("carry"),
        )  # fmt: skip
        traj = traj.concatenate(more)
        st = steady_state(traj, shape, run.average_revolutions, surface)
        extensions += 1
    if st.drift > run.drift_tol:
        st = replace(st, settled=False)
    st.meta.update(dt=settings.dt, extensions=extensions)
    return st


FINER_STEP = 4
"""A steady state whose integration fails is run once more with its time step divided by this."""


def run_steady(
    scenario: Any, kind: str = "drft", omega_rpm: float = 30.0, lam: float | None = None, *, compiled: bool = True
) -> SteadyState:
    """Simulate ``scenario`` (a LocomotorScenario) with force model ``kind`` at ``omega_rpm``.

    Parameters
    ----------
    scenario : LocomotorScenario (geometry, inertias, force-model parameters, run control).
    kind : "rft", "drft-inertial" or "drft".
    omega_rpm : RPM, > 0 (forward rolling).
    lam : overrides the scenario's lambda.
    compiled : False runs the Python reference integrator instead of the compiled loop.

    Returns
    -------
    SteadyState averaged over the scenario's ``run.average_revolutions`` last revolutions,
    after the run has been extended until it stops drifting (see :func:`run_until_steady`).
    A run whose integration fails (:class:`~intrusim.bodies.IntegratorError`) is made once more
    with ``FINER_STEP`` x finer steps; ``meta["retried"]`` then says why. If that fails too, its
    error is raised.
    """
    w = finite("omega_rpm", omega_rpm)
    if w <= 0.0:
        raise InputError(f"omega_rpm must be > 0, got {omega_rpm!r}")
    model = scenario.build_model(kind, lam)
    shape = scenario.rft_shape()
    drive = scenario.drive(w)
    start = (model, shape, scenario.rigid_body(), drive, scenario.initial_state(shape))
    retried = None
    try:
        st = run_until_steady(*start, scenario.run, compiled=compiled)
    except IntegratorError as err:
        run = scenario.run
        finer = run.model_copy(
            update=dict(dt_max=run.dt_max / FINER_STEP, steps_per_revolution=run.steps_per_revolution * FINER_STEP)
        )
        try:
            st = run_until_steady(*start, finer, compiled=compiled)
        except IntegratorError as again:
            raise IntegratorError(
                f"{again} (with {FINER_STEP} x finer steps; at the default step: {err}). A scenario TOML sets the "
                f"step: [run] dt_max (now {run.dt_max:g} s) and steps_per_revolution (now {run.steps_per_revolution})"
            ) from None
        retried = f"{FINER_STEP} x finer steps, the default step failed: {err}"
    st.meta.update(scenario=scenario.name, kind=kind, omega_rpm=w, lam=model.lam, retried=retried)
    return st
