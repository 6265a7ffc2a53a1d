"""Dynamic RFT (paper Eq. 4): the inertial and structural corrections to quasistatic RFT.

    t = alpha(beta, gamma) H(-z~) |z~|  -  n lambda rho v_n^2,      z~ = z + dh

* dynamic inertial correction: -n lambda rho v_n^2 on leading elements (n . v > 0);
* dynamic structural correction: the free surface seen by an element is lowered by dh.
  For a driven wheel (paper, Fig 5C) dh = r psi(r omega^2 / g) with psi the identity, on the
  elements in the REAR half of the wheel-sand contact arc (split by the angle subtended at the
  wheel centre); dh = 0 in front. Calibrated on MPM, psi may be affine:
  psi(x) = a + c x (:class:`AffinePsi`, :mod:`intrusim.analysis.calibration`).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable, Protocol

import numba
import numpy as np

from intrusim._checks import InputError, finite, non_negative, positive
from intrusim.params import GRAVITY


def inertial_traction(normal: np.ndarray, velocity: np.ndarray, rho: float, lam: float) -> np.ndarray:
    """Dynamic inertial correction -n lambda rho v_n^2 (Eq. 4), N/m^2, zero on trailing elements.

    Parameters
    ----------
    normal : (N, 2) outward unit normals.
    velocity : (N, 2) element velocities, m/s.
    rho : media density, kg/m^3 (the paper uses rho_c = 638 for poppy seeds).
    lam : O(1) fitting constant lambda.
    """
    rho = non_negative("rho", rho)
    lam = non_negative("lambda", lam)
    n = np.asarray(normal, float)
    vn = np.einsum("ij,ij->i", n, np.asarray(velocity, float))
    mag = np.where(vn > 0.0, lam * rho * vn * vn, 0.0)
    return -n * mag[:, None]


def identity_psi(x: float) -> float:
    """The paper's free-surface law psi(x) = x (Fig 5C)."""
    return x


@dataclass(frozen=True)
class AffinePsi:
    """Free-surface law psi(x) = offset + slope x, dimensionless (x = r omega^2 / g).

    The paper's law is the identity (offset 0, slope 1); fitted to our MPM rear-surface drop
    (Fig 5C) it is ~0.5 x, or ~0.12 + 0.34 x (docs/results.md).
    """

    slope: float = 1.0
    offset: float = 0.0

    def __post_init__(self) -> None:
        non_negative("psi slope", self.slope)
        finite("psi offset", self.offset)

    def __call__(self, x: float) -> float:
        return self.offset + self.slope * x


def free_surface_law(slope: float = 1.0, offset: float = 0.0) -> Callable[[float], float]:
    """psi(x) = offset + slope x; the paper's :func:`identity_psi` itself for (1, 0)."""
    if slope == 1.0 and offset == 0.0:
        return identity_psi
    return AffinePsi(slope, offset)


def structural_depth_shift(
    radius: float, omega: float, gravity: float = GRAVITY, psi: Callable[[float], float] = identity_psi
) -> float:
    """Rear free-surface drop dh = r psi(r omega^2 / g) of a driven wheel (Fig 5C), m.

    Parameters
    ----------
    radius : wheel radius r, m (the paper's nominal radius; 0.106 m for the Table S1 wheel).
    omega : angular velocity, rad/s (its sign does not matter).
    gravity : g, m/s^2.
    psi : the dimensionless free-surface law; the paper finds the identity.
    """
    r = positive("radius", radius)
    w = finite("omega", omega)
    g = positive("gravity", gravity)
    return r * float(psi(r * w * w / g))


def travel_sign(omega: float, vx: float) -> float:
    """+1 if the body rolls/moves towards +x, -1 towards -x (omega is counter-clockwise)."""
    if omega != 0.0:
        return -1.0 if omega > 0.0 else 1.0
    return -1.0 if vx < 0.0 else 1.0


MID_ANGLE_TIE = 1e-9  # rad: an element this close to the mid-angle counts as front


def contact_angle(position: np.ndarray, centre: np.ndarray, forward: float) -> np.ndarray:
    """Angle of each element seen from the wheel centre, from straight down, positive forward (rad)."""
    rel = np.asarray(position, float) - np.asarray(centre, float)
    return np.arctan2(forward * rel[:, 0], -rel[:, 1])


def rear_half_mask(position: np.ndarray, centre: np.ndarray, submerged: np.ndarray, forward: float) -> np.ndarray:
    """Elements behind the mid-angle of the contact arc, seen from the wheel centre.

    The contact arc is spanned by the ``submerged`` elements; angles are measured at the
    centre from straight down, positive towards the travel direction ``forward`` (+-1).
    Returns a boolean mask (all False when nothing is submerged).
    """
    phi = contact_angle(position, centre, forward)
    return phi < arc_mid_angle(phi, submerged)  # False everywhere for NaN


def arc_mid_angle(phi: np.ndarray, contact: np.ndarray) -> float:
    """The mid-angle of the arc spanned by the ``contact`` elements at angles ``phi`` (rad), less
    MID_ANGLE_TIE (evenly spaced elements can sit exactly on it); NaN when none is in contact."""
    if not np.any(contact):
        return float("nan")
    return 0.5 * float(phi[contact].min() + phi[contact].max()) - MID_ANGLE_TIE


@numba.njit(cache=True)
def circle_arc_mid(height: float, radius: float, dh: float) -> float:
    """Mid-angle (rad, from straight down, + forward) of the contact arc of a circle of ``radius`` whose
    centre is ``height`` above the undisturbed surface: from where it meets the lowered rear surface
    z = -dh behind (straight down if it does not reach it) to where it meets z = 0 in front; NaN when
    the circle does not reach the surface. Continuous in the height, unlike the ends of the submerged
    elements, which jump as a lug tip enters or leaves a level."""
    if not height < radius:
        return np.nan
    front = np.arccos(max(height / radius, -1.0))
    u = (height + dh) / radius
    rear = -np.arccos(max(u, -1.0)) if u < 1.0 else 0.0
    return 0.5 * (front + rear)


@numba.njit(cache=True)
def zone_weight(phi: float, mid: float, width: float) -> float:
    """Share of dh an element at angle ``phi`` sees (rad, from straight down, + forward): 1 behind the
    zone boundary ``mid``, 0 in front of it; with ``width`` > 0 the lowered surface rises linearly
    across the band of that angular width centred on ``mid`` (width 0: the paper's sharp split)."""
    if width <= 0.0:
        return 1.0 if phi < mid else 0.0
    return min(1.0, max(0.0, 0.5 - (phi - mid) / width))


class FreeSurfaceModel(Protocol):
    """Effective free-surface drop dh for each element (the structural correction)."""

    def depth_shift(
        self, position: np.ndarray, centre: np.ndarray, omega: float, vx: float, surface_z: float
    ) -> np.ndarray:
        """dh (m, >= 0) for elements at world ``position`` (N, 2) of a body centred at ``centre``."""
        ...


@dataclass(frozen=True)
class FlatFreeSurface:
    """No structural correction: dh = 0 everywhere (quasistatic RFT, plates, runners)."""

    def depth_shift(self, position, centre, omega, vx, surface_z):  # noqa: D102
        return np.zeros(len(position))

    def kernel_params(self, omega: float, vx: float) -> tuple[int, float, float]:
        """(mode, dh, forward sign) for the compiled force kernel: mode 0 = flat."""
        return 0, 0.0, 1.0


SPLIT_MODES = {"submerged": 1, "effective": 2, "circle": 3}  # the compiled kernel's mode of each split
SPLITS = tuple(SPLIT_MODES)


@dataclass(frozen=True)
class WheelRearHalf:
    """The paper's wheel model: dh = r psi(r omega^2 / g) on the rear half of the contact arc.

    The paper splits "the contact area between sand and wheel" in two equal halves by the angle
    it subtends at the wheel centre, without saying where the contact ends at the rear. Three
    readings, selected by ``split``:

    * ``"submerged"`` (default, the literal reading): the arc spans every element below the
      undisturbed surface z = 0, front and rear;
    * ``"effective"``: the arc ends at the rear where the wheel meets the LOWERED rear surface
      z = -dh (elements behind the lowest point count only if below -dh), so the split moves
      forward as dh grows. This reading makes the correction much stronger (docs/rft.md);
    * ``"circle"``: the effective reading with the arc's ends taken on the wheel's outer circle of
      ``radius`` (:func:`circle_arc_mid`) rather than at the extreme submerged elements: its
      mid-angle moves continuously with the wheel's height, where the elements' ends jump each
      time a lug tip crosses a level (the default step's error, docs/locomotion.md).

    Attributes
    ----------
    radius : r, m (nominal wheel radius).
    gravity : g, m/s^2.
    psi : dimensionless law, identity by default.
    split : "submerged", "effective" or "circle".
    zone_width : rad, the angular width of the band across which the lowered surface rises from
        -dh behind the mid-angle to 0 in front of it (:func:`zone_weight`); 0: the paper's sharp
        split, where each element that crosses the mid-angle sees dh appear at once. Not in the paper.
    """

    radius: float
    gravity: float = GRAVITY
    psi: Callable[[float], float] = identity_psi
    split: str = "submerged"
    zone_width: float = 0.0

    def __post_init__(self) -> None:
        positive("radius", self.radius)
        non_negative("zone_width", self.zone_width)
        positive("gravity", self.gravity)
        if self.split not in SPLITS:
            raise InputError(f"split must be one of {SPLITS}, got {self.split!r}")

    def drop(self, omega: float) -> float:
        return structural_depth_shift(self.radius, omega, self.gravity, self.psi)

    def depth_shift(self, position, centre, omega, vx, surface_z):  # noqa: D102
        fwd = travel_sign(omega, vx)
        dh = self.drop(omega)
        depth = np.asarray(position)[:, 1] - surface_z
        phi = contact_angle(position, centre, fwd)
        if self.split == "circle":
            mid = circle_arc_mid(float(centre[1]) - surface_z, self.radius, dh) - MID_ANGLE_TIE
        elif self.split == "effective":
            mid = arc_mid_angle(phi, np.where(phi < 0.0, depth + dh < 0.0, depth < 0.0))
        else:
            mid = arc_mid_angle(phi, depth < 0.0)
        if not np.isfinite(mid):
            return np.zeros(len(depth))
        if self.zone_width > 0.0:  # zone_weight, vectorised
            return dh * np.clip(0.5 - (phi - mid) / self.zone_width, 0.0, 1.0)
        return np.where(phi < mid, dh, 0.0)

    def kernel_params(self, omega: float, vx: float) -> tuple[int, float, float]:
        """(mode, dh, forward sign) for the compiled force kernel: mode 1 = submerged split, 2 = effective, 3 = circle."""
        return SPLIT_MODES[self.split], self.drop(omega), travel_sign(omega, vx)
