"""Rigid polygon - grain contact on the grid: Coulomb friction, no tension (SPEC 1, step 3).

For each grid node within ``band`` of the polygon (signed distance d < band, d < 0 inside):
v_b = v_cm + omega x r (rigid velocity at the node), v_rel = v_node - v_b, n = outward normal.
If v_rel . n < 0 (approaching) the normal part is removed and the tangential part is reduced
by at most mu |dv_n| (Coulomb); separating nodes are left alone. The momentum removed from the
grains, summed over nodes and divided by dt, is the force on the body (and its moment about
the body reference point). The reductions are accumulated in float64, once over all nodes and
once over the nodes ahead of the reference point (x > x_body), so the force can be split front / rear.
With fixed-point sums (a GPU: ``backend.deterministic_sums``) each step's node sums are 64-bit
integers, exact in any order, added to the float64 totals by one serial kernel.
"""

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
import taichi as ti

from . import backend
from ._taichi_private import free_ndarrays
from .coulomb import coulomb_project
from .exact_sums import ATOMIC, FIXED, scatter_add
from .particles import LANES, get_scalar, get_vec2, set_mat2, set_vec2
from .step_graph import Launch, Var

if TYPE_CHECKING:
    from .grid import Grid


@ti.func
def polygon_signed_distance(p, verts: ti.template(), nv):
    """Signed distance from p to a closed polygon (negative inside) and the outward unit normal.

    The normal is (p - q)/|p - q| with q the nearest boundary point (sign flipped inside); on the
    boundary it falls back to the nearest edge's outward normal (ccw polygon).
    """
    best = 1e30
    q_best = p
    edge_n = ti.Vector([0.0, 1.0])
    inside = False
    for k in range(nv):
        a = verts[k]
        b = verts[(k + 1) % nv]
        ab = b - a
        t = ti.math.clamp((p - a).dot(ab) / ab.dot(ab), 0.0, 1.0)
        q = a + t * ab
        d2 = (p - q).dot(p - q)
        if d2 < best:
            best = d2
            q_best = q
            edge_n = ti.Vector([ab[1], -ab[0]]).normalized()
        # crossing number for the inside test
        if (a[1] > p[1]) != (b[1] > p[1]):
            x_cross = a[0] + (p[1] - a[1]) / (b[1] - a[1]) * ab[0]
            if p[0] < x_cross:
                inside = not inside
    dist = ti.sqrt(best)
    n = edge_n
    if dist > 1e-12:
        n = (p - q_best) / dist
        if inside:
            n = -n
    sd = dist
    if inside:
        sd = -dist
    return sd, n


@ti.func
def node_box(cx: ti.f64, cz: ti.f64, radius: ti.f64, h: ti.f64, pad: int, nx: int, ny: int):
    """Node index range [i0, i1) x [j0, j1) covering the disc of ``radius`` about (cx, cz), clipped
    to the nx x ny grid (in float64, as the pose is held)."""
    i0 = ti.max(ti.cast(ti.floor((cx - radius) / h), ti.i32) + pad, 0)
    i1 = ti.min(ti.cast(ti.ceil((cx + radius) / h), ti.i32) + pad + 1, nx)
    j0 = ti.max(ti.cast(ti.floor((cz - radius) / h), ti.i32) + pad, 0)
    j1 = ti.min(ti.cast(ti.ceil((cz + radius) / h), ti.i32) + pad + 1, ny)
    return i0, ti.max(i1, i0), j0, ti.max(j1, j0)


def _make_contact_kernel(fixed: bool):
    mode = FIXED if fixed else ATOMIC  # how the nodes' impulses are summed (exact_sums.scatter_add)

    @ti.kernel
    def rigid_polygon_contact(
        gm: ti.types.ndarray(),
        gv: ti.types.ndarray(),
        verts: ti.types.ndarray(),
        nv: int,
        h: float,
        pad: int,
        pose: ti.types.ndarray(),
        mu: float,
        band: float,
        reach: float,
        dt: float,
        impulse: ti.types.ndarray(),
        scale: float,
    ):
        """Project grid velocities against one rigid polygon; impulse[0] += (Fx, Fz, My) dt on the body.

        impulse[1] += the same from the nodes ahead of the reference point (x > x_body) only.
        Fixed point (``fixed``): ``impulse`` holds this step's 64-bit integer sums of
        round(value * ``scale``), exact in any order (``fold_impulse`` adds them to the totals);
        otherwise float64 atomic adds into the totals.

        ``pose`` = (x, z, theta, vx, vz, omega) in float64 on the device (the body's dynamics may
        advance it there, see intruder.advance_coupled). ``reach`` = the largest vertex distance from
        the reference point + band: nodes farther away are outside the band and skip the distance
        computation; the nodes visited are the box of ``node_box`` around (x, z) that covers reach + h.
        """
        bx, bz, theta = ti.cast(pose[0], float), ti.cast(pose[1], float), ti.cast(pose[2], float)
        bvx, bvz, omega = ti.cast(pose[3], float), ti.cast(pose[4], float), ti.cast(pose[5], float)
        h64 = ti.cast(h, ti.f64)
        i0, i1, j0, j1 = node_box(pose[0], pose[1], ti.cast(reach, ti.f64) + h64, h64, pad, gm.shape[0], gm.shape[1])
        c, s = ti.cos(theta), ti.sin(theta)
        nj = j1 - j0
        ti.loop_config(serialize=backend.SERIAL_LOOPS)
        for q in range((i1 - i0) * nj):  # the box, row by row (as ti.ndrange)
            i = i0 + q // nj
            j = j0 + q % nj
            node = ti.Vector([(i - pad) * h, (j - pad) * h])
            r = node - ti.Vector([bx, bz])
            if gm[i, j] > 0.0 and r.norm_sqr() < reach * reach:
                local = ti.Vector([c * r[0] + s * r[1], -s * r[0] + c * r[1]])  # R(-theta) r
                sd, n_loc = polygon_signed_distance(local, verts, nv)
                if sd < band:
                    n = ti.Vector([c * n_loc[0] - s * n_loc[1], s * n_loc[0] + c * n_loc[1]])
                    vb = ti.Vector([bvx - omega * r[1], bvz + omega * r[0]])  # v_cm + omega x r
                    v_old = gv[i, j]
                    v_new = vb + coulomb_project(v_old - vb, n, mu)
                    dp = ti.cast(gm[i, j], ti.f64) * ti.cast(v_new - v_old, ti.f64)  # on the grains
                    moment = ti.cast(r[0], ti.f64) * (-dp[1]) - ti.cast(r[1], ti.f64) * (-dp[0])
                    j_node = ti.Vector([-dp[0], -dp[1], moment])
                    scatter_add(impulse, 0, j_node, mode, scale)
                    if r[0] > 0.0:  # ahead of the body's reference point
                        scatter_add(impulse, 1, j_node, mode, scale)
                    gv[i, j] = v_new

    return rigid_polygon_contact


_CONTACT_KERNELS = {fixed: _make_contact_kernel(fixed) for fixed in (False, True)}


def _make_point_contact_kernel(fixed: bool):
    mode = FIXED if fixed else ATOMIC  # how the points' impulses are summed (exact_sums.scatter_add)

    @ti.kernel
    def rigid_polygon_point_contact(
        x: ti.types.ndarray(),
        v: ti.types.ndarray(),
        C: ti.types.ndarray(),
        mass: ti.types.ndarray(),
        n_points: int,
        verts: ti.types.ndarray(),
        nv: int,
        pose: ti.types.ndarray(),
        lead: float,
        mu: float,
        gap: float,
        dt: float,
        cand: ti.types.ndarray(),
        count: ti.types.ndarray(),
        impulse: ti.types.ndarray(),
        scale: float,
    ):
        """Coulomb contact of the points (after G2P) with one rigid polygon at its exact surface.

        Of the points near the body (``cand[:count[0]]``, found before G2P by the grid part), a
        point whose centre lies closer than ``gap`` (half a point spacing: the point's own extent)
        to the polygon, or inside it, and approaches it (v_rel . n < 0, n the outward normal at the
        nearest boundary point) gets v_p = v_b + coulomb_project(v_p - v_b, n, mu), v_b the body's
        rigid velocity at the point; its position this step follows the new velocity,
        x_p += dt (v_new - v_old), and a point found inside the polygon is put back on its surface
        (along n; no momentum). Its affine velocity C_p (P2G's m_p C_p (x_i - x_p)) becomes the
        body's rigid velocity gradient [[0, -omega], [omega, 0]]: the grid's gradient G2P gave it
        spans the body's surface, and kept beside the new v_p it would put into the nodes inside
        the body each step a momentum their projection takes out again, a force on the body that
        grows as 1 / dt (docs/mpm.md, "The contact points' affine velocity"). impulse[0] += the
        momentum taken from the points (on the body), impulse[1] += the same from points ahead of
        the reference point (x > x_body), as the grid contact. ``pose`` as there, at the step's
        start (the body moved by ``lead`` x its velocity since: dt when the host posed it, 0 when
        its dynamics already advanced it on the device). The last point's changes go to the pads
        of its block too (they stay copies of it).
        """
        bvx, bvz, omega = ti.cast(pose[3], float), ti.cast(pose[4], float), ti.cast(pose[5], float)
        bx = ti.cast(pose[0], float) + lead * bvx
        bz = ti.cast(pose[1], float) + lead * bvz
        theta = ti.cast(pose[2], float) + lead * omega
        c, s = ti.cos(theta), ti.sin(theta)
        ti.loop_config(serialize=backend.SERIAL_LOOPS)
        for k in range(count[0]):
            p = cand[k]
            xp = get_vec2(x, p)
            r = xp - ti.Vector([bx, bz])
            local = ti.Vector([c * r[0] + s * r[1], -s * r[0] + c * r[1]])  # R(-theta) r
            sd, n_loc = polygon_signed_distance(local, verts, nv)
            if sd < gap:
                n = ti.Vector([c * n_loc[0] - s * n_loc[1], s * n_loc[0] + c * n_loc[1]])
                vb = ti.Vector([bvx - omega * r[1], bvz + omega * r[0]])  # v_cm + omega x r
                v_old = get_vec2(v, p)
                v_new = vb + coulomb_project(v_old - vb, n, mu)
                x_new = xp + dt * (v_new - v_old)
                if sd < 0.0:  # inside: back onto the surface
                    x_new += -sd * n
                last = p
                if p == n_points - 1:  # the pads after the last point stay its copies
                    last = x.shape[0] * LANES - 1
                rigid_gradient = ti.Matrix([[0.0, -omega], [omega, 0.0]])
                for q in range(p, last + 1):
                    set_vec2(v, q, v_new)
                    set_vec2(x, q, x_new)
                    set_mat2(C, q, rigid_gradient)
                dp = ti.cast(get_scalar(mass, p), ti.f64) * ti.cast(v_new - v_old, ti.f64)  # on the point
                moment = ti.cast(r[0], ti.f64) * (-dp[1]) - ti.cast(r[1], ti.f64) * (-dp[0])
                j_point = ti.Vector([-dp[0], -dp[1], moment])
                scatter_add(impulse, 0, j_point, mode, scale)
                if r[0] > 0.0:  # ahead of the body's reference point
                    scatter_add(impulse, 1, j_point, mode, scale)

    return rigid_polygon_point_contact


_POINT_CONTACT_KERNELS = {fixed: _make_point_contact_kernel(fixed) for fixed in (False, True)}


@ti.func
def quadratic_weights(xp, h, pad):
    """Base node index and the quadratic B-spline weights (per axis) of a point at xp, as in P2G/G2P."""
    X = xp / h + pad
    base = ti.cast(ti.floor(X - 0.5), ti.i32)
    fx = X - ti.cast(base, float)
    w = [0.5 * (1.5 - fx) ** 2, 0.75 - (fx - 1.0) ** 2, 0.5 * (fx - 0.5) ** 2]
    return base, w


def _make_grid_point_contact_kernel(fixed: bool):
    mode = FIXED if fixed else ATOMIC

    @ti.kernel
    def rigid_polygon_grid_point_contact(
        x: ti.types.ndarray(),
        mass: ti.types.ndarray(),
        n_points: int,
        gm: ti.types.ndarray(),
        gv: ti.types.ndarray(),
        h: float,
        pad: int,
        verts: ti.types.ndarray(),
        nv: int,
        pose: ti.types.ndarray(),
        mu: float,
        gap: float,
        reach: float,
        margin: float,
        sweeps: int,
        relax: float,
        near: ti.types.ndarray(),
        geo: ti.types.ndarray(),
        cand: ti.types.ndarray(),
        count_out: ti.types.ndarray(),
        impulse: ti.types.ndarray(),
        scale: float,
    ):
        """The contact located at the points, enforced on the grid velocities (before G2P).

        The points closer than ``gap`` to the polygon (or inside it) are the contact points. For
        each, in a fixed order, ``sweeps`` times (Gauss-Seidel): v_p = sum_i w_ip v_i, the velocity
        G2P will give it; if it approaches the body, dv = v_b + coulomb_project(v_p - v_b, n, mu) - v_p
        (n the outward normal at the point's nearest boundary point) and the impulse m_p dv / S_p,
        S_p = sum_i w_ip^2 m_p / m_i, times ``relax``, is given to its nodes in the shares w_ip
        (v_i += relax w_ip m_p dv / (S_p m_i)); with relax 1 it would make v_p exactly the projected
        velocity (projected Gauss-Seidel, under-relaxed); minus the momentum given to the nodes goes
        to the body's impulse (impulse[1] too for a point ahead of the reference
        point). So the body's surface acts where the points meet it, not where nodes lie.

        The points within ``gap + margin`` of the polygon are listed in ``cand`` (their number in
        ``count_out[0]``) for the contact at the points after G2P: the blocks of points within
        ``reach`` of the reference point are marked, and the signed distance and world normal of
        their points found (``geo[p]`` = (sd, n_x, n_z)), in parallel; the candidates are then
        listed in one serial pass in the points' order, as the sweeps run: deterministic. The
        sweeps read each point's distance and normal from ``geo`` (the points and the body do not
        move during the sweeps).
        """
        bx, bz, theta = ti.cast(pose[0], float), ti.cast(pose[1], float), ti.cast(pose[2], float)
        bvx, bvz, omega = ti.cast(pose[3], float), ti.cast(pose[4], float), ti.cast(pose[5], float)
        c, s = ti.cos(theta), ti.sin(theta)
        ti.loop_config(serialize=backend.SERIAL_LOOPS)
        for blk in range(x.shape[0]):
            dx = x[blk, 0] - bx
            dz = x[blk, 1] - bz
            d2 = dx * dx + dz * dz
            hit = 0
            for k in ti.static(range(LANES)):
                if d2[k] < reach * reach:
                    hit = 1
            near[blk] = hit
            if hit:
                for k in range(LANES):
                    p = blk * LANES + k
                    sd, n = 1e30, ti.Vector([0.0, 0.0])
                    r = get_vec2(x, p) - ti.Vector([bx, bz])
                    if p < n_points and r.norm_sqr() < reach * reach:
                        local = ti.Vector([c * r[0] + s * r[1], -s * r[0] + c * r[1]])
                        sd, n_loc = polygon_signed_distance(local, verts, nv)
                        n = ti.Vector([c * n_loc[0] - s * n_loc[1], s * n_loc[0] + c * n_loc[1]])
                    geo[p] = ti.Vector([sd, n[0], n[1]])
        count = 0
        ti.loop_config(serialize=True)
        for blk in range(x.shape[0]):
            if near[blk]:
                for k in range(LANES):
                    p = blk * LANES + k
                    if geo[p][0] < gap + margin:
                        cand[count] = p
                        count += 1
        count_out[0] = count
        ti.loop_config(serialize=True)
        for q in range(sweeps * count):
            p = cand[q % count]
            xp = get_vec2(x, p)
            r = xp - ti.Vector([bx, bz])
            g = geo[p]
            sd, n = g[0], ti.Vector([g[1], g[2]])
            vb = ti.Vector([bvx - omega * r[1], bvz + omega * r[0]])
            base, w = quadratic_weights(xp, h, pad)
            vp = ti.Vector([0.0, 0.0])
            for a, b in ti.static(ti.ndrange(3, 3)):
                vp += w[a][0] * w[b][1] * gv[base[0] + a, base[1] + b]
            dv = vb + coulomb_project(vp - vb, n, mu) - vp
            if sd < gap and dv.norm_sqr() > 0.0:
                mp = get_scalar(mass, p)
                S = 0.0  # v_p's change per unit of dv given to the nodes: sum_i w_ip^2 m_p / m_i
                for a, b in ti.static(ti.ndrange(3, 3)):
                    mi = gm[base[0] + a, base[1] + b]
                    if mi > 0.0:
                        S += (w[a][0] * w[b][1]) ** 2 * mp / mi
                if S > 0.0:
                    dv *= relax / S  # relax = 1: v_p becomes exactly the projected velocity
                dp = ti.Vector([0.0, 0.0], ti.f64)  # the momentum given to the nodes (m_p dv but for empty nodes)
                for a, b in ti.static(ti.ndrange(3, 3)):
                    i, j = base[0] + a, base[1] + b
                    mi = gm[i, j]
                    if mi > 0.0:
                        gv[i, j] += (w[a][0] * w[b][1] * mp / mi) * dv
                        dp += ti.cast(w[a][0] * w[b][1] * mp, ti.f64) * ti.cast(dv, ti.f64)
                moment = ti.cast(r[0], ti.f64) * (-dp[1]) - ti.cast(r[1], ti.f64) * (-dp[0])
                j_point = ti.Vector([-dp[0], -dp[1], moment])
                scatter_add(impulse, 0, j_point, mode, scale)
                if r[0] > 0.0:
                    scatter_add(impulse, 1, j_point, mode, scale)

    return rigid_polygon_grid_point_contact


# projected Gauss-Seidel sweeps of the grid part of the contact at the points, under-relaxed (docs/mpm.md).
# The contact points outnumber the nodes they share, so no node velocities meet every point's constraint:
# full steps (relax 1) let the last point in the order win and left the footing's load rise 6.7 % at
# dt / 2 (10 cells across); the plain impulse m_p dv (no 1 / S_p) enforced too little per sweep and left
# the 30 RPM wheel at 5 mm cells moving +3.8 % in v per dt halving after 8 sweeps; relax 0.5 with 8 sweeps
# moves the wheel -0.2 % (v) and -1.0 % (sinkage), the footing 0.4-1.7 %
GRID_SWEEPS = 8
GRID_RELAX = 0.5

_GRID_POINT_CONTACT_KERNELS = {fixed: _make_grid_point_contact_kernel(fixed) for fixed in (False, True)}


@ti.kernel
def fold_impulse(step_sums: ti.types.ndarray(), impulse: ti.types.ndarray(), inv_scale: float):
    """impulse[q] += step_sums[q] / scale ; step_sums[q] = 0 (a step's exact fixed-point sums into
    the float64 totals, in a fixed order)."""
    for q in range(step_sums.shape[0]):
        impulse[q] += ti.cast(step_sums[q], ti.f64) * ti.cast(inv_scale, ti.f64)
        step_sums[q] = ti.Vector([0, 0, 0], ti.i64)


@ti.kernel
def set_pose(pose: ti.types.ndarray(), x: ti.f64, z: ti.f64, theta: ti.f64, vx: ti.f64, vz: ti.f64, omega: ti.f64):
    """pose = (x, z, theta, vx, vz, omega): a pose given by the host (prescribed motion)."""
    pose[0], pose[1], pose[2], pose[3], pose[4], pose[5] = x, z, theta, vx, vz, omega


POSE_FIELDS = ("x", "z", "theta", "vx", "vz", "omega")


@dataclass
class BodyPose:
    """Pose and rigid velocity handed to the contact kernel (world frame, SI)."""

    x: float
    z: float
    theta: float
    vx: float
    vz: float
    omega: float


class PolygonContact:
    """Coulomb contact between the grains and one rigid polygon.

    Parameters
    ----------
    vertices : (N, 2) body-frame polygon, m, counter-clockwise.
    mu : grain-body friction coefficient.
    band : contact band, m (``point_gap`` None: grid nodes with signed distance < band are projected).
    point_gap : m, or None: contact at the points, at the body's exact surface (points whose
        centre is closer than ``point_gap`` to it, see ``rigid_polygon_point_contact``; the default
        of ``MPMConfig.contact``), in place of the grid nodes' band.
    nodes : with ``point_gap``, the grid part is the projection of the grid nodes closer than
        ``band`` (0: inside the body; ``MPMConfig.contact`` "nodes") in place of the points' sweeps;
        the points' correction after G2P is the same.
    """

    def __init__(
        self,
        vertices: np.ndarray,
        mu: float,
        band: float,
        fixed_scale: float | None = None,
        point_gap: float | None = None,
        nodes: bool = False,
    ):
        from .backend import info

        verts = np.asarray(vertices, dtype=float)
        if verts.ndim != 2 or verts.shape[1] != 2 or len(verts) < 3:
            raise ValueError("vertices must be an (N>=3, 2) array")
        area2 = np.sum(verts[:, 0] * np.roll(verts[:, 1], -1) - np.roll(verts[:, 0], -1) * verts[:, 1])
        if area2 < 0:  # make it counter-clockwise so that edge normals point outward
            verts = verts[::-1].copy()
        self.vertices = verts
        self.mu = float(mu)
        self.band = float(band)
        self.point_gap = None if point_gap is None else float(point_gap)
        self.nodes = bool(nodes) and point_gap is not None
        # contact at the points: the points near the body (indices, their number) and the blocks of
        # points near its reference point
        self._cand = self._near = self._geo = None
        self._count = ti.ndarray(ti.i32, shape=1)
        self._count.fill(0)
        self.radius = float(np.max(np.linalg.norm(verts, axis=1)))
        self._verts = ti.Vector.ndarray(2, info().real, shape=len(verts))
        self._verts.from_numpy(verts.astype(info().np_real))
        # cumulative (Fx, Fz, My) dt on the body [0], and from the nodes ahead of it [1]
        # (3-vectors: one read back in ~6 us, to_numpy ~100 us; with the dynamics on the host each
        # step reads [0], on the device only the records do)
        self.impulse = ti.Vector.ndarray(3, ti.f64, shape=2)
        # (x, z, theta, vx, vz, omega) in float64: the pose the contact kernel reads (set by the host
        # each step, or advanced on the device by the body's dynamics: no read-back per step); zero, the
        # polygon as given and at rest, is a static obstacle's pose
        self.pose = ti.ndarray(ti.f64, shape=len(POSE_FIELDS))
        self.pose.fill(0.0)
        # fixed_scale: each step's node sums in 64-bit fixed point (exact in any order; a GPU), then
        # added to ``impulse`` by one serial kernel, so that runs do not depend on the threads' order
        self.fixed_scale = None if fixed_scale is None else float(fixed_scale)
        self.step_sums = None
        if self.fixed_scale is not None:
            self.step_sums = ti.Vector.ndarray(3, ti.i64, shape=2)
            self.step_sums.fill(0)

    def write_pose(self, pose: BodyPose) -> None:
        """Set the device pose (x, z, theta, vx, vz, omega) the contact kernel reads."""
        self.pose.from_numpy(np.array([getattr(pose, n) for n in POSE_FIELDS], np.float64))

    def read_pose(self) -> BodyPose:
        """The device pose (float64, as the contact kernel and the body's dynamics left it)."""
        return BodyPose(*(float(v) for v in self.pose.to_numpy()))

    def launches(
        self, grid: "Grid", dt: float, prefix: str, posed_by_host: bool = True, particles=None
    ) -> list[Launch]:
        """The contact kernel's launch (and, in fixed point, the fold of its sums into the totals).

        ``posed_by_host``: first set the device pose from the ``Var`` named ``prefix + name`` for
        each of :data:`POSE_FIELDS` (see :meth:`launch_values`); otherwise the pose stays what is
        on the device (a static obstacle's, or a body whose dynamics run there)."""
        fixed = self.fixed_scale is not None
        if self.point_gap is not None:  # contact located at the points: its grid part
            p = particles
            if self._cand is None or self._cand.shape[0] < p.n or self._near.shape[0] != p.blocks:
                free_ndarrays([self._geo])  # the former points' (a run whose points come and go)
                self._cand = ti.ndarray(ti.i32, shape=p.n)
                self._near = ti.ndarray(ti.i32, shape=p.blocks)
                self._geo = ti.Vector.ndarray(3, backend.info().real, shape=p.blocks * LANES)
            out = [Launch(set_pose, (self.pose, *(Var(prefix + n) for n in POSE_FIELDS)))] if posed_by_host else []
            out.append(
                Launch(
                    _GRID_POINT_CONTACT_KERNELS[fixed],
                    (
                        p.x,
                        p.mass,
                        p.n,
                        grid.m,
                        grid.v,
                        grid.h,
                        grid.pad,
                        self._verts,
                        len(self.vertices),
                        self.pose,
                        self.mu,
                        self.point_gap,
                        self.radius + self.point_gap + grid.h,
                        grid.h,
                        0 if self.nodes else GRID_SWEEPS,  # "nodes": the points listed, the grid left to the band
                        GRID_RELAX,
                        self._near,
                        self._geo,
                        self._cand,
                        self._count,
                        self.step_sums if fixed else self.impulse,
                        self.fixed_scale if fixed else 1.0,
                    ),
                )
            )
            if self.nodes:
                out.append(self._band_launch(grid, dt))
            if fixed:
                out.append(Launch(fold_impulse, (self.step_sums, self.impulse, 1.0 / self.fixed_scale)))
            return out
        out = [self._band_launch(grid, dt)]
        if posed_by_host:
            out.insert(0, Launch(set_pose, (self.pose, *(Var(prefix + n) for n in POSE_FIELDS))))
        if fixed:
            out.append(Launch(fold_impulse, (self.step_sums, self.impulse, 1.0 / self.fixed_scale)))
        return out

    def _band_launch(self, grid: "Grid", dt: float) -> Launch:
        """The projection of the grid nodes closer than ``band`` to the body (``rigid_polygon_contact``)."""
        fixed = self.fixed_scale is not None
        return Launch(
            _CONTACT_KERNELS[fixed],
            (
                grid.m,
                grid.v,
                self._verts,
                len(self.vertices),
                grid.h,
                grid.pad,
                self.pose,
                self.mu,
                self.band,
                self.radius + self.band,
                dt,
                self.step_sums if fixed else self.impulse,
                self.fixed_scale if fixed else 1.0,
            ),
        )

    def point_launches(self, particles, dt: float, lead: float) -> list[Launch]:
        """With ``point_gap``: the contact at the points, launched after G2P (and the fold of its
        fixed-point sums); ``lead``: how far in time the body is past the pose on the device (dt
        when the host posed it at the step's start, 0 when its dynamics advanced it there)."""
        if self.point_gap is None:
            return []
        fixed = self.fixed_scale is not None
        p = particles
        out = [
            Launch(
                _POINT_CONTACT_KERNELS[fixed],
                (
                    p.x,
                    p.v,
                    p.C,
                    p.mass,
                    p.n,
                    self._verts,
                    len(self.vertices),
                    self.pose,
                    lead,
                    self.mu,
                    self.point_gap,
                    dt,
                    self._cand,
                    self._count,
                    self.step_sums if fixed else self.impulse,
                    self.fixed_scale if fixed else 1.0,
                ),
            )
        ]
        if fixed:
            out.append(Launch(fold_impulse, (self.step_sums, self.impulse, 1.0 / self.fixed_scale)))
        return out

    @staticmethod
    def launch_values(pose: BodyPose, prefix: str) -> dict[str, float]:
        """This step's ``Var`` values of :meth:`launches` with ``posed_by_host``: the pose."""
        return {prefix + n: float(getattr(pose, n)) for n in POSE_FIELDS}

    def read_impulse(self) -> np.ndarray:
        """Cumulative impulse on the body (Jx, Jz per unit width N s/m; angular N s)."""
        return self._read(0)

    def read_impulse_ahead(self) -> np.ndarray:
        """The part of :meth:`read_impulse` from the nodes ahead of the body's reference point."""
        return self._read(1)

    def _read(self, i: int) -> np.ndarray:
        j = self.impulse[i]  # one element: ~6 us, against ~100 us for to_numpy
        return np.array([j[0], j[1], j[2]])

    def write_impulse(self, impulse, ahead=None) -> None:
        """Set the cumulative impulse and its part from ahead (restart from a checkpoint; a
        checkpoint from before the split has none: the part from ahead restarts from zero)."""
        total = np.asarray(impulse, np.float64).reshape(3)
        part = np.zeros(3) if ahead is None else np.asarray(ahead, np.float64).reshape(3)
        self.impulse.from_numpy(np.stack([total, part]))
        if self.step_sums is not None:
            self.step_sums.fill(0)
