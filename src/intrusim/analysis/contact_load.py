"""Where an MPM wheel bears on the grains: the load around its rim and the arc that carries it.

DRFT's structural correction (:mod:`intrusim.laws.drft`) lowers the surface that the rear half of
the wheel's contact arc bears on, by dh = r psi(r omega^2 / g). The MPM shows that arc directly:
the grains' pressure next to the wheel, summed by the angle seen from the wheel centre
(:func:`angular_load`), is the wheel's load around its rim. The loaded arc's ends are quantiles
of that distribution (:func:`loaded_arc`): the angles with a fraction ``q`` of the load behind
them and ``q`` in front of them. The rear end is where the wheel stops bearing on the grains; the
wheel's outer circle meets the surface it bears on there, z = -dh_b below the undisturbed surface,
dh_b = r cos(phi_rear) - h, h the centre's height above the undisturbed surface
(:func:`bearing_drop`). dh_b / r is the psi of the "circle" split (``WheelRearHalf``) measured,
where the paper's dh (Fig 5C, :mod:`intrusim.analysis.free_surface`) is the drop of the free
surface behind the wheel.

Angles are measured at the centre from straight down, positive towards the travel direction
(as ``laws.drft.contact_angle``), in radians.
"""

from __future__ import annotations

import numpy as np

from intrusim._checks import InputError, finite, finite_array, positive


def angular_load(
    positions: np.ndarray, pressure: np.ndarray, centre: tuple[float, float], forward: float, radius: float,
    shell: float, bins: int = 72,
) -> tuple[np.ndarray, np.ndarray]:  # fmt: skip
    """The grains' pressure within ``radius + shell`` of the wheel centre, summed by angle.

    Returns (bin-centre angles (bins,), rad, in (-pi, pi); the summed pressure of each bin, Pa;
    per equal-volume particle, a load up to the particle volume). Grains pulled (pressure < 0:
    none in a tension-free medium) count as 0.
    """
    pos = finite_array("positions", positions, (2,))
    p = finite_array("pressure", pressure)
    if len(p) != len(pos):
        raise InputError("positions and pressure must have the same length")
    if forward not in (1.0, -1.0, 1, -1):
        raise InputError(f"forward must be +1 or -1, got {forward!r}")
    reach = positive("radius", radius) + positive("shell", shell)
    if int(bins) < 4:
        raise InputError(f"bins must be >= 4, got {bins!r}")
    rel = pos - [finite("centre x", centre[0]), finite("centre z", centre[1])]
    near = np.hypot(rel[:, 0], rel[:, 1]) < reach
    phi = np.arctan2(forward * rel[near, 0], -rel[near, 1])
    edges = np.linspace(-np.pi, np.pi, int(bins) + 1)
    load, _ = np.histogram(phi, bins=edges, weights=np.maximum(p[near], 0.0))
    return 0.5 * (edges[1:] + edges[:-1]), load


def loaded_arc(angles: np.ndarray, load: np.ndarray, fraction: float = 0.05) -> tuple[float, float]:
    """(rear end, front end) of the loaded arc, rad: the angles with ``fraction`` of the load behind
    them and ``fraction`` in front of them (the load spread evenly across each bin); NaNs without load."""
    a = finite_array("angles", angles)
    w = finite_array("load", load)
    if len(a) != len(w) or len(a) < 2 or np.any(np.diff(a) <= 0.0):
        raise InputError("angles must be increasing and as many as the load values (2 or more)")
    if not 0.0 < fraction < 0.5:
        raise InputError(f"fraction must be in (0, 0.5), got {fraction!r}")
    if np.any(w < 0.0):
        raise InputError("load must be >= 0")
    total = float(w.sum())
    if total <= 0.0:
        return float("nan"), float("nan")
    half = 0.5 * np.diff(a).mean()
    edges = np.concatenate([a - half, a[-1:] + half])
    cum = np.concatenate([[0.0], np.cumsum(w)]) / total
    return float(np.interp(fraction, cum, edges)), float(np.interp(1.0 - fraction, cum, edges))


def bearing_drop(rear_angle: float, height: float, radius: float) -> float:
    """dh_b = r cos(phi_rear) - h, m: how far below the undisturbed surface the wheel's outer circle
    (``radius``) meets the grains it bears on at the loaded arc's rear end ``rear_angle`` (rad), its
    centre ``height`` above that surface."""
    return positive("radius", radius) * float(np.cos(finite("rear_angle", rear_angle))) - finite("height", height)
