"""Reductions over the material points: guards (NaN, escape, CFL) of the grains and of the rigid
bodies, and global quantities."""

import math

import numpy as np
import taichi as ti

from .particles import get_scalar, get_sym2, get_vec2


@ti.kernel
def guard_scan(
    x: ti.types.ndarray(),
    v: ti.types.ndarray(),
    sigma: ti.types.ndarray(),
    n: int,
    lx: float,
    lz: float,
    margin: float,
    out: ti.types.ndarray(),
):
    """out = [n_nan, n_escaped, max |v|, index of a NaN point, index of an escaped point] over the n
    points (block arrays, see particles).

    The stress is scanned too: a point's velocity comes back from the grid each step, and with
    fixed-point atomic sums (integers) a NaN does not survive the grid, but its stress keeps it."""
    for k in range(5):
        out[k] = 0.0 if k != 3 and k != 4 else -1.0
    for p in range(n):
        xp = get_vec2(x, p)
        vp = get_vec2(v, p)
        sp = get_sym2(sigma, p)
        speed = ti.cast(vp.norm(), ti.f64)
        bad = (
            ti.math.isnan(xp).any()
            or ti.math.isnan(vp).any()
            or ti.math.isinf(vp).any()
            or ti.math.isnan(sp).any()
            or ti.math.isinf(sp).any()
        )
        if bad:
            out[0] += 1.0
            ti.atomic_max(out[3], ti.cast(p, ti.f64))
        elif xp[0] < -margin or xp[0] > lx + margin or xp[1] < -margin or xp[1] > lz + margin:
            out[1] += 1.0
            ti.atomic_max(out[4], ti.cast(p, ti.f64))
        else:
            ti.atomic_max(out[2], speed)


@ti.kernel
def kinetic_energy_and_mass(v: ti.types.ndarray(), mass: ti.types.ndarray(), n: int, out: ti.types.ndarray()):
    """out = [sum m |v|^2 / 2 (J/m), sum m (kg/m)] in float64 over the n points (block arrays)."""
    out[0] = 0.0
    out[1] = 0.0
    for p in range(n):
        m = ti.cast(get_scalar(mass, p), ti.f64)
        vp = get_vec2(v, p)
        vv = ti.cast(vp.dot(vp), ti.f64)
        out[0] += 0.5 * m * vv
        out[1] += m


class SimulationError(RuntimeError):
    """A guard stopped the run; the message holds the diagnosis."""


def make_scratch(n: int = 5):
    return ti.ndarray(ti.f64, shape=n)


def guard_report(
    out: np.ndarray, x: np.ndarray, v: np.ndarray, dt: float, h: float, max_cell_fraction: float
) -> str | None:
    """Diagnosis text for a failed guard, or None if all is well."""
    n_nan, n_esc, vmax = int(out[0]), int(out[1]), float(out[2])
    if n_nan:
        i = int(out[3])
        return f"NaN/inf in particle state: {n_nan} points, e.g. point {i} at x={x[i]}, v={v[i]}"
    if n_esc:
        i = int(out[4])
        return f"particle escape: {n_esc} points left the domain, e.g. point {i} at x={x[i]}, v={v[i]}"
    if vmax * dt > max_cell_fraction * h:
        i = int(np.argmax(np.linalg.norm(v, axis=1)))
        return (
            f"CFL breach: max speed {vmax:.4g} m/s moves {vmax * dt / h:.3g} cells per step "
            f"(limit {max_cell_fraction}) at point {i}, x={x[i]}"
        )
    return None


def body_report(bodies, lx: float, lz: float, dt: float, h: float, max_cells_per_step: float = 1.0) -> str | None:
    """Diagnosis text for a rigid body gone wrong, or None: a NaN/inf in its state, a body wholly
    out of the box (through the floor, a wall or far above the open top), or a body moving more
    than ``max_cells_per_step`` cells in a step (its contact would skip grid nodes). ``bodies``:
    the solver's intruders (their ``state`` and body-frame ``contact.vertices``)."""
    for k, body in enumerate(bodies):
        st = body.state
        values = st.as_dict()
        bad = {n: v for n, v in values.items() if not math.isfinite(v)}
        if bad:
            return f"NaN/inf in body {k}'s state: " + ", ".join(f"{n}={v}" for n, v in bad.items())
        radius = float(np.max(np.linalg.norm(np.asarray(body.contact.vertices, dtype=float), axis=1)))
        if st.x + radius < 0.0 or st.x - radius > lx or st.z + radius < 0.0 or st.z - radius > lz:
            return (
                f"body escape: body {k} left the box {lx:g} x {lz:g} m, at x={st.x:.4g} m, z={st.z:.4g} m, "
                f"v=({st.vx:.4g}, {st.vz:.4g}) m/s"
            )
        speed = math.hypot(st.vx, st.vz) + abs(st.omega) * radius
        if speed * dt > max_cells_per_step * h:
            return (
                f"body CFL breach: body {k} moves {speed * dt / h:.3g} cells per step (limit {max_cells_per_step:g}; "
                f"v=({st.vx:.4g}, {st.vz:.4g}) m/s, omega={st.omega:.4g} rad/s) at x={st.x:.4g} m, z={st.z:.4g} m"
            )
    return None
