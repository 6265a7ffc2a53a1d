"""Has a run settled? The stop test of a continuum run, and what happened when it had not.

A run of a driven body is judged on its last two *settling windows*, each one revolution of the
body (2 pi / |omega|: every lug has passed once), after the run's transient (ramp and settle time):

* **settled** when the mean velocity and the mean sinkage each moved by less than ``tol`` (a
  fraction, 1 % by default) from the earlier window to the later one; the answer is then the later
  window's means, with the change between the two windows as its settling uncertainty. Given the
  body's radius r, a change is relative to at least a tenth of r (sinkage) and of r |omega| (v),
  so a body riding at the surface or nearly stopped is judged on a scale of its own size, not
  on a mean near zero;
* **buried** (entrapment) when the body's whole height is under the undisturbed surface in the
  later window, whatever else it does;
* otherwise the outcome says what the body is still doing, most serious first: **sinking** (the
  sinkage still grows: "still sinking at X mm/s", entrapment if it never stops), **rising**,
  **slowing** or **accelerating** (v still changes, at X m/s^2);
* **too short** when the run after its transient is shorter than two windows: nothing can be said.

:func:`settling` is a pure function of the sampled series, so the same test stops a run
(``MPMSettings.settle_tol``) and judges a finished one (``result.json``'s ``outcome``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

SETTLE_TOL = 0.01  # the default stop test: v and sinkage each within 1 % over the last revolution
OUTCOMES = ("settled", "buried", "sinking", "rising", "slowing", "accelerating", "too short")


def settle_window(omega: float) -> float:
    """One settling window, s: one revolution of a body turning at ``omega`` rad/s."""
    w = abs(float(omega))
    if not (math.isfinite(w) and w > 0.0):
        raise ValueError(f"a settling window needs a turning body, got omega = {omega!r}")
    return 2.0 * math.pi / w


@dataclass(frozen=True)
class Settling:
    """The verdict of :func:`settling` (SI).

    outcome : one of :data:`OUTCOMES`; text : the same in words, with the rate that matters.
    window : s, one settling window; t_end : s, the end of the later window.
    velocity, sinkage : the later window's means (m/s, m).
    dv, ds : |change| of the mean velocity and of the mean sinkage from the earlier window to the
        later one, relative to the later one (the settling uncertainty of a settled answer).
    sinkage_rate : m/s, the sinkage's change over one window, per second (> 0 sinking).
    acceleration : m/s^2, the velocity's change over one window, per second.
    tol : the test's tolerance.
    """

    outcome: str
    text: str
    window: float
    t_end: float
    velocity: float
    sinkage: float
    dv: float
    ds: float
    sinkage_rate: float
    acceleration: float
    tol: float

    @property
    def settled(self) -> bool:
        return self.outcome == "settled"

    def summary(self) -> dict[str, Any]:
        """The numbers of the verdict, for a run's record (``result.json``, a sweep's CSV)."""
        return {"outcome": self.outcome, "settle_dv": self.dv, "settle_ds": self.ds,
                "sinkage_rate": self.sinkage_rate, "acceleration": self.acceleration,
                "settle_window": self.window, "settle_tol": self.tol}  # fmt: skip


def settling(
    t: Any,
    velocity: Any,
    sinkage: Any,
    omega: float,
    t_start: float,
    tol: float = SETTLE_TOL,
    radius: float | None = None,
) -> Settling:
    """Judge a run from its samples ``t`` (s), ``velocity`` (m/s) and ``sinkage`` (m) after
    ``t_start`` (the end of its transient), the body turning at ``omega`` rad/s (module docstring);
    ``radius`` (m): the body's outer radius: buried beyond a sinkage of 2 r, and the floor of the
    changes' scales (None: neither)."""
    if not (math.isfinite(tol) and 0.0 < tol < 1.0):
        raise ValueError(f"tol must be a fraction in (0, 1), got {tol!r}")
    t, v, s = (np.asarray(a, float) for a in (t, velocity, sinkage))
    w = settle_window(omega)
    t_end = float(t[-1]) if len(t) else math.nan
    later = (t > t_end - w) & (t > t_start)
    earlier = (t > t_end - 2 * w) & (t <= t_end - w) & (t > t_start)
    if not len(t) or t_end - 2 * w < t_start - 1e-9 or not earlier.any() or not later.any():
        need = t_start + 2 * w
        text = f"too short to judge: the test needs two revolutions after t = {t_start:.3g} s, to t = {need:.3g} s"
        return Settling("too short", text, w, t_end, math.nan, math.nan, math.nan, math.nan, math.nan, math.nan, tol)
    v1, v0 = float(v[later].mean()), float(v[earlier].mean())
    s1, s0 = float(s[later].mean()), float(s[earlier].mean())
    floor_s = 0.1 * radius if radius is not None else 1e-12
    floor_v = 0.1 * radius * abs(float(omega)) if radius is not None else 1e-12
    dv = abs(v1 - v0) / max(abs(v1), floor_v)
    ds = abs(s1 - s0) / max(abs(s1), floor_s)
    rate, accel = (s1 - s0) / w, (v1 - v0) / w
    if radius is not None and s1 >= 2 * radius:  # the circle the turning body sweeps wholly under the surface
        outcome = "buried"
        text = (f"buried: its top {(s1 - 2 * radius) * 1e3:.3g} mm under the surface (entrapped), sinking at "
                f"{rate * 1e3:.3g} mm/s, v {v1:.3g} m/s")  # fmt: skip
    elif dv < tol and ds < tol:
        outcome = "settled"
        text = (
            f"settled: v and sinkage moved {dv:.2%} and {ds:.2%} over the last revolution ({w:.3g} s; test {tol:.0%})"
        )
    elif ds >= tol:
        outcome = "sinking" if rate > 0 else "rising"
        text = f"still {outcome} at {abs(rate) * 1e3:.3g} mm/s (sinkage {ds:.1%} over the last revolution, {w:.3g} s)"
    else:
        outcome = "accelerating" if accel > 0 else "slowing"
        text = f"still {outcome} at {abs(accel):.3g} m/s^2 (v {dv:.1%} over the last revolution, {w:.3g} s)"
    return Settling(outcome, text, w, t_end, v1, s1, dv, ds, rate, accel, tol)
