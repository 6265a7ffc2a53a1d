"""The window tables that ``research/run_histories.py`` writes, read back for comparisons.

A window CSV has one row per run and window (run, label, t_start, t_end, velocity, sinkage); a
``_steady.csv`` one row per run with its steady state (omega in rad/s, velocity, sinkage, slip, ...).
Units SI; slip = 1 - v / (r omega).
"""

from __future__ import annotations

import csv
import math
from pathlib import Path

import numpy as np

from intrusim._checks import InputError, positive

WINDOW_KEYS = ("t_start", "t_end", "velocity", "sinkage")


def slip(velocity: float, omega_rpm: float, radius: float) -> float:
    """slip = 1 - v / (r omega), omega given in RPM."""
    return 1.0 - velocity / (positive("radius", radius) * positive("omega_rpm", omega_rpm) * 2.0 * math.pi / 60.0)


def wheel_state(row: dict[str, float], omega_rpm: float, radius: float) -> dict[str, float]:
    """``row`` (a window or a window mean: velocity, sinkage) with slip = 1 - v / (r omega) and
    sinkage / r added, omega in RPM."""
    return {**row, "slip": slip(row["velocity"], omega_rpm, radius), "sinkage_over_r": row["sinkage"] / radius}


def _rows(path: Path) -> list[dict[str, str]]:
    try:
        with Path(path).open(newline="") as f:
            return list(csv.DictReader(f))
    except FileNotFoundError:
        raise InputError(f"{path}: no such file (a run_histories.py CSV)") from None


def read_windows(path: Path, label: str) -> list[dict[str, float]]:
    """The windows (t_start, t_end, velocity, sinkage) of run ``label`` in a window CSV, in time order."""
    rows = [r for r in _rows(path) if r.get("label") == label]
    if not rows:
        raise InputError(f"{path}: no run labelled {label!r}")
    missing = [k for k in WINDOW_KEYS if k not in rows[0]]
    if missing:
        raise InputError(f"{path}: not a run_histories window CSV (no {', '.join(missing)} column)")
    return sorted(({k: float(r[k]) for k in WINDOW_KEYS} for r in rows), key=lambda w: w["t_start"])


def window_mean(rows: list[dict[str, float]], t0: float, t1: float) -> dict[str, float]:
    """Means of v and sinkage over the windows inside [t0, t1] (equal lengths, so a plain mean),
    their number and the drift (last window's v - first's) / mean v."""
    inside = [r for r in rows if r["t_start"] >= t0 - 1e-6 and r["t_end"] <= t1 + 1e-6]
    if not inside:
        end = rows[-1]["t_end"] if rows else float("nan")
        raise InputError(f"no window inside {t0}-{t1} s (the run ends at {end} s)")
    speeds = [r["velocity"] for r in inside]
    return {"velocity": float(np.mean(speeds)), "sinkage": float(np.mean([r["sinkage"] for r in inside])),
            "windows": len(inside), "drift": float((speeds[-1] - speeds[0]) / np.mean(speeds))}  # fmt: skip


def read_steady(path: Path, label: str) -> dict[str, float]:
    """One row of a ``_steady.csv``: velocity, sinkage, slip and omega_rpm."""
    for r in _rows(path):
        if r.get("label") == label:
            row = {k: float(v) for k, v in r.items() if k in ("velocity", "sinkage", "slip")}
            return {**row, "omega_rpm": float(r["omega"]) * 30.0 / math.pi}
    raise InputError(f"{path}: no row labelled {label!r}")
