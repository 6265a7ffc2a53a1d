"""A grain-length law for DRFT's media scaling xi (an extension, not in the paper).

RFT and DRFT have no length: a wheel half the size in the same sand is the same wheel at half
the scale. The nonlocal-law MPM has one, the grain diameter d of its cooperativity length: on the
resolved grid (2.5 mm cells) the large wheel with 12 mm grains and the half-size wheel with 6 mm
grains (both d / r 0.113) are one non-dimensional state, and the large wheel with 6 mm grains
(d / r 0.057) slips and sinks more (research/notes/results_log.md, "grain length"). DRFT fitted on one d / r
carries to another wheel only at the same d / r; this module makes xi a function of it:

    xi(d / r) = xi_ref (d / r / q_ref)^p

fitted by least squares in log xi on xi values calibrated at two or more d / r
(:func:`intrusim.analysis.calibration.calibrate` with ``params=("xi",)``), q_ref their geometric
mean. With two points the law passes through both and only a third d / r, or another wheel at
one of them, tests it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np


def d_over_r(grain_diameter: float, radius: float) -> float:
    """The grain length over the wheel's radius, d / r (both m, finite, > 0)."""
    for name, x in (("grain_diameter", grain_diameter), ("radius", radius)):
        if not (isinstance(x, (int, float)) and math.isfinite(x) and x > 0.0):
            raise ValueError(f"{name} must be finite and > 0 (m), got {x!r}")
    return float(grain_diameter) / float(radius)


@dataclass(frozen=True)
class XiLengthLaw:
    """xi(q) = xi_ref (q / q_ref)^exponent, q = d / r."""

    xi_ref: float
    q_ref: float
    exponent: float

    def __post_init__(self) -> None:
        if not (math.isfinite(self.xi_ref) and self.xi_ref > 0.0 and math.isfinite(self.q_ref) and self.q_ref > 0.0):
            raise ValueError(f"xi_ref and q_ref must be finite and > 0, got {self.xi_ref!r}, {self.q_ref!r}")
        if not math.isfinite(self.exponent):
            raise ValueError(f"exponent must be finite, got {self.exponent!r}")

    def xi(self, q: Any) -> Any:
        """xi at d / r = ``q`` (scalar or array, each > 0)."""
        qa = np.asarray(q, float)
        if not (np.all(np.isfinite(qa)) and np.all(qa > 0.0)):
            raise ValueError(f"d / r must be finite and > 0, got {q!r}")
        out = self.xi_ref * (qa / self.q_ref) ** self.exponent  # xi = xi_ref (q / q_ref)^p
        return float(out) if out.ndim == 0 else out

    def summary(self) -> dict[str, float]:
        return {"xi_ref": self.xi_ref, "q_ref": self.q_ref, "exponent": self.exponent}


def fit_xi_length_law(q: Any, xi: Any) -> XiLengthLaw:
    """Least-squares fit of log xi = log xi_ref + p log(q / q_ref), q_ref the geometric mean of q.

    Raises ValueError unless q and xi are 1-D, of equal length, finite and > 0, with at least two
    distinct q.
    """
    qa, xa = np.asarray(q, float), np.asarray(xi, float)
    if qa.ndim != 1 or qa.shape != xa.shape:
        raise ValueError(f"q and xi must be 1-D arrays of equal length, got shapes {qa.shape} and {xa.shape}")
    if not (np.all(np.isfinite(qa)) and np.all(np.isfinite(xa)) and np.all(qa > 0.0) and np.all(xa > 0.0)):
        raise ValueError(f"q (d / r) and xi must be finite and > 0, got {qa.tolist()} and {xa.tolist()}")
    if len(np.unique(qa)) < 2:
        raise ValueError(f"a length law needs xi at two distinct d / r at least, got d / r {qa.tolist()}")
    lq, lx = np.log(qa), np.log(xa)
    q_ref = float(np.exp(lq.mean()))
    p = float(np.sum((lq - lq.mean()) * (lx - lx.mean())) / np.sum((lq - lq.mean()) ** 2))
    return XiLengthLaw(xi_ref=float(np.exp(lx.mean())), q_ref=q_ref, exponent=p)
