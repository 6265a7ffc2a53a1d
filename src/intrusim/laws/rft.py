"""Quasistatic Resistive Force Theory (paper Eq. 3) with the Li-Zhang-Goldman (2013) fit.

Angle conventions (checked against Li et al. 2013 and public RFT wheel codes; see docs/rft.md),
in the frame x forward, z up:

* beta: orientation of a surface element, minus the counter-clockwise angle of its tangent,
  wrapped to [-pi/2, pi/2] (a plate is the same plate rotated by pi). With outward normal
  n = (n_x, n_z): cos 2 beta = n_z^2 - n_x^2 and sin 2 beta = 2 n_x n_z.
* gamma: direction of the element's velocity, gamma = atan2(-v_z, -v_x). Straight-down
  intrusion is gamma = +pi/2, motion towards -x is gamma = 0.

The published fit covers gamma in [-pi/2, pi/2] (motion with a -x component). Other directions
follow by the mirror symmetry x -> -x: evaluate at (-beta, pi - gamma) (or -pi - gamma) and flip
the sign of alpha_x.
"""

from __future__ import annotations

import json
import tomllib
from pathlib import Path

import numpy as np

from intrusim._checks import InputError, non_negative
from intrusim.params import li2013_coefficients

N_PER_CM3 = 1.0e6  # N/cm^3 -> N/m^3


def _coefficient_table(block: dict[str, float]) -> np.ndarray:
    """TOML block {"m,n": value} -> (3, 2) array indexed [m + 1, n], m in {-1, 0, 1}, n in {0, 1}."""
    table = np.zeros((3, 2))
    for key, value in block.items():
        m, n = (int(s) for s in key.split(","))
        if m not in (-1, 0, 1) or n not in (0, 1):
            raise ValueError(f"term {key!r} is outside m in -1..1, n in 0..1")
        table[m + 1, n] = float(value)
    return table


def coefficient_table(blocks: dict) -> np.ndarray:
    """{"A": {"m,n": value}, ..., "D": {...}} (N/cm^3) -> (4, 3, 2) table; missing terms are zero."""
    return np.stack([_coefficient_table(blocks.get(k, {})) for k in "ABCD"])


def li2013_tables() -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The generic coefficients (A, B, C, D) as (3, 2) arrays [m + 1, n], in N/cm^3."""
    return tuple(coefficient_table(li2013_coefficients()))  # type: ignore[return-value]


LI2013 = coefficient_table(li2013_coefficients())  # (4, 3, 2): [A, B, C, D][m + 1, n], N/cm^3
A_COEF, B_COEF, C_COEF, D_COEF = LI2013


def load_coefficients(path: str | Path) -> np.ndarray:
    """A coefficient table from a TOML or JSON file laid out as ``data/rft_li2013.toml`` (N/cm^3).

    ``intrusim.analysis.rft_fit.write_coefficients`` writes such a JSON from a measured map.
    """
    path = Path(path)
    if not path.is_file():
        raise InputError(f"RFT coefficient file {str(path)!r} not found")
    text = path.read_text()
    try:
        data = tomllib.loads(text) if path.suffix == ".toml" else json.loads(text)
    except (tomllib.TOMLDecodeError, json.JSONDecodeError) as err:
        raise InputError(f"{path}: not valid {'TOML' if path.suffix == '.toml' else 'JSON'} ({err})") from None
    if not isinstance(data, dict) or not any(k in data for k in "ABCD"):
        raise InputError(f"{path}: no coefficient blocks A, B, C, D")
    if data.get("units", "N/cm^3") != "N/cm^3":
        raise InputError(f"{path}: RFT coefficients must be in N/cm^3, got {data['units']!r}")
    try:
        table = coefficient_table(data)
    except (ValueError, TypeError, IndexError, AttributeError) as err:
        raise InputError(f'{path}: each block must map "m,n" (m in -1..1, n in 0..1) to a number ({err})') from None
    if not np.all(np.isfinite(table)):
        raise InputError(f"{path}: non-finite coefficients")
    return table


def as_table(coef: np.ndarray | None) -> np.ndarray:
    """A checked (4, 3, 2) coefficient table (N/cm^3); None: the generic one, :data:`LI2013`."""
    if coef is None:
        return LI2013
    coef = np.asarray(coef, float)
    if coef.shape != (4, 3, 2):
        raise InputError(f"an RFT coefficient table has shape (4, 3, 2), got {coef.shape}")
    return coef


def alpha_fit(beta: np.ndarray, gamma: np.ndarray, coef: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
    """The raw Li (2013) discrete Fourier fit, without symmetry extension (N/cm^3).

    alpha_z = sum_{m=-1..1, n=0..1} A_mn cos(2 m beta + n gamma) + B_mn sin(2 m beta + n gamma)
    alpha_x = sum_{m=-1..1, n=0..1} C_mn cos(2 m beta + n gamma) + D_mn sin(2 m beta + n gamma)

    Valid for beta, gamma in [-pi/2, pi/2]; use :func:`alpha` for any angles. ``coef``: a
    (4, 3, 2) table ``[A, B, C, D][m + 1, n]`` in N/cm^3 (default: the generic one, :data:`LI2013`).
    """
    A, B, C, D = as_table(coef)
    beta = np.asarray(beta, float)
    gamma = np.asarray(gamma, float)
    ax = np.zeros(np.broadcast(beta, gamma).shape)
    az = np.zeros_like(ax)
    for m in (-1, 0, 1):
        for n in (0, 1):
            arg = 2 * m * beta + n * gamma
            ca, sa = np.cos(arg), np.sin(arg)
            az = az + A[m + 1, n] * ca + B[m + 1, n] * sa
            ax = ax + C[m + 1, n] * ca + D[m + 1, n] * sa
    return ax, az


def wrap_beta(beta: np.ndarray) -> np.ndarray:
    """Wrap a plate orientation into [-pi/2, pi/2) (orientation is defined modulo pi)."""
    return (np.asarray(beta, float) + 0.5 * np.pi) % np.pi - 0.5 * np.pi


def alpha(
    beta: np.ndarray, gamma: np.ndarray, xi: float = 1.0, coef: np.ndarray | None = None
) -> tuple[np.ndarray, np.ndarray]:
    """Stress per unit depth (alpha_x, alpha_z) for any beta and gamma, in N/m^3 (Eq. 3).

    The generic fit is scaled by the media coefficient ``xi`` (poppy seeds: 0.35). Directions
    outside the fitted range |gamma| <= pi/2 use the mirror symmetry x -> -x.

    Parameters
    ----------
    beta : array, rad. Element orientation (see module docstring).
    gamma : array, rad. Velocity direction, atan2(-v_z, -v_x).
    xi : float, >= 0. Media scaling coefficient.
    coef : (4, 3, 2) table in N/cm^3 (default: the generic fit); e.g. one measured on the MPM
        medium (``intrusim.analysis.rft_fit``), usually with xi = 1.
    """
    xi = non_negative("xi", xi)
    ax, az = mirror_extended(lambda b, g: alpha_fit(b, g, coef), beta, gamma)
    return xi * N_PER_CM3 * ax, xi * N_PER_CM3 * az


def mirror_extended(fit, beta: np.ndarray, gamma: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``fit(beta, gamma) -> (alpha_x, alpha_z)``, defined for beta, gamma in [-pi/2, pi/2], at any angles.

    beta is wrapped modulo pi (a plate is the same plate rotated by pi); a direction with
    |gamma| > pi/2 is evaluated at its mirror image x -> -x, (-beta, +-pi - gamma), with
    alpha_x flipped. Used by :func:`alpha` and by measured maps (``analysis.rft_fit``).
    """
    b = wrap_beta(beta)
    g = (np.asarray(gamma, float) + np.pi) % (2 * np.pi) - np.pi  # wrap to [-pi, pi)
    mirror = np.abs(g) > 0.5 * np.pi
    g_fit = np.where(mirror, np.sign(g) * np.pi - g, g)
    b_fit = np.where(mirror, -b, b)
    ax, az = fit(b_fit, g_fit)
    return np.where(mirror, -ax, ax), az


def element_angles(normal: np.ndarray, velocity: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(beta, gamma) of elements with outward unit ``normal`` (N, 2) moving at ``velocity`` (N, 2).

    beta = -(counter-clockwise tangent angle), tangent = (-n_z, n_x); gamma = atan2(-v_z, -v_x).
    """
    n = np.asarray(normal, float)
    v = np.asarray(velocity, float)
    tangent_angle = np.arctan2(n[..., 0], -n[..., 1])
    return wrap_beta(-tangent_angle), np.arctan2(-v[..., 1], -v[..., 0])


def rft_traction(
    normal: np.ndarray,
    velocity: np.ndarray,
    depth: np.ndarray,
    xi: float,
    coef: np.ndarray | None = None,
) -> np.ndarray:
    """Quasistatic RFT traction t = alpha(beta, gamma) H(-z) |z| on leading elements (Eq. 3), N/m^2.

    Elements that do not move into the medium (n . v <= 0, the leading-edge rule) or lie
    above the surface get zero traction.

    Parameters
    ----------
    normal : (N, 2) outward unit normals.
    velocity : (N, 2) element velocities, m/s.
    depth : (N,) height of each element relative to the (effective) free surface, m;
        negative below the surface (the paper's z, or z~ = z + dh for DRFT).
    xi : media scaling coefficient.
    coef : (4, 3, 2) coefficient table in N/cm^3 (default: the generic fit).
    """
    return rft_traction_with(lambda b, g: alpha(b, g, xi, coef), normal, velocity, depth)


def rft_traction_with(alpha_fn, normal: np.ndarray, velocity: np.ndarray, depth: np.ndarray) -> np.ndarray:
    """:func:`rft_traction` with any stress-per-depth law ``alpha_fn(beta, gamma) -> (alpha_x, alpha_z)``
    in N/m^3 (e.g. a measured map, ``intrusim.analysis.rft_fit.interpolated_map``), N/m^2."""
    n = np.asarray(normal, float)
    v = np.asarray(velocity, float)
    z = np.asarray(depth, float)
    beta, gamma = element_angles(n, v)
    ax, az = alpha_fn(beta, gamma)
    leading = np.einsum("ij,ij->i", n, v) > 0.0
    active = leading & (z < 0.0)
    scale = np.where(active, -z, 0.0)
    return np.column_stack([ax * scale, az * scale])
