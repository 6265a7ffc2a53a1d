"""Agreement of a reduced-order model (RFT / DRFT) with a reference (MPM) over an omega sweep."""

from __future__ import annotations

import numpy as np

from intrusim._checks import InputError


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
