"""Force models: the net force and moment of the granular medium on a rigid body.

One interface, several implementations. A force model answers ``wrench(state)``: the force
(N) and moment (N m, about the body reference point, counter-clockwise) on the body in a given
:class:`~intrusim.kinematics.BodyState`. RFT, inertial-only DRFT and full DRFT are one class,
:class:`ResistiveForceModel`, with different settings (see :func:`make_force_model`). The MPM
solver is a history-dependent force model: it evolves the medium itself and is driven through
the same bodies and scenarios (``intrusim.mpm``).

The fast path is a compiled (Numba) loop over the elements that needs no trigonometry per
element (cos 2 beta, sin 2 beta come from the normal, cos gamma, sin gamma from the velocity);
:func:`element_tractions` is the vectorised NumPy path built from the pure laws, used to check
it and to draw traction arrows.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Callable, Literal, Protocol

import numba
import numpy as np

from intrusim._checks import InputError, finite, non_negative
from intrusim._traction import alpha_constants, element_force, fit_rows
from intrusim.geometry import Shape, SurfaceElements
from intrusim.kinematics import BodyState, Wrench, element_motion
from intrusim.laws.bulldozing import bulldozing_scale, bulldozing_wrench
from intrusim.laws.drft import (
    MID_ANGLE_TIE,
    SPLIT_MODES,
    AffinePsi,
    FlatFreeSurface,
    FreeSurfaceModel,
    WheelRearHalf,
    circle_arc_mid,
    identity_psi,
    inertial_traction,
    zone_weight,
)  # fmt: skip
from intrusim.laws.rft import N_PER_CM3, as_table, rft_traction
from intrusim.params import GRAVITY

ModelKind = Literal["rft", "drft-inertial", "drft"]
Structural = Literal["none", "wheel-rear-half", "wheel-rear-half-effective", "wheel-rear-half-circle"]
STRUCTURAL_SPLITS = {"wheel-rear-half": "submerged", "wheel-rear-half-effective": "effective",
                     "wheel-rear-half-circle": "circle"}  # fmt: skip  # each wheel model's WheelRearHalf.split
STRUCTURAL_MODELS: tuple[str, ...] = ("none", *STRUCTURAL_SPLITS)


class ForceModel(Protocol):
    """Anything that gives the granular wrench on a body in a given state."""

    def wrench(self, state: BodyState) -> Wrench: ...


CHUNK = 16  # elements per culling chunk of the compiled kernel (consecutive elements of the outline)


def chunk_bounds(mid: np.ndarray, chunk: int = CHUNK) -> tuple[np.ndarray, np.ndarray]:
    """Bounding circles (centre (K, 2), radius (K,)) of consecutive runs of ``chunk`` elements.

    The kernel skips a whole run when its circle lies above every contact level, so a wheel
    pays the full per-element cost only for the ~1/4 of its outline that is submerged. The
    radius carries a small relative margin, so the culling never drops an element the
    per-element test would keep (it only saves work; results are unchanged).
    """
    n = mid.shape[0]
    k = (n + chunk - 1) // chunk
    pad = np.concatenate([mid, np.repeat(mid[-1:], k * chunk - n, axis=0)]).reshape(k, chunk, 2)  # repeats
    cen = 0.5 * (pad.min(axis=1) + pad.max(axis=1))
    r = np.sqrt(((pad - cen[:, None, :]) ** 2).sum(axis=2)).max(axis=1)
    rad = r * (1.0 + 1e-9) + 1e-12 * (1.0 + np.abs(pad).max(axis=(1, 2)))
    return cen, rad


@numba.njit(cache=True, inline="always")
def _pseudo_angle(y: float, x: float) -> float:
    """A strictly increasing function of atan2(y, x) on (-pi, pi], in (-2, 2], with no trigonometry.

    Same sign conventions as atan2 (signed zeros included), so p(y, x) < 0 exactly when
    atan2(y, x) < 0; comparing pseudo-angles orders directions like comparing angles.
    """
    d = abs(y) + abs(x)
    if d == 0.0:
        return np.arctan2(y, x) * (2.0 / np.pi)  # 0, -0, +-2 like atan2's +-0, +-pi
    r = y / d
    if x >= 0.0:
        return r
    if y > 0.0 or (y == 0.0 and np.copysign(1.0, y) > 0.0):
        return 2.0 - r
    return -2.0 - r


@numba.njit(cache=True, inline="always")
def _angle_of_pseudo(p: float) -> float:
    """atan2(y, x) of a direction from its pseudo-angle p = _pseudo_angle(y, x) (the inverse map)."""
    if p > 1.0:
        return np.arctan2(2.0 - p, 1.0 - p)
    if p < -1.0:
        return np.arctan2(-2.0 - p, 1.0 + p)
    return np.arctan2(p, 1.0 - abs(p))


@numba.njit(cache=True)
def zone_band(phi_mid: float, width: float) -> tuple[float, float, float]:
    """(p_mid, p_lo, p_hi): pseudo-angles of the zone boundary and of its band's ends (laws.drft.zone_weight);
    -inf for a boundary at or behind -pi (no split), and p_lo = p_hi = p_mid for width 0."""
    if not phi_mid > -np.pi:
        return -np.inf, -np.inf, -np.inf
    p_mid = _pseudo_angle(np.sin(phi_mid), np.cos(phi_mid))
    if width <= 0.0:
        return p_mid, p_mid, p_mid
    lo, hi = phi_mid - 0.5 * width, phi_mid + 0.5 * width
    p_lo = _pseudo_angle(np.sin(lo), np.cos(lo)) if lo > -np.pi else -np.inf
    p_hi = _pseudo_angle(np.sin(hi), np.cos(hi)) if hi < np.pi else np.inf
    return p_mid, p_lo, p_hi


@numba.njit(cache=True)
def _wrench_kernel(
    mid: np.ndarray,
    nrm: np.ndarray,
    area: np.ndarray,
    ccen: np.ndarray,
    crad: np.ndarray,
    x: float,
    z: float,
    theta: float,
    vx: float,
    vz: float,
    omega: float,
    surface_z: float,
    coef: np.ndarray,
    alpha_scale: float,
    lam_rho: float,
    fs_mode: int,
    dh: float,
    forward: float,
    arc_radius: float,
    zone_width: float,
) -> tuple[float, float, float]:
    """Sum of DRFT element forces t dA, t = alpha H(-z~)|z~| - n lam rho v_n^2 (Eq. 4), and moment.

    ``ccen``, ``crad``: bounding circles of runs of CHUNK consecutive elements (chunk_bounds).
    Angles of the contact arc (from straight down, + forward) are compared through a monotone
    pseudo-angle; atan2 is taken only for the two ends of the arc. ``fs_mode`` 3 (the "circle" split)
    takes the arc's ends on the circle of ``arc_radius`` (laws.drft.circle_arc_mid) instead. With
    ``zone_width`` > 0 the lowered surface rises across a band of that angular width (laws.drft.zone_weight).
    """
    c, s = np.cos(theta), np.sin(theta)
    n_el = mid.shape[0]
    n_ch = ccen.shape[0]
    # an element can touch only below this height (rear elements: below surface - dh)
    thr = surface_z
    if fs_mode >= 1 and dh < 0.0:
        thr = surface_z - dh
    # pass 1: elements that may touch (bounding-circle culling of whole chunks first), their
    # positions relative to the centre and, with a free-surface split, the contact arc
    idx = np.empty(n_el, np.int64)
    rel = np.empty((n_el, 3))  # rx, rz, pseudo-angle from straight down (+ forward)
    n_c = 0
    plo, phi_ = np.inf, -np.inf
    lo_y, lo_x, hi_y, hi_x = 0.0, 0.0, 0.0, 0.0
    any_sub = False
    for j in range(n_ch):
        if z + (s * ccen[j, 0] + c * ccen[j, 1]) - crad[j] >= thr:
            continue
        for i in range(j * CHUNK, min((j + 1) * CHUNK, n_el)):
            rz = s * mid[i, 0] + c * mid[i, 1]
            if z + rz >= thr:
                continue
            rx = c * mid[i, 0] - s * mid[i, 1]
            idx[n_c] = i
            rel[n_c, 0] = rx
            rel[n_c, 1] = rz
            if fs_mode >= 1:  # contact arc seen from the centre, angles from straight down, + forward
                py, px = forward * rx, -rz
                p = _pseudo_angle(py, px)
                rel[n_c, 2] = p
                # mode 1: below the undisturbed surface; mode 2: behind the lowest point, below z = -dh
                level = surface_z - dh if (fs_mode == 2 and p < 0.0) else surface_z
                if fs_mode <= 2 and z + rz < level:
                    any_sub = True
                    if p < plo:
                        plo, lo_y, lo_x = p, py, px
                    if p > phi_:
                        phi_, hi_y, hi_x = p, py, px
            n_c += 1
    phi_mid = -np.inf  # the mid-angle of the contact arc (-inf: no split; NaN for the circle out of contact)
    if fs_mode == 3:
        phi_mid = circle_arc_mid(z - surface_z, arc_radius, dh) - MID_ANGLE_TIE
    elif any_sub:
        phi_mid = 0.5 * (np.arctan2(lo_y, lo_x) + np.arctan2(hi_y, hi_x)) - MID_ANGLE_TIE
    _, p_lo, p_hi = zone_band(phi_mid, zone_width)  # pseudo-angles: behind p_lo all of dh, from p_hi none
    # pass 2: forces of the candidates, in element order
    kz, kx = fit_rows(alpha_constants(coef))
    fx = 0.0
    fz = 0.0
    mom = 0.0
    for q in range(n_c):
        i = idx[q]
        rx = rel[q, 0]
        rz = rel[q, 1]
        nx = c * nrm[i, 0] - s * nrm[i, 1]
        nz = s * nrm[i, 0] + c * nrm[i, 1]
        ux = vx - omega * rz
        uz = vz + omega * rx
        vn = nx * ux + nz * uz
        if vn <= 0.0:  # leading-edge rule
            continue
        depth = z + rz - surface_z
        if fs_mode >= 1:
            p = rel[q, 2]
            if p < p_lo:
                depth += dh
            elif p < p_hi:
                depth += dh * zone_weight(_angle_of_pseudo(p), phi_mid, zone_width)
        if depth >= 0.0:
            continue
        ex, ez = element_force(
            nx, nz, nz * nz - nx * nx, 2.0 * nx * nz, ux, uz, vn, depth, kz, kx, alpha_scale, lam_rho, area[i]
        )
        fx += ex
        fz += ez
        mom += rx * ez - rz * ex
    return fx, fz, mom


@dataclass(frozen=True)
class ResistiveForceModel:
    """RFT / DRFT force model of one rigid body (Eqs. 3-4).

    Attributes
    ----------
    elements : SurfaceElements of the body (body frame).
    xi : media scaling coefficient of the Li (2013) generic fit (poppy seeds 0.35).
    rho : media density for the inertial correction, kg/m^3 (the paper: rho_c = 638).
    lam : lambda of the inertial correction (0 = none).
    free_surface : structural-correction model (FlatFreeSurface = none).
    surface_z : height of the undisturbed free surface, m.
    coef : (4, 3, 2) RFT coefficient table ``[A, B, C, D][m + 1, n]`` in N/cm^3, scaled by xi
        (None: the generic Li 2013 fit; ``laws.rft.load_coefficients`` reads a measured one).
    bulldozing : N/m^2, resistance per squared depth of the body-level bulldozing term
        F_b = -bulldozing d^2 tanh(v_x / V_REG) (:mod:`intrusim.laws.bulldozing`; 0: none, the paper).
    radius : m, outer radius of the body: d = surface_z - (z - radius), the depth of its lowest point.
    """

    elements: SurfaceElements
    xi: float = 0.35
    rho: float = 638.0
    lam: float = 0.0
    free_surface: FreeSurfaceModel = field(default_factory=FlatFreeSurface)
    surface_z: float = 0.0
    coef: np.ndarray | None = field(default=None, compare=False)
    bulldozing: float = 0.0
    radius: float = 0.0

    def __post_init__(self) -> None:
        non_negative("xi", self.xi)
        non_negative("bulldozing", self.bulldozing)
        if non_negative("radius", self.radius) == 0.0 and self.bulldozing > 0.0:
            raise InputError("radius must be > 0 when the bulldozing term is on (it sets the depth d)")
        object.__setattr__(self, "_coef", np.ascontiguousarray(as_table(self.coef)))  # None: the generic table
        non_negative("rho", self.rho)
        non_negative("lambda", self.lam)
        finite("surface_z", self.surface_z)
        object.__setattr__(self, "_mid", np.ascontiguousarray(self.elements.midpoint))
        object.__setattr__(self, "_nrm", np.ascontiguousarray(self.elements.normal))
        object.__setattr__(self, "_area", np.ascontiguousarray(self.elements.area))
        cen, rad = chunk_bounds(self._mid)
        object.__setattr__(self, "_ccen", cen)
        object.__setattr__(self, "_crad", rad)
        fs = self.free_surface  # the compiled kernel's circle radius and zone band (0 for models without them)
        object.__setattr__(self, "_arc", (float(getattr(fs, "radius", 0.0)), float(getattr(fs, "zone_width", 0.0))))

    def wrench(self, state: BodyState) -> Wrench:
        """Force and moment on the body (compiled path)."""
        return Wrench(*self.wrench_tuple(state.x, state.z, state.theta, state.vx, state.vz, state.omega))

    def wrench_tuple(
        self, x: float, z: float, theta: float, vx: float, vz: float, omega: float
    ) -> tuple[float, float, float]:
        """(fx, fz, moment) for raw floats: the hot path of the integrators (no object creation)."""
        if hasattr(self.free_surface, "kernel_params"):
            mode, dh, fwd = self.free_surface.kernel_params(omega, vx)
        else:  # a user-supplied free-surface model without a compiled form
            return tuple(self.wrench_numpy(BodyState(x, z, theta, vx, vz, omega)).as_array())  # type: ignore[return-value]
        fx, fz, mom = _wrench_kernel(
            self._mid, self._nrm, self._area, self._ccen, self._crad, x, z, theta, vx, vz, omega, self.surface_z,
            self._coef, self.xi * N_PER_CM3, self.lam * self.rho, mode, dh, fwd,
            *self._arc,
        )  # fmt: skip
        if self.bulldozing > 0.0:
            bx, bm = bulldozing_wrench(self.bulldozing, self.radius, self.surface_z, z, vx)
            fx, mom = fx + bx, mom + bm
        return fx, fz, mom

    def compiled_spec(self) -> tuple | None:
        """Arguments of the compiled step loop (``intrusim._implicit_jit``), or None.

        (mid, nrm, area, ccen, crad, surface_z, coef, alpha_scale, lam_rho, fs_kind, fs_radius,
        fs_gravity, fs_slope, fs_offset, bulldozing, radius, zone_width): fs_kind 0 = flat free surface, 1 / 2 =
        :class:`WheelRearHalf` with the "submerged" / "effective" split (3: "circle") and psi(x) = offset + slope x
        (the paper's identity, or an :class:`AffinePsi`), whose drop dh = r psi(r omega^2 / g) the
        loop evaluates itself (``_traction.rear_surface_drop``, the same arithmetic as
        ``laws.drft.structural_depth_shift``). None for a free-surface model without a compiled
        form (a user-defined psi or model): the integrator then uses its Python loop and ``wrench_tuple``.
        """
        fs = self.free_surface
        if type(fs) is FlatFreeSurface:
            kind, r, g, slope, offset = 0, 1.0, 1.0, 1.0, 0.0
        elif type(fs) is WheelRearHalf and (fs.psi is identity_psi or type(fs.psi) is AffinePsi):
            kind, r, g = SPLIT_MODES[fs.split], float(fs.radius), float(fs.gravity)
            slope, offset = (1.0, 0.0) if fs.psi is identity_psi else (float(fs.psi.slope), float(fs.psi.offset))  # type: ignore[attr-defined]
        else:
            return None
        return (
            self._mid,
            self._nrm,
            self._area,
            self._ccen,
            self._crad,
            float(self.surface_z),
            self._coef,
            self.xi * N_PER_CM3,
            self.lam * self.rho,
            kind,
            r,
            g,
            slope,
            offset,
            float(self.bulldozing),
            float(self.radius),
            self._arc[1],
        )

    def element_tractions(self, state: BodyState) -> tuple[np.ndarray, np.ndarray]:
        """World positions (N, 2) and tractions t (N, 2, N/m^2) of every element (NumPy path)."""
        motion = element_motion(self.elements, state)
        centre = np.array([state.x, state.z])
        dh = self.free_surface.depth_shift(motion.position, centre, state.omega, state.vx, self.surface_z)
        depth = motion.position[:, 1] - self.surface_z + dh
        t = rft_traction(motion.normal, motion.velocity, depth, self.xi, self.coef)
        t += np.where((depth < 0)[:, None], inertial_traction(motion.normal, motion.velocity, self.rho, self.lam), 0.0)
        return motion.position, t

    def largest_element_force(self, x: float, z: float, theta: float, vx: float, vz: float, omega: float) -> float:
        """The largest force magnitude of one element, N (NumPy path): how far the force jumps at most
        where one element switches on or off, the resolution the integrator accepts a step's imbalance to."""
        _, t = self.element_tractions(BodyState(x, z, theta, vx, vz, omega))
        f = t * self.elements.area[:, None]
        return float(np.max(np.hypot(f[:, 0], f[:, 1]), initial=0.0))

    def wrench_numpy(self, state: BodyState) -> Wrench:
        """Force and moment from the vectorised NumPy path (reference for the compiled one)."""
        motion = element_motion(self.elements, state)
        _, t = self.element_tractions(state)
        f = t * self.elements.area[:, None]
        moment = float(np.sum(motion.offset[:, 0] * f[:, 1] - motion.offset[:, 1] * f[:, 0]))
        fx = float(f[:, 0].sum())
        if self.bulldozing > 0.0:
            bx, bm = bulldozing_wrench(self.bulldozing, self.radius, self.surface_z, state.z, state.vx)
            fx, moment = fx + bx, moment + bm
        return Wrench(fx, float(f[:, 1].sum()), moment)


def make_force_model(
    kind: ModelKind,
    shape: Shape,
    *,
    xi: float = 0.35,
    rho: float = 638.0,
    lam: float = 1.0,
    structural: Structural = "none",
    surface_z: float = 0.0,
    elements: SurfaceElements | None = None,
    psi: Callable[[float], float] = identity_psi,
    coef: np.ndarray | None = None,
    bulldozing: float = 0.0,
    mu: float = 0.56,
    gravity: float = GRAVITY,
    zone_width: float = 0.0,
) -> ResistiveForceModel:
    """Build one of the paper's force models for ``shape``.

    kind
        ``"rft"``: quasistatic RFT (Eq. 3), lambda and structural correction ignored.
        ``"drft-inertial"``: RFT + lambda rho v_n^2 only (Fig 4B, Fig 5 dashed).
        ``"drft"``: RFT + inertial + structural correction (Eq. 4); ``structural`` selects
        the free-surface model (``"wheel-rear-half"`` for wheels, ``"none"`` for plates/runners;
        ``"wheel-rear-half-effective"``: the contact arc ends at the lowered rear surface;
        ``"wheel-rear-half-circle"``: the same, the arc's ends taken on the wheel's outer circle, see
        :class:`~intrusim.laws.drft.WheelRearHalf`).
    zone_width
        rad, the band across which the wheel's lowered rear surface rises (``WheelRearHalf.zone_width``;
        0: the paper's sharp split).
    psi
        free-surface law of the wheel structural correction, dh = r psi(r omega^2 / g) (paper:
        the identity; :func:`~intrusim.laws.drft.free_surface_law` builds a fitted affine one).
    coef
        RFT coefficient table (N/cm^3, scaled by xi); None: the generic Li (2013) fit.
    bulldozing, mu, gravity
        k_b of the body-level bulldozing resistance k_b (1/2) K_p(mu) rho g W d^2, d the depth of
        the shape's outer circle (``shape.radius``), W the elements' width
        (:mod:`intrusim.laws.bulldozing`; not in the paper, 0 = none). Added to every kind.
    """
    els = shape.elements if elements is None else elements
    bull = dict(bulldozing=bulldozing_scale(bulldozing, mu, rho, gravity, els.width), radius=float(shape.radius))
    if kind == "rft":
        return ResistiveForceModel(els, xi=xi, rho=rho, lam=0.0, surface_z=surface_z, coef=coef, **bull)
    if kind == "drft-inertial":
        return ResistiveForceModel(els, xi=xi, rho=rho, lam=lam, surface_z=surface_z, coef=coef, **bull)
    if kind == "drft":
        if structural not in STRUCTURAL_MODELS:
            raise InputError(f"structural must be one of {STRUCTURAL_MODELS}, got {structural!r}")
        fs: FreeSurfaceModel = FlatFreeSurface()
        if structural in STRUCTURAL_SPLITS:
            fs = WheelRearHalf(shape.radius, psi=psi, split=STRUCTURAL_SPLITS[structural], zone_width=zone_width)
        return ResistiveForceModel(
            els, xi=xi, rho=rho, lam=lam, free_surface=fs, surface_z=surface_z, coef=coef, **bull
        )
    raise InputError(f"force model kind must be 'rft', 'drft-inertial' or 'drft', got {kind!r}")
