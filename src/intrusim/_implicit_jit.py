"""Compiled (Numba) time loop of the implicit integrator of :mod:`intrusim.bodies`.

The same scheme as the Python loop of ``bodies.simulate`` (which stays the reference and the
fallback for force models without a compiled form), step for step:

* BDF2 (``order`` 2, from the second step) or backward Euler on (vx, vz), positions by the same
  formula from the new velocity, theta following the prescribed omega ramp exactly;
* damped modified Newton with a 2 x 2 forward-difference Jacobian kept from step to step and
  refreshed on poor contraction; the same stall / ``force_tol_rel`` acceptance rule;
* a failed step retried in 2, 4, ..., 2^max_halvings backward-Euler sub-steps;
* the same divergence checks (non-finite state, max_speed, max_depth).

The force is that of the compiled RFT/DRFT kernel ``forces._wrench_kernel``, with the
free-surface parameters (mode, dh, forward sign) of ``_traction.surface_params`` (the same numbers
as ``WheelRearHalf.kernel_params`` for the identity or an affine psi); both evaluate each element
with the one compiled element law, ``_traction.element_force``. Within a step it is evaluated
on elements rotated once per step (``_step_force``, see below), bit for bit the same numbers. Errors come back as status
codes and numbers; ``bodies.simulate`` turns them into the same IntegratorError messages as the
Python loop.
"""

from __future__ import annotations

import math

import numba
import numpy as np

from intrusim._traction import alpha_constants, element_force, fit_rows, surface_params
from intrusim.forces import CHUNK, _angle_of_pseudo, _pseudo_angle, _wrench_kernel, zone_band
from intrusim.kinematics import bdf2_base as bdf2_base_py
from intrusim.kinematics import unbalanced_impulse as unbalanced_impulse_py
from intrusim.laws.bulldozing import bulldozing_wrench
from intrusim.laws.drft import MID_ANGLE_TIE, circle_arc_mid, zone_weight

# status codes
OK = 0
SINGULAR = 1  # singular Newton Jacobian (info[0] = t)
NEWTON_NONFINITE = 2  # non-finite velocity in the Newton iteration (info[0] = t)
NOT_CONVERGED = 3  # Newton failed in every sub-step split (info = t_end, |G|, tol, t, h)
STATE_NONFINITE = 4  # non-finite state (info[0] = t)
TOO_FAST = 5  # info = t, speed
TOO_DEEP = 6  # info = t, depth below the surface


bdf2_base = numba.njit(cache=True)(bdf2_base_py)  # one copy: the Python loop calls bdf2_base_py
unbalanced_impulse = numba.njit(cache=True)(unbalanced_impulse_py)  # likewise


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
    mid, nrm, area, ccen, crad, surface_z, coef, alpha_scale, lam_rho, fs_kind, fs_r, fs_g, fs_slope, fs_offset,
    x, z, th, vx, vz, om, zone_width,
):  # fmt: skip
    """``ResistiveForceModel.wrench_tuple`` for a model with a compiled free surface."""
    mode, dh, fwd = surface_params(fs_kind, fs_r, fs_g, fs_slope, fs_offset, vx, om)
    return _wrench_kernel(
        mid, nrm, area, ccen, crad, x, z, th, vx, vz, om, surface_z, coef, alpha_scale, lam_rho, mode, dh, fwd, fs_r,
        zone_width,
    )  # fmt: skip


# Within one implicit step theta and omega are fixed: every force evaluation of the Newton
# iteration (finite-difference Jacobian included) sees the same rotated elements and differs only
# in the centre height z and velocity (vx, vz). The step rotates the elements that can touch once
# (_rotate_elements, _rotated_frame); each evaluation finds the contact arc (_contact_arc_mid),
# computes every element's force in a branch-free loop the compiler vectorises (_element_forces;
# an element the kernel would skip gets exactly 0) and sums them in element order (_ordered_sums).
# Each element force is the same IEEE expression as in forces._wrench_kernel and adding +-0
# changes no sum, so the result is that kernel's, bit for bit (tests/unit/test_step_force_kernel.py).
GEO_ROWS = 8  # rx, rz, nx, nz, cos 2 beta, sin 2 beta, pseudo-angle from straight down, area
# A step's rotated set covers centre heights z >= z0 + dt (vz0 - slack) and its leading subset the
# velocities within slack of (vx0, vz0) per component; slack = V_SLACK + 1.5 x the last step's
# velocity change. Outside, an evaluation uses every rotated element, or (below the height range,
# or on a turned travel sign at omega = 0) the full kernel: the same result, only slower.
V_SLACK = 0.01  # m/s


@numba.njit(cache=True)
def _contact_threshold(surface_z, mode, dh):
    """Height below which an element can touch: the surface, or surface - dh when dh < 0."""
    if mode >= 1 and dh < 0.0:
        return surface_z - dh
    return surface_z


@numba.njit(cache=True, inline="always")
def _put_element(dst, n, rx, rz, nx, nz, p, dA):
    """Column n of a rotated-element table: r, n, cos 2b = n_z^2 - n_x^2, sin 2b = 2 n_x n_z, p, dA."""
    dst[0, n], dst[1, n], dst[2, n], dst[3, n] = rx, rz, nx, nz
    dst[4, n], dst[5, n] = nz * nz - nx * nx, 2.0 * nx * nz
    dst[6, n], dst[7, n] = p, dA


@numba.njit(cache=True)
def _rotate_elements(mid, nrm, area, ccen, crad, th, z_low, thr, mode, fwd, vx0, vz0, om, v_slack, geo, lead):
    """Rotated elements r = R(th) p, n = R(th) n0 of a step; returns (n_g, n_l).

    geo[:, :n_g]: every element that can touch at a centre height z >= z_low (z_low + r_z < thr;
    float addition is monotone), in element order, with p the pseudo-angle of (fwd r_x, -r_z),
    the contact-arc angle. lead[:, :n_l]: those of them that can lead (v_n > 0) at a velocity
    within v_slack of (vx0, vz0) in each component: v_n0 > -1.5 v_slack, as |dv_n| <= sqrt(2) v_slack.
    """
    c, s = np.cos(th), np.sin(th)
    n_el = mid.shape[0]
    n_g, n_l = 0, 0
    vn_min = -(1.5 * v_slack + 1e-9)
    for j in range(ccen.shape[0]):
        if z_low + (s * ccen[j, 0] + c * ccen[j, 1]) - crad[j] >= thr:
            continue
        for i in range(j * CHUNK, min((j + 1) * CHUNK, n_el)):
            rz = s * mid[i, 0] + c * mid[i, 1]
            if z_low + rz >= thr:
                continue
            rx = c * mid[i, 0] - s * mid[i, 1]
            nx = c * nrm[i, 0] - s * nrm[i, 1]
            nz = s * nrm[i, 0] + c * nrm[i, 1]
            p = _pseudo_angle(fwd * rx, -rz) if mode >= 1 else 0.0
            _put_element(geo, n_g, rx, rz, nx, nz, p, area[i])
            n_g += 1
            if nx * (vx0 - om * rz) + nz * (vz0 + om * rx) > vn_min:
                _put_element(lead, n_l, rx, rz, nx, nz, p, area[i])
                n_l += 1
    return n_g, n_l


@numba.njit(cache=True)
def _contact_arc_mid(geo, n_g, z, surface_z, mode, dh, fwd, arc_radius):
    """The mid-angle of the contact arc (its two ends' mean angle, less MID_ANGLE_TIE), rad; -inf without a split."""
    if mode == 0:
        return -np.inf
    if mode == 3:  # the arc's ends on the circle of arc_radius (NaN out of contact: no split)
        return circle_arc_mid(z - surface_z, arc_radius, dh) - MID_ANGLE_TIE
    rx, rz, p_el = geo[0], geo[1], geo[6]
    plo, phi_ = np.inf, -np.inf
    qlo, qhi = -1, -1
    for q in range(n_g):  # mode 1: below the surface; mode 2: behind the lowest point, below z = -dh
        p = p_el[q]
        level = surface_z - dh if (mode == 2 and p < 0.0) else surface_z
        if z + rz[q] < level:
            if p < plo:
                plo, qlo = p, q
            if p > phi_:
                phi_, qhi = p, q
    if qlo < 0:
        return -np.inf
    return 0.5 * (np.arctan2(fwd * rx[qlo], -rz[qlo]) + np.arctan2(fwd * rx[qhi], -rz[qhi])) - MID_ANGLE_TIE


@numba.njit(cache=True)
def _zone_share(geo, n_g, share, phi_mid, width):
    """share[:n_g]: the share of dh each element sees (laws.drft.zone_weight): 1 behind the zone's band,
    linear across it, 0 in front of it (no band, width 0: 1 or 0 at the boundary; phi_mid -inf: 0)."""
    _, p_lo, p_hi = zone_band(phi_mid, width)
    p_ = geo[6]
    for q in range(n_g):
        p = p_[q]
        if p < p_lo:
            share[q] = 1.0
        elif p < p_hi:
            share[q] = zone_weight(_angle_of_pseudo(p), phi_mid, width)
        else:
            share[q] = 0.0


@numba.njit(cache=True, inline="always")
def _put_element_force(geo, q, out, depth, z, vx, vz, om, kz, kx, alpha_scale, lam_rho, thr):
    """out[:3, q] = (f_x, f_z, r x f) of element q at ``depth``: the expression of forces._wrench_kernel, or
    exactly 0 where the kernel skips it (above thr, trailing, not submerged; NaN alike)."""
    rx, rz, nx, nz = geo[0, q], geo[1, q], geo[2, q], geo[3, q]
    ux = vx - om * rz
    uz = vz + om * rx
    vn = nx * ux + nz * uz
    ex, ez = element_force(nx, nz, geo[4, q], geo[5, q], ux, uz, vn, depth, kz, kx, alpha_scale, lam_rho, geo[7, q])
    on = (not (z + rz >= thr)) & (not (vn <= 0.0)) & (not (depth >= 0.0))
    ex = ex if on else 0.0
    ez = ez if on else 0.0
    out[0, q] = ex
    out[1, q] = ez
    out[2, q] = rx * ez - rz * ex


@numba.njit(cache=True, error_model="numpy")
def _element_forces(geo, n_g, out, z, vx, vz, om, surface_z, k, alpha_scale, lam_rho, dh, thr, phi_mid, width):
    """out[:3, :n_g] = (f_x, f_z, r x f) per element, f = (alpha H(-z~)|z~| - n lam rho v_n^2) dA (Eq. 4).

    Branch-free (vectorised): an element below thr, leading (v_n > 0) and submerged (z~ < 0) gets
    the expression of forces._wrench_kernel, any other exactly 0. Behind the zone boundary
    ``phi_mid`` (rad; -inf: none) the surface is lowered by dh; with a band (``width`` > 0) by each
    element's share (_zone_share, in out[3]).
    """
    kz, kx = fit_rows(k)
    rz_, p_ = geo[1], geo[6]
    if width > 0.0:
        share = out[3]
        _zone_share(geo, n_g, share, phi_mid, width)
        for q in range(n_g):
            depth = z + rz_[q] - surface_z + dh * share[q]
            _put_element_force(geo, q, out, depth, z, vx, vz, om, kz, kx, alpha_scale, lam_rho, thr)
    else:
        p_mid = zone_band(phi_mid, 0.0)[0]
        for q in range(n_g):
            d0 = z + rz_[q] - surface_z
            depth = d0 + dh if p_[q] < p_mid else d0  # the lowered rear surface (p_mid = -inf: none)
            _put_element_force(geo, q, out, depth, z, vx, vz, om, kz, kx, alpha_scale, lam_rho, thr)
    return out


@numba.njit(cache=True)
def _ordered_sums(out, n_g):
    """(sum f_x, sum f_z, sum r x f) in element order, as forces._wrench_kernel adds them."""
    fx = 0.0
    fz = 0.0
    mom = 0.0
    for q in range(n_g):
        fx += out[0, q]
        fz += out[1, q]
        mom += out[2, q]
    return fx, fz, mom


@numba.njit(cache=True)
def _force_rotated(
    frame, work, z, vx, vz, om, surface_z, k, alpha_scale, lam_rho, mode, dh, fwd, thr, arc_radius, width
):
    """forces._wrench_kernel on a step's rotated elements: sum of (alpha H(-z~)|z~| - n lam rho v_n^2) dA, and moment."""
    geo, n_g, lead, n_l, _, _, vx0, vz0, v_slack = frame
    phi_mid = _contact_arc_mid(geo, n_g, z, surface_z, mode, dh, fwd, arc_radius)
    src, n = geo, n_g
    if abs(vx - vx0) <= v_slack and abs(vz - vz0) <= v_slack:  # only the elements that can lead
        src, n = lead, n_l
    _element_forces(
        src, n, work, z, vx, vz, om, surface_z, k, alpha_scale, lam_rho, dh if mode >= 1 else 0.0, thr, phi_mid, width
    )
    return _ordered_sums(work, n)


@numba.njit(cache=True)
def _rotated_frame(spec, th, z_low, fwd, vx0, vz0, om, v_slack, geo, lead):
    """(geo, n_g, lead, n_l, z_low, fwd, vx0, vz0, v_slack): the rotated elements of one step (_rotate_elements)."""
    mid, nrm, area, ccen, crad, sz, coef, asc, lr, fk, fr, fg, fc, fo, bs, br, zw = spec
    mode, dh, _ = surface_params(fk, fr, fg, fc, fo, vx0, om)
    thr = _contact_threshold(sz, mode, dh)
    n_g, n_l = _rotate_elements(mid, nrm, area, ccen, crad, th, z_low, thr, mode, fwd, vx0, vz0, om, v_slack, geo, lead)
    return geo, n_g, lead, n_l, z_low, fwd, vx0, vz0, v_slack


@numba.njit(cache=True)
def _step_force(spec, frame, work, k, z, th, vx, vz, om):
    """One force evaluation of a step: from its rotated elements, or from scratch below z_low / on a turned travel sign;
    plus the body's bulldozing resistance (laws.bulldozing, 0 unless the model has one)."""
    mid, nrm, area, ccen, crad, sz, coef, asc, lr, fk, fr, fg, fc, fo, bs, br, zw = spec
    mode, dh, fwd = surface_params(fk, fr, fg, fc, fo, vx, om)
    if z >= frame[4] and fwd == frame[5]:
        fx, fz, m = _force_rotated(
            frame, work, z, vx, vz, om, sz, k, asc, lr, mode, dh, fwd, _contact_threshold(sz, mode, dh), fr, zw
        )
    else:
        fx, fz, m = _force(
            mid, nrm, area, ccen, crad, sz, coef, asc, lr, fk, fr, fg, fc, fo, 0.0, z, th, vx, vz, om, zw
        )  # x: unused
    if bs > 0.0:
        bx, bm = bulldozing_wrench(bs, br, sz, z, vx)
        fx, m = fx + bx, m + bm
    return fx, fz, m


@numba.njit(cache=True)
def _largest_element_force(spec, frame, work, k, z, vx, vz, om):
    """``ResistiveForceModel.largest_element_force`` on a step's rotated elements: max |f| of one element, N."""
    mid, nrm, area, ccen, crad, sz, coef, asc, lr, fk, fr, fg, fc, fo, bs, br, zw = spec
    geo, n_g = frame[0], frame[1]
    mode, dh, fwd = surface_params(fk, fr, fg, fc, fo, vx, om)
    thr = _contact_threshold(sz, mode, dh)
    phi_mid = _contact_arc_mid(geo, n_g, z, sz, mode, dh, fwd, fr)
    _element_forces(geo, n_g, work, z, vx, vz, om, sz, k, asc, lr, dh if mode >= 1 else 0.0, thr, phi_mid, zw)
    big = 0.0
    for q in range(n_g):
        big = max(big, math.hypot(work[0, q], work[1, q]))
    return big


@numba.njit(cache=True)
def _implicit_step(
    spec, x0, z0, th1, vx0, vz0, om1, dt, ax_ext, az_ext, inv_mx, inv_mz,
    max_iter, velocity_tol, fd_step, stall_iter, contraction, max_backtrack, g_tol, jac, has_jac, geo, lead, work, k, v_slack,
):  # fmt: skip
    """One implicit step from the base state, as ``bodies._implicit_step`` (BDF2 passes its base and (2/3) dt).

    Returns (status, vx1, vz1, fx, fz, moment, iterations, best |G|); ``jac`` (4,) and
    ``has_jac`` (1,) are updated in place; ``geo``, ``lead``, ``work``: work arrays of
    _rotate_elements and _element_forces,
    ``k``: ``_traction.alpha_constants`` of the fit.
    """
    mid, nrm, area, ccen, crad, sz, coef, asc, lr, fk, fr, fg, fc, fo, bs, br, zw = spec
    # theta and omega are fixed in the step: rotate the elements that can touch once
    _, _, fwd = surface_params(fk, fr, fg, fc, fo, vx0, om1)
    frame = _rotated_frame(spec, th1, z0 + dt * (vz0 - v_slack), fwd, vx0, vz0, om1, v_slack, geo, lead)
    vx, vz = vx0, vz0
    h = fd_step
    fx, fz, m = _step_force(spec, frame, work, k, z0 + dt * vz, th1, vx, vz, om1)
    gx = vx - vx0 - dt * (fx * inv_mx + ax_ext)
    gz = vz - vz0 - dt * (fz * inv_mz + az_ext)
    norm = math.hypot(gx, gz)
    b_norm, b_vx, b_vz, b_fx, b_fz, b_m = norm, vx, vz, fx, fz, m
    stall = 0
    refreshed = -1
    for it in range(1, max_iter + 1):
        if has_jac[0] == 0 or (stall > 0 and refreshed < it - 1):
            f1x, f1z, _ = _step_force(spec, frame, work, k, z0 + dt * vz, th1, vx + h, vz, om1)
            gx1 = (vx + h) - vx0 - dt * (f1x * inv_mx + ax_ext)
            gz1 = vz - vz0 - dt * (f1z * inv_mz + az_ext)
            f2x, f2z, _ = _step_force(spec, frame, work, k, z0 + dt * (vz + h), th1, vx, vz + h, om1)
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
            nfx, nfz, nm = _step_force(spec, frame, work, k, z0 + dt * nz, th1, nx, nz, om1)
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
    # the law's resolution: one element's force (bodies._implicit_step)
    if b_norm <= dt * max(inv_mx, inv_mz) * _largest_element_force(
        spec, frame, work, k, z0 + dt * b_vz, b_vx, b_vz, om1
    ):
        return OK, b_vx, b_vz, b_fx, b_fz, b_m, max_iter, b_norm
    return NOT_CONVERGED, vx, vz, fx, fz, m, max_iter, b_norm


@numba.njit(cache=True)
def simulate_implicit(
    spec, w_target, ramp, t_start, dt, n, x, z, th0, vx, vz, ax_ext, az_ext, inv_mx, inv_mz,
    max_iter, velocity_tol, fd_step, stall_iter, contraction, max_backtrack, max_halvings, g_rate,
    max_speed, max_depth, surface, out, iters, info, order, xm, zm, vxm, vzm, carry,
):  # fmt: skip
    """Fill ``out`` (9, n + 1: x, z, theta, vx, vz, omega, fx, fz, moment) and ``iters`` (n + 1,).

    ``order`` 2: BDF2 (``bdf2_base``) from the second step, or from the first when (xm, zm, vxm, vzm),
    the state one step before the start, is given (not NaN); backward Euler in a first step without
    it and in the sub-steps of a step whose Newton iteration failed; ``order`` 1: backward Euler.
    ``carry`` (7,): [impulse x, impulse z, has Jacobian, j11, j12, j21, j22], the integrator's state
    a former run left (``bodies.Carry``), updated in place to this run's at its end.
    Returns (status, step index); on failure ``info`` holds the numbers of the message.
    """
    mid, nrm, area, ccen, crad, sz, coef, asc, lr, fk, fr, fg, fc, fo, bs, br, zw = spec
    om = _omega_at(w_target, ramp, t_start)
    angle0 = _angle_at(w_target, ramp, t_start)
    th_base = th0 - angle0
    fx, fz, m = _force(mid, nrm, area, ccen, crad, sz, coef, asc, lr, fk, fr, fg, fc, fo, x, z, th0, vx, vz, om, zw)
    if bs > 0.0:
        bx, bm = bulldozing_wrench(bs, br, sz, z, vx)
        fx, m = fx + bx, m + bm
    out[0, 0], out[1, 0], out[2, 0], out[3, 0], out[4, 0] = x, z, th0, vx, vz
    out[5, 0], out[6, 0], out[7, 0], out[8, 0] = om, fx, fz, m
    iters[0] = 0
    jac = carry[3:7].copy()  # the Newton Jacobian a former run left (carry[2]: whether it did)
    has_jac = np.full(1, int(carry[2]), np.int64)
    geo = np.empty((GEO_ROWS, mid.shape[0]))
    lead = np.empty((GEO_ROWS, mid.shape[0]))
    work = np.empty((4, mid.shape[0]))  # per element: f_x, f_z, r x f, the zone band's share of dh
    fit = alpha_constants(coef)
    v_slack = V_SLACK
    has_back = not math.isnan(xm)  # the state one step back (BDF2)
    px, pz = carry[0], carry[1]  # the impulse (per unit mass) a former run left unbalanced
    for i in range(1, n + 1):
        ti = t_start + i * dt
        tprev = t_start + (i - 1) * dt
        om1 = _omega_at(w_target, ramp, ti)
        th1 = th0 + (_angle_at(w_target, ramp, ti) - angle0)
        done = False
        total = 0
        l_norm, l_tol, l_t, l_h = 0.0, 0.0, 0.0, 0.0
        if order == 2 and has_back:
            xb, zb, vxb, vzb, c = bdf2_base(x, z, vx, vz, xm, zm, vxm, vzm)
            st, vx1, vz1, sfx, sfz, sm, it, bn = _implicit_step(
                spec, xb, zb, th1, vxb - c * px, vzb - c * pz, om1, c * dt, ax_ext, az_ext, inv_mx, inv_mz, max_iter, velocity_tol,
                fd_step, stall_iter, contraction, max_backtrack, g_rate * c * dt, jac, has_jac, geo, lead, work, fit,
                v_slack,
            )  # fmt: skip
            if st == SINGULAR or st == NEWTON_NONFINITE:
                info[0] = ti
                return st, i
            if st == OK:
                # the step's unbalanced impulse (per unit mass), made up by the next step
                px = unbalanced_impulse(vx1, vxb, px, c, dt, sfx * inv_mx + ax_ext)
                pz = unbalanced_impulse(vz1, vzb, pz, c, dt, sfz * inv_mz + az_ext)
                v_slack = V_SLACK + 1.5 * max(abs(vx1 - vx), abs(vz1 - vz))
                xm, zm, vxm, vzm = x, z, vx, vz
                x, z, vx, vz = xb + c * dt * vx1, zb + c * dt * vz1, vx1, vz1
                has_back = True
                fx, fz, m = sfx, sfz, sm
                done = True
                total = it
            else:
                has_jac[0] = 0  # then backward Euler, in sub-steps if need be
        for halvings in range(max_halvings + 1):
            if done:
                break
            k = 2**halvings
            h = dt / k
            xs, zs, vxs, vzs, total = x, z, vx, vz, 0
            qx, qz = px, pz
            g_tol = g_rate * h
            failed = False
            for j in range(1, k + 1):
                tj = tprev + j * h
                st, vx1, vz1, sfx, sfz, sm, it, bn = _implicit_step(
                    spec, xs, zs, th_base + _angle_at(w_target, ramp, tj), vxs - qx, vzs - qz, _omega_at(w_target, ramp, tj),
                    h, ax_ext, az_ext, inv_mx, inv_mz, max_iter, velocity_tol, fd_step, stall_iter, contraction,
                    max_backtrack, g_tol, jac, has_jac, geo, lead, work, fit, v_slack,
                )  # fmt: skip
                if st == SINGULAR or st == NEWTON_NONFINITE:
                    info[0] = tj
                    return st, i
                if st == NOT_CONVERGED:
                    l_norm, l_tol, l_t, l_h = bn, g_tol, tj, h
                    failed = True
                    break
                qx = unbalanced_impulse(vx1, vxs, qx, 1.0, h, sfx * inv_mx + ax_ext)
                qz = unbalanced_impulse(vz1, vzs, qz, 1.0, h, sfz * inv_mz + az_ext)
                xs, zs, vxs, vzs, total = xs + h * vx1, zs + h * vz1, vx1, vz1, total + it
                fx, fz, m = sfx, sfz, sm
            if not failed:
                px, pz = qx, qz
                v_slack = V_SLACK + 1.5 * max(abs(vxs - vx), abs(vzs - vz))  # for the next step's leading subset
                xm, zm, vxm, vzm = x, z, vx, vz
                x, z, vx, vz = xs, zs, vxs, vzs
                has_back = True
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
    carry[0], carry[1], carry[2] = px, pz, has_jac[0]
    carry[3:7] = jac
    return OK, n
