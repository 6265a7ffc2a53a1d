"""Fit the Li, Zhang & Goldman (2013) Fourier form to a measured map alpha(beta, gamma).

Li et al. keep nine terms of the discrete Fourier series (``intrusim.laws.rft``):

    alpha_z = A00 + A10 cos 2b + B11 sin(2b + g) + B01 sin g + B-11 sin(-2b + g)
    alpha_x = C11 cos(2b + g) + C01 cos g + C-11 cos(-2b + g) + D10 sin 2b

These terms, and only these, keep the mirror symmetry x -> -x on the edges gamma = +-pi/2 of the
fitted range (alpha_z even and alpha_x odd in beta there), so the extension of ``laws.rft.alpha``
to every direction stays continuous. The fit is linear least squares in each component; the
result is a (4, 3, 2) table [A, B, C, D][m + 1, n] in N/cm^3, the layout of the generic one.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from intrusim._checks import InputError
from intrusim.laws.rft import N_PER_CM3

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
    import json

    path = Path(path)
    path.write_text(json.dumps({"units": "N/cm^3", **coefficient_blocks(coef), "meta": meta or {}}, indent=1))
    return path
