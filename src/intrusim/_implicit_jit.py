"""Compiled (Numba) time loop of the implicit integrator of :mod:`intrusim.bodies`.

The same scheme as the Python loop of ``bodies.simulate`` (which stays the reference and the
fallback for force models without a compiled form), step for step:

* backward Euler on (vx, vz), positions from the new velocity, theta following the prescribed
  omega ramp exactly;
* damped modified Newton with a 2 x 2 forward-difference Jacobian kept from step to step and
  refreshed on poor contraction; the same stall / ``force_tol_rel`` acceptance rule;
* a failed step retried in 2, 4, ..., 2^max_halvings sub-steps;
* the same divergence checks (non-finite state, max_speed, max_depth).

The force is the compiled RFT/DRFT kernel ``forces._wrench_kernel`` called directly, with the
free-surface parameters (mode, dh, forward sign) computed here exactly as
``WheelRearHalf.kernel_params`` does for the paper's psi (identity). Errors come back as status
codes and numbers; ``bodies.simulate`` turns them into the same IntegratorError messages as the
Python loop.
"""

from __future__ import annotations

import math

import numba
import numpy as np

from intrusim.forces import _wrench_kernel

# status codes
OK = 0
SINGULAR = 1  # singular Newton Jacobian (info[0] = t)
NEWTON_NONFINITE = 2  # non-finite velocity in the Newton iteration (info[0] = t)
NOT_CONVERGED = 3  # Newton failed in every sub-step split (info = t_end, |G|, tol, t, h)
STATE_NONFINITE = 4  # non-finite state (info[0] = t)
TOO_FAST = 5  # info = t, speed
TOO_DEEP = 6  # info = t, depth below the surface


@numba.njit(cache=True)
def _omega_at(w: float, ramp: float, t: float) -> float:
    if ramp <= 0.0 or t >= ramp:
        return w
    return w * max(t, 0.0) / ramp


@numba.njit(cache=True)
def _angle_at(w: float, ramp: float, t: float) -> float:
    if ramp <= 0.0:
        return w * t
    if t <= ramp:
        tt = max(t, 0.0)
        return 0.5 * w * (tt * tt) / ramp
    return w * (t - 0.5 * ramp)


@numba.njit(cache=True)
def _force(
    mid, nrm, area, ccen, crad, surface_z, coef, alpha_scale, lam_rho, fs_kind, fs_r, fs_g,
    x, z, th, vx, vz, om,
):  # fmt: skip
    """``ResistiveForceModel.wrench_tuple`` for a model with a compiled free surface."""
    mode, dh, fwd = 0, 0.0, 1.0
    if fs_kind >= 1:  # WheelRearHalf.kernel_params with psi = identity: dh = r (r w^2 / g)
        mode = fs_kind
        dh = fs_r * (fs_r * om * om / fs_g)
        if om != 0.0:  # travel_sign(omega, vx)
            fwd = -1.0 if om > 0.0 else 1.0
        else:
            fwd = -1.0 if vx < 0.0 else 1.0
    return _wrench_kernel(
        mid, nrm, area, ccen, crad, x, z, th, vx, vz, om, surface_z, coef, alpha_scale, lam_rho, mode, dh, fwd
    )


@numba.njit(cache=True)
def _implicit_step(
    spec, x0, z0, th1, vx0, vz0, om1, dt, ax_ext, az_ext, inv_mx, inv_mz,
    max_iter, velocity_tol, fd_step, stall_iter, contraction, max_backtrack, g_tol, jac, has_jac,
):  # fmt: skip
    """One backward-Euler step, as ``bodies._implicit_step``.

    Returns (status, vx1, vz1, fx, fz, moment, iterations, best |G|); ``jac`` (4,) and
    ``has_jac`` (1,) are updated in place.
    """
    mid, nrm, area, ccen, crad, sz, coef, asc, lr, fk, fr, fg = spec
    vx, vz = vx0, vz0
    h = fd_step
    fx, fz, m = _force(mid, nrm, area, ccen, crad, sz, coef, asc, lr, fk, fr, fg, x0 + dt * vx, z0 + dt * vz, th1, vx, vz, om1)
    gx = vx - vx0 - dt * (fx * inv_mx + ax_ext)
    gz = vz - vz0 - dt * (fz * inv_mz + az_ext)
    norm = math.hypot(gx, gz)
    b_norm, b_vx, b_vz, b_fx, b_fz, b_m = norm, vx, vz, fx, fz, m
    stall = 0
    refreshed = -1
    for it in range(1, max_iter + 1):
        if has_jac[0] == 0 or (stall > 0 and refreshed < it - 1):
            f1x, f1z, _ = _force(mid, nrm, area, ccen, crad, sz, coef, asc, lr, fk, fr, fg,
                                 x0 + dt * (vx + h), z0 + dt * vz, th1, vx + h, vz, om1)  # fmt: skip
            gx1 = (vx + h) - vx0 - dt * (f1x * inv_mx + ax_ext)
            gz1 = vz - vz0 - dt * (f1z * inv_mz + az_ext)
            f2x, f2z, _ = _force(mid, nrm, area, ccen, crad, sz, coef, asc, lr, fk, fr, fg,
                                 x0 + dt * vx, z0 + dt * (vz + h), th1, vx, vz + h, om1)  # fmt: skip
            gx2 = vx - vx0 - dt * (f2x * inv_mx + ax_ext)
            gz2 = (vz + h) - vz0 - dt * (f2z * inv_mz + az_ext)
            jac[0] = (gx1 - gx) / h
            jac[1] = (gx2 - gx) / h
            jac[2] = (gz1 - gz) / h
            jac[3] = (gz2 - gz) / h
            has_jac[0] = 1
            refreshed = it
        j11, j12, j21, j22 = jac[0], jac[1], jac[2], jac[3]
        det = j11 * j22 - j12 * j21
        if not math.isfinite(det) or det == 0.0:
            return SINGULAR, vx, vz, fx, fz, m, it, b_norm
        dvx = -(j22 * gx - j12 * gz) / det
        dvz = -(-j21 * gx + j11 * gz) / det
        norm0 = norm
        step = 1.0
        nx, nz, ngx, ngz, nfx, nfz, nm = vx, vz, gx, gz, fx, fz, m
        for _ in range(max_backtrack):  # backtracking: accept the first step that reduces |G|
            nx, nz = vx + step * dvx, vz + step * dvz
            nfx, nfz, nm = _force(mid, nrm, area, ccen, crad, sz, coef, asc, lr, fk, fr, fg,
                                  x0 + dt * nx, z0 + dt * nz, th1, nx, nz, om1)  # fmt: skip
            ngx = nx - vx0 - dt * (nfx * inv_mx + ax_ext)
            ngz = nz - vz0 - dt * (nfz * inv_mz + az_ext)
            if math.hypot(ngx, ngz) < norm0:
                break
            step *= 0.5
        if not (math.isfinite(nx) and math.isfinite(nz) and math.isfinite(ngx) and math.isfinite(ngz)):
            return NEWTON_NONFINITE, vx, vz, fx, fz, m, it, b_norm
        update = math.hypot(dvx, dvz)
        vx, vz, gx, gz, fx, fz, m = nx, nz, ngx, ngz, nfx, nfz, nm
        norm = math.hypot(gx, gz)
        if update <= velocity_tol:
            return OK, vx, vz, fx, fz, m, it, b_norm
        if norm < b_norm:
            b_norm, b_vx, b_vz, b_fx, b_fz, b_m = norm, vx, vz, fx, fz, m
        if norm > contraction * norm0 or step < 1.0:
            stall += 1
        else:
            stall = 0
        if stall >= stall_iter and b_norm <= g_tol:
            return OK, b_vx, b_vz, b_fx, b_fz, b_m, it, b_norm
    if b_norm <= g_tol:
        return OK, b_vx, b_vz, b_fx, b_fz, b_m, max_iter, b_norm
    return NOT_CONVERGED, vx, vz, fx, fz, m, max_iter, b_norm


@numba.njit(cache=True)
def simulate_implicit(
    spec, w_target, ramp, t_start, dt, n, x, z, th0, vx, vz, ax_ext, az_ext, inv_mx, inv_mz,
    max_iter, velocity_tol, fd_step, stall_iter, contraction, max_backtrack, max_halvings, g_rate,
    max_speed, max_depth, surface, out, iters, info,
):  # fmt: skip
    """Fill ``out`` (9, n + 1: x, z, theta, vx, vz, omega, fx, fz, moment) and ``iters`` (n + 1,).

    Returns (status, step index); on failure ``info`` holds the numbers of the message.
    """
    mid, nrm, area, ccen, crad, sz, coef, asc, lr, fk, fr, fg = spec
    om = _omega_at(w_target, ramp, t_start)
    angle0 = _angle_at(w_target, ramp, t_start)
    th_base = th0 - angle0
    fx, fz, m = _force(mid, nrm, area, ccen, crad, sz, coef, asc, lr, fk, fr, fg, x, z, th0, vx, vz, om)
    out[0, 0], out[1, 0], out[2, 0], out[3, 0], out[4, 0] = x, z, th0, vx, vz
    out[5, 0], out[6, 0], out[7, 0], out[8, 0] = om, fx, fz, m
    iters[0] = 0
    jac = np.zeros(4)
    has_jac = np.zeros(1, np.int64)
    for i in range(1, n + 1):
        ti = t_start + i * dt
        tprev = t_start + (i - 1) * dt
        om1 = _omega_at(w_target, ramp, ti)
        th1 = th0 + (_angle_at(w_target, ramp, ti) - angle0)
        done = False
        total = 0
        l_norm, l_tol, l_t, l_h = 0.0, 0.0, 0.0, 0.0
        for halvings in range(max_halvings + 1):
            k = 2**halvings
            h = dt / k
            xs, zs, vxs, vzs, total = x, z, vx, vz, 0
            g_tol = g_rate * h
            failed = False
            for j in range(1, k + 1):
                tj = tprev + j * h
                st, vx1, vz1, sfx, sfz, sm, it, bn = _implicit_step(
                    spec, xs, zs, th_base + _angle_at(w_target, ramp, tj), vxs, vzs, _omega_at(w_target, ramp, tj),
                    h, ax_ext, az_ext, inv_mx, inv_mz, max_iter, velocity_tol, fd_step, stall_iter, contraction,
                    max_backtrack, g_tol, jac, has_jac,
                )  # fmt: skip
                if st == SINGULAR or st == NEWTON_NONFINITE:
                    info[0] = tj
                    return st, i
                if st == NOT_CONVERGED:
                    l_norm, l_tol, l_t, l_h = bn, g_tol, tj, h
                    failed = True
                    break
                xs, zs, vxs, vzs, total = xs + h * vx1, zs + h * vz1, vx1, vz1, total + it
                fx, fz, m = sfx, sfz, sm
            if not failed:
                x, z, vx, vz = xs, zs, vxs, vzs
                done = True
                break
            has_jac[0] = 0  # jac.clear()
        if not done:
            info[0], info[1], info[2], info[3], info[4] = tprev + dt, l_norm, l_tol, l_t, l_h
            return NOT_CONVERGED, i
        if not (math.isfinite(x) and math.isfinite(z) and math.isfinite(vx) and math.isfinite(vz)):
            info[0] = ti
            return STATE_NONFINITE, i
        if math.hypot(vx, vz) > max_speed:
            info[0], info[1] = ti, math.hypot(vx, vz)
            return TOO_FAST, i
        if z < surface - max_depth:
            info[0], info[1] = ti, surface - z
            return TOO_DEEP, i
        out[0, i], out[1, i], out[2, i], out[3, i], out[4, i] = x, z, th1, vx, vz
        out[5, i], out[6, i], out[7, i], out[8, i] = om1, fx, fz, m
        iters[i] = total
    return OK, n
