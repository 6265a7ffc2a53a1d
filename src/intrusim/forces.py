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
from typing import Literal, Protocol

import numba
import numpy as np

from intrusim._checks import InputError, finite, non_negative
from intrusim.geometry import Shape, SurfaceElements
from intrusim.kinematics import BodyState, Wrench, element_motion
from intrusim.laws.drft import MID_ANGLE_TIE, FlatFreeSurface, FreeSurfaceModel, WheelRearHalf, inertial_traction
from intrusim.laws.rft import A_COEF, B_COEF, C_COEF, D_COEF, N_PER_CM3, rft_traction

ModelKind = Literal["rft", "drft-inertial", "drft"]
Structural = Literal["none", "wheel-rear-half", "wheel-rear-half-effective"]
STRUCTURAL_MODELS: tuple[str, ...] = ("none", "wheel-rear-half", "wheel-rear-half-effective")


class ForceModel(Protocol):
    """Anything that gives the granular wrench on a body in a given state."""

    def wrench(self, state: BodyState) -> Wrench:
        ...


@numba.njit(cache=True)
def _alpha_unit(c2b: float, s2b: float, cg: float, sg: float, coef: np.ndarray) -> tuple[float, float]:
    """alpha_x, alpha_z of the Li (2013) fit from cos/sin of 2 beta and gamma (fitted range).

    coef[k, m + 1, n] holds A, B, C, D; the fit is a sum over m in {-1, 0, 1}, n in {0, 1} of
    cos/sin(2 m beta + n gamma), expanded with the angle-addition formulas.
    """
    az = 0.0
    ax = 0.0
    for mi in range(3):
        m = mi - 1
        cm, sm = (c2b, m * s2b) if m != 0 else (1.0, 0.0)  # cos/sin(2 m beta), m = +-1 or 0
        for n in range(2):
            if n == 0:
                ca, sa = cm, sm
            else:
                ca, sa = cm * cg - sm * sg, sm * cg + cm * sg
            az += coef[0, mi, n] * ca + coef[1, mi, n] * sa
            ax += coef[2, mi, n] * ca + coef[3, mi, n] * sa
    return ax, az


@numba.njit(cache=True)
def _wrench_kernel(
    mid: np.ndarray,
    nrm: np.ndarray,
    area: np.ndarray,
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
) -> tuple[float, float, float]:
    """Sum of DRFT element forces t dA, t = alpha H(-z~)|z~| - n lam rho v_n^2 (Eq. 4), and moment."""
    c, s = np.cos(theta), np.sin(theta)
    n_el = mid.shape[0]
    phi_mid = 0.0
    if fs_mode >= 1:  # contact arc seen from the centre, angles from straight down, + forward
        lo, hi, any_sub = 1e300, -1e300, False
        for i in range(n_el):
            rx = c * mid[i, 0] - s * mid[i, 1]
            rz = s * mid[i, 0] + c * mid[i, 1]
            phi = np.arctan2(forward * rx, -rz)
            # mode 1: below the undisturbed surface; mode 2: behind the lowest point, below z = -dh
            level = surface_z - dh if (fs_mode == 2 and phi < 0.0) else surface_z
            if z + rz < level:
                lo, hi, any_sub = min(lo, phi), max(hi, phi), True
        phi_mid = 0.5 * (lo + hi) - MID_ANGLE_TIE if any_sub else -1e300
    fx = 0.0
    fz = 0.0
    mom = 0.0
    for i in range(n_el):
        rx = c * mid[i, 0] - s * mid[i, 1]
        rz = s * mid[i, 0] + c * mid[i, 1]
        nx = c * nrm[i, 0] - s * nrm[i, 1]
        nz = s * nrm[i, 0] + c * nrm[i, 1]
        ux = vx - omega * rz
        uz = vz + omega * rx
        vn = nx * ux + nz * uz
        if vn <= 0.0:  # leading-edge rule
            continue
        depth = z + rz - surface_z
        if fs_mode >= 1 and np.arctan2(forward * rx, -rz) < phi_mid:
            depth += dh
        if depth >= 0.0:
            continue
        speed = np.sqrt(ux * ux + uz * uz)
        c2b = nz * nz - nx * nx
        s2b = 2.0 * nx * nz
        sg = -uz / speed
        if ux > 0.0:  # mirror x -> -x into the fitted range
            ax, az = _alpha_unit(c2b, -s2b, ux / speed, sg, coef)
            ax = -ax
        else:
            ax, az = _alpha_unit(c2b, s2b, -ux / speed, sg, coef)
        dA = area[i]
        ex = (alpha_scale * ax * (-depth) - nx * lam_rho * vn * vn) * dA
        ez = (alpha_scale * az * (-depth) - nz * lam_rho * vn * vn) * dA
        fx += ex
        fz += ez
        mom += rx * ez - rz * ex
    return fx, fz, mom


_COEF = np.ascontiguousarray(np.stack([A_COEF, B_COEF, C_COEF, D_COEF]))


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
    """

    elements: SurfaceElements
    xi: float = 0.35
    rho: float = 638.0
    lam: float = 0.0
    free_surface: FreeSurfaceModel = field(default_factory=FlatFreeSurface)
    surface_z: float = 0.0

    def __post_init__(self) -> None:
        non_negative("xi", self.xi)
        non_negative("rho", self.rho)
        non_negative("lambda", self.lam)
        finite("surface_z", self.surface_z)
        object.__setattr__(self, "_mid", np.ascontiguousarray(self.elements.midpoint))
        object.__setattr__(self, "_nrm", np.ascontiguousarray(self.elements.normal))
        object.__setattr__(self, "_area", np.ascontiguousarray(self.elements.area))

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
        return _wrench_kernel(
            self._mid, self._nrm, self._area, x, z, theta, vx, vz, omega, self.surface_z,
            _COEF, self.xi * N_PER_CM3, self.lam * self.rho, mode, dh, fwd,
        )  # fmt: skip

    def element_tractions(self, state: BodyState) -> tuple[np.ndarray, np.ndarray]:
        """World positions (N, 2) and tractions t (N, 2, N/m^2) of every element (NumPy path)."""
        motion = element_motion(self.elements, state)
        centre = np.array([state.x, state.z])
        dh = self.free_surface.depth_shift(motion.position, centre, state.omega, state.vx, self.surface_z)
        depth = motion.position[:, 1] - self.surface_z + dh
        t = rft_traction(motion.normal, motion.velocity, depth, self.xi)
        t += np.where((depth < 0)[:, None], inertial_traction(motion.normal, motion.velocity, self.rho, self.lam), 0.0)
        return motion.position, t

    def wrench_numpy(self, state: BodyState) -> Wrench:
        """Force and moment from the vectorised NumPy path (reference for the compiled one)."""
        motion = element_motion(self.elements, state)
        _, t = self.element_tractions(state)
        f = t * self.elements.area[:, None]
        moment = float(np.sum(motion.offset[:, 0] * f[:, 1] - motion.offset[:, 1] * f[:, 0]))
        return Wrench(float(f[:, 0].sum()), float(f[:, 1].sum()), moment)


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
) -> ResistiveForceModel:
    """Build one of the paper's force models for ``shape``.

    kind
        ``"rft"``: quasistatic RFT (Eq. 3), lambda and structural correction ignored.
        ``"drft-inertial"``: RFT + lambda rho v_n^2 only (Fig 4B, Fig 5 dashed).
        ``"drft"``: RFT + inertial + structural correction (Eq. 4); ``structural`` selects
        the free-surface model (``"wheel-rear-half"`` for wheels, ``"none"`` for plates/runners;
        ``"wheel-rear-half-effective"``: the contact arc ends at the lowered rear surface, see
        :class:`~intrusim.laws.drft.WheelRearHalf`).
    """
    els = shape.elements if elements is None else elements
    if kind == "rft":
        return ResistiveForceModel(els, xi=xi, rho=rho, lam=0.0, surface_z=surface_z)
    if kind == "drft-inertial":
        return ResistiveForceModel(els, xi=xi, rho=rho, lam=lam, surface_z=surface_z)
    if kind == "drft":
        if structural not in STRUCTURAL_MODELS:
            raise InputError(f"structural must be one of {STRUCTURAL_MODELS}, got {structural!r}")
        fs: FreeSurfaceModel = FlatFreeSurface()
        if structural == "wheel-rear-half":
            fs = WheelRearHalf(shape.radius)
        elif structural == "wheel-rear-half-effective":
            fs = WheelRearHalf(shape.radius, split="effective")
        return ResistiveForceModel(els, xi=xi, rho=rho, lam=lam, free_surface=fs, surface_z=surface_z)
    raise InputError(f"force model kind must be 'rft', 'drft-inertial' or 'drft', got {kind!r}")
