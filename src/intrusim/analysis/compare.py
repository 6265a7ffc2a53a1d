"""Agreement of a reduced-order model (RFT / DRFT) with a reference (MPM): over an omega sweep, and force by force along a recorded motion."""

from __future__ import annotations

from typing import Any, Mapping

import numpy as np

from intrusim._checks import InputError
from intrusim.geometry import TAG_LUG_SIDE, TAG_LUG_TIP, TAG_SURFACE

PARTS = {"rim": TAG_SURFACE, "grouser sides": TAG_LUG_SIDE, "grouser tips": TAG_LUG_TIP}


def relative_difference(model_x: np.ndarray, model_y: np.ndarray, ref_x: np.ndarray, ref_y: np.ndarray) -> np.ndarray:
    """(model - ref) / |ref| at the reference abscissae, the model interpolated linearly in x.

    Reference points outside the model's x range get NaN (no extrapolation).
    """
    mx, my, rx, ry = (np.asarray(a, float) for a in (model_x, model_y, ref_x, ref_y))
    if mx.shape != my.shape or rx.shape != ry.shape:
        raise InputError("x and y arrays must have equal shapes")
    ok = np.isfinite(mx) & np.isfinite(my)
    if ok.sum() < 2:
        raise InputError("the model curve needs at least 2 finite points")
    order = np.argsort(mx[ok])
    xs, ys = mx[ok][order], my[ok][order]
    at = np.interp(rx, xs, ys, left=np.nan, right=np.nan)
    return (at - ry) / np.abs(ry)


def mean_wrench_along(model: object, series: Mapping[str, Any], surface_z: float = 0.0) -> np.ndarray:
    """Mean (fx, fz, moment) of a force model along a recorded trajectory, N and N m.

    model : a :class:`~intrusim.forces.ResistiveForceModel` (free surface at height 0 in its frame).
    series : equal-length arrays "x", "z", "theta", "vx", "vz", "omega" (an MPM run's time series,
        a DRFT trajectory); each sample counts once, so samples should be evenly spaced in time.
    surface_z : height of the undisturbed free surface in the series' frame (an MPM bed's depth), m.

    Along a model's own steady trajectory this gives its steady force (fx = -push, fz = weight);
    along another model's (MPM's) it says which force component the two disagree on.
    """
    keys = ("x", "z", "theta", "vx", "vz", "omega")
    missing = [k for k in keys if k not in series]
    if missing:
        raise InputError(f"the series lacks {missing}")
    cols = [np.asarray(series[k], float) for k in keys]
    if len({c.shape for c in cols}) != 1 or cols[0].ndim != 1 or cols[0].size == 0:
        raise InputError("the series arrays must be 1-D, non-empty and of equal length")
    if not all(np.all(np.isfinite(c)) for c in cols):
        raise InputError("the series has NaN or infinite values")
    x, z, th, vx, vz, om = cols
    w = [model.wrench_tuple(*state) for state in zip(x, z - surface_z, th, vx, vz, om)]  # type: ignore[attr-defined]
    return np.mean(np.asarray(w, float), axis=0)


def forces_by_part(
    tags: np.ndarray, ahead: np.ndarray, forces: np.ndarray, halves: tuple[str, str] = ("ahead", "behind")
) -> dict[str, np.ndarray]:
    """(fx, fz) of the elements of each part (:data:`PARTS`), split into those ``ahead`` of the
    body centre (boolean mask) and the rest: {"rim, ahead": (2,), ...}, halves named ``halves``."""
    out = {}
    for name, tag in PARTS.items():
        for half, sel in zip(halves, (ahead, ~ahead)):
            out[f"{name}, {half}"] = forces[(tags == tag) & sel].sum(axis=0)
    return out
