"""Fit the Li, Zhang & Goldman (2013) Fourier form to a measured map alpha(beta, gamma).

Li et al. keep nine terms of the discrete Fourier series (``intrusim.laws.rft``):

    alpha_z = A00 + A10 cos 2b + B11 sin(2b + g) + B01 sin g + B-11 sin(-2b + g)
    alpha_x = C11 cos(2b + g) + C01 cos g + C-11 cos(-2b + g) + D10 sin 2b

These terms, and only these, keep the mirror symmetry x -> -x on the edges gamma = +-pi/2 of the
fitted range (alpha_z even and alpha_x odd in beta there), so the extension of ``laws.rft.alpha``
to every direction stays continuous. The fit is linear least squares in each component; the
result is a (4, 3, 2) table ``[A, B, C, D][m + 1, n]`` in N/cm^3, the layout of the generic one.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from intrusim._checks import InputError
from intrusim.laws.rft import N_PER_CM3, mirror_extended

# (table index 0..3 = A, B, C, D; m; n) of the kept terms, alpha_z first, then alpha_x
Z_TERMS = ((0, 0, 0), (0, 1, 0), (1, 1, 1), (1, 0, 1), (1, -1, 1))
X_TERMS = ((2, 1, 1), (2, 0, 1), (2, -1, 1), (3, 1, 0))


def _basis(terms, beta: np.ndarray, gamma: np.ndarray) -> np.ndarray:
    cols = []
    for k, m, n in terms:
        arg = 2 * m * beta + n * gamma
        cols.append(np.cos(arg) if k in (0, 2) else np.sin(arg))
    return np.column_stack(cols)


def fit_li_form(beta, gamma, alpha_x, alpha_z) -> tuple[np.ndarray, dict]:
    """Least-squares fit of the nine Li terms to a map in N/m^3, beta and gamma in rad.

    Returns the (4, 3, 2) coefficient table in N/cm^3 and a dict with the rms and largest
    residual of each component (N/m^3) and the number of points. Needs at least 5 points that
    are not all at one beta or one gamma (the system must have full rank).
    """
    b, g, ax, az = (np.ravel(np.asarray(a, float)) for a in (beta, gamma, alpha_x, alpha_z))
    if not (len(b) == len(g) == len(ax) == len(az)):
        raise InputError("beta, gamma, alpha_x and alpha_z must have the same length")
    if not np.all(np.isfinite(np.concatenate([b, g, ax, az]))):
        raise InputError("the map holds non-finite values")
    coef = np.zeros((4, 3, 2))
    info: dict = {"points": int(len(b))}
    for name, terms, y in (("z", Z_TERMS, az), ("x", X_TERMS, ax)):
        basis = _basis(terms, b, g)
        if np.linalg.matrix_rank(basis) < len(terms):
            raise InputError(f"the map does not determine the {len(terms)} alpha_{name} terms (rank too low)")
        sol, *_ = np.linalg.lstsq(basis, y, rcond=None)
        for (k, m, n), c in zip(terms, sol):
            coef[k, m + 1, n] = c / N_PER_CM3
        res = y - basis @ sol
        info[f"rms_{name}"] = float(np.sqrt(np.mean(res**2)))
        info[f"max_{name}"] = float(np.max(np.abs(res)))
    return coef, info


def coefficient_blocks(coef: np.ndarray) -> dict[str, dict[str, float]]:
    """(4, 3, 2) table -> {"A": {"m,n": value}, ...} (N/cm^3), the layout of rft_li2013.toml."""
    out: dict[str, dict[str, float]] = {}
    for k, name in enumerate("ABCD"):
        out[name] = {f"{m - 1},{n}": float(coef[k, m, n]) for m in range(3) for n in range(2) if coef[k, m, n] != 0.0}
    return out


def scale_to(coef: np.ndarray, reference: np.ndarray) -> float:
    """The single factor xi that brings ``reference`` closest to ``coef`` (least squares over the table)."""
    r = np.ravel(reference)
    return float(np.dot(np.ravel(coef), r) / np.dot(r, r))


def write_coefficients(path: str | Path, coef: np.ndarray, meta: dict | None = None) -> Path:
    """Save a table as JSON: {"units": "N/cm^3", "A": {...}, ..., "meta": {...}}."""
    path = Path(path)
    path.write_text(json.dumps({"units": "N/cm^3", **coefficient_blocks(coef), "meta": meta or {}}, indent=1))
    return path


def interpolated_map(beta, gamma, alpha_x, alpha_z):
    """alpha(beta, gamma) (N/m^3) interpolated linearly in a measured map, without a fitted form.

    The map must cover a full regular grid over beta and gamma in [-pi/2, pi/2] (beta = -pi/2 may
    be left out: it is the plate beta = pi/2). Other angles use the conventions of
    :func:`intrusim.laws.rft.alpha` (:func:`~intrusim.laws.rft.mirror_extended`). Returns a
    function of (beta, gamma) arrays.
    """
    from scipy.interpolate import RegularGridInterpolator

    b, g, ax, az = (np.ravel(np.asarray(a, float)) for a in (beta, gamma, alpha_x, alpha_z))
    b = np.where(np.isclose(b, -0.5 * np.pi), 0.5 * np.pi, b)
    has_vertical = np.isclose(b, 0.5 * np.pi)
    b = np.concatenate([b, np.full(has_vertical.sum(), -0.5 * np.pi)])  # the vertical plate at both ends
    g = np.concatenate([g, g[has_vertical]])
    ax = np.concatenate([ax, ax[has_vertical]])
    az = np.concatenate([az, az[has_vertical]])
    bs, gs = np.unique(np.round(b, 9)), np.unique(np.round(g, 9))
    if not (np.isclose(bs[0], -0.5 * np.pi) and np.isclose(bs[-1], 0.5 * np.pi)
            and np.isclose(gs[0], -0.5 * np.pi) and np.isclose(gs[-1], 0.5 * np.pi)):  # fmt: skip
        raise InputError("the map must span beta and gamma from -pi/2 to pi/2")
    grid_x = np.full((len(bs), len(gs)), np.nan)
    grid_z = np.full_like(grid_x, np.nan)
    i, j = np.searchsorted(bs, np.round(b, 9)), np.searchsorted(gs, np.round(g, 9))
    grid_x[i, j], grid_z[i, j] = ax, az
    if np.isnan(grid_x).any():
        raise InputError("the map must hold every (beta, gamma) of its grid")
    fx = RegularGridInterpolator((bs, gs), grid_x)
    fz = RegularGridInterpolator((bs, gs), grid_z)

    def on_grid(b, g):  # the fitted range; clipped against rounding at the edges
        pts = np.stack(np.broadcast_arrays(np.clip(b, bs[0], bs[-1]), np.clip(g, gs[0], gs[-1])), axis=-1)
        return fx(pts), fz(pts)

    return lambda beta, gamma: mirror_extended(on_grid, beta, gamma)
