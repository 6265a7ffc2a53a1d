"""Free-surface measurements on MPM particle data (paper Fig 5C).

The paper measures the structural correction as the drop dh of the rear free surface: "the
lowest point making rear contact with the wheel for which hydrostatic pressure -> 0". Going down
the rear of the wheel from the top, the contact material is first pressure-free (ejected or
surface grains), then pressurised. We take the particles within a contact band of the wheel
outline, behind the wheel centre (relative to the travel direction), and locate that transition
as the highest contact particle whose pressure exceeds a small tolerance: dh is how far it lies
below the undisturbed surface. Pressure-free material lower down (the loosened wake under the
wheel) is thereby not mistaken for the free surface.
"""

from __future__ import annotations

import numpy as np

from intrusim._checks import InputError, finite, finite_array, positive


def polygon_signed_distance(points: np.ndarray, polygon: np.ndarray) -> np.ndarray:
    """Signed distance (m) from ``points`` (N, 2) to a closed ``polygon`` (M, 2): < 0 inside."""
    p = np.asarray(points, float)[:, None, :]
    a = np.asarray(polygon, float)[None, :, :]
    b = np.roll(a, -1, axis=1)
    ab = b - a
    t = np.clip(np.einsum("nmk,nmk->nm", p - a, ab) / np.einsum("nmk,nmk->nm", ab, ab), 0.0, 1.0)
    d = np.min(np.linalg.norm(p - (a + t[..., None] * ab), axis=2), axis=1)
    # even-odd rule for inside
    ya, yb = a[..., 1], b[..., 1]
    crosses = (ya > p[..., 1]) != (yb > p[..., 1])
    x_cross = a[..., 0] + (p[..., 1] - ya) * ab[..., 0] / np.where(yb - ya == 0, 1.0, yb - ya)
    inside = np.count_nonzero(crosses & (p[..., 0] < x_cross), axis=1) % 2 == 1
    return np.where(inside, -d, d)


def rear_contact_indices(
    positions: np.ndarray, polygon_world: np.ndarray, centre: tuple[float, float], forward: float, band: float
) -> np.ndarray:
    """Indices of the particles within ``band`` (m) of the outline and behind the centre (relative
    to the travel direction ``forward`` = +1 or -1): the wheel's rear contact."""
    cx, cz = centre
    # only particles inside the wheel's bounding circle plus the band can touch it
    reach = np.max(np.linalg.norm(np.asarray(polygon_world) - [cx, cz], axis=1)) + band
    near = np.hypot(positions[:, 0] - cx, positions[:, 1] - cz) < reach
    near &= forward * (positions[:, 0] - cx) < 0.0  # rear half-plane
    idx = np.flatnonzero(near)
    if len(idx) == 0:
        return idx
    return idx[polygon_signed_distance(positions[idx], polygon_world) < band]


def rear_contact_drop(
    positions: np.ndarray,
    pressure: np.ndarray,
    polygon_world: np.ndarray,
    centre: tuple[float, float],
    forward: float,
    surface_z: float,
    band: float,
    pressure_tol: float,
    below_surface_only: bool = False,
    rule: str = "highest_loaded",
) -> float:
    """Drop dh (m) of the rear free surface where it meets the wheel; NaN if no loaded rear contact.

    Parameters
    ----------
    positions : (N, 2) particle positions, m.
    pressure : (N,) particle pressure P = -tr(sigma)/3, Pa.
    polygon_world : (M, 2) wheel outline in the world frame, m.
    centre : wheel centre (x, z), m.
    forward : +1 if the wheel travels towards +x, -1 otherwise.
    surface_z : undisturbed free-surface height, m.
    band : particles closer than this to the outline are in contact, m (about one grid cell).
    pressure_tol : pressure above which a contact particle counts as loaded, Pa (about
        rho g h / 2 for grid spacing h).
    below_surface_only : count only contact particles below ``surface_z`` (grains carried up
        the wheel's rear, loaded by their own weight, would otherwise give dh < 0).
    rule : "highest_loaded" (the measurement used: the highest rear contact particle whose
        pressure exceeds ``pressure_tol``) or "lowest_free" (the paper's words read literally: the
        lowest rear contact particle whose pressure is at most ``pressure_tol``; this also finds the
        loosened, pressure-free wake under the wheel).
    """
    if rule not in ("highest_loaded", "lowest_free"):
        raise InputError(f"rule must be 'highest_loaded' or 'lowest_free', got {rule!r}")
    pos = finite_array("positions", positions, (2,))
    p = finite_array("pressure", pressure)
    if len(p) != len(pos):
        raise InputError("positions and pressure must have the same length")
    band = positive("band", band)
    tol = positive("pressure_tol", pressure_tol)
    finite("centre x", centre[0])
    finite("centre z", centre[1])
    if forward not in (1.0, -1.0, 1, -1):
        raise InputError(f"forward must be +1 or -1, got {forward!r}")
    idx = rear_contact_indices(pos, polygon_world, centre, forward, band)
    if below_surface_only:
        idx = idx[pos[idx, 1] < surface_z]
    if rule == "lowest_free":
        free = idx[p[idx] <= tol]
        return float(surface_z - pos[free, 1].min()) if len(free) else float("nan")
    loaded = idx[p[idx] > tol]
    if len(loaded) == 0:  # nothing behind the wheel pushes back: no rear free surface to measure
        return float("nan")
    return float(surface_z - pos[loaded, 1].max())


def wake_drop(
    positions: np.ndarray, rear_x: float, forward: float, surface_z: float, width: tuple[float, float]
) -> float:
    """Depth (m) below ``surface_z`` of the top of the grains in the strip ``width`` = (near, far)
    metres behind ``rear_x`` (the wheel's rearmost extent); negative for a ridge; NaN if empty."""
    pos = finite_array("positions", positions, (2,))
    behind = forward * (finite("rear_x", rear_x) - pos[:, 0])
    near, far = width
    if not 0.0 <= near < far:
        raise InputError(f"width must be (near, far) with 0 <= near < far, got {width!r}")
    strip = (behind > near) & (behind < far)
    return float(surface_z - pos[strip, 1].max()) if strip.any() else float("nan")
