"""RFT stress-per-depth maps alpha(beta, gamma) measured on the MPM medium.

Li, Zhang & Goldman (2013) measured the generic RFT coefficients by moving a small plate of
orientation beta through the grains in direction gamma and dividing the force by the plate area
and depth. :class:`PlateMapCase` is the same experiment in the 2D plane-strain MPM: a plate of
length L and one or two cells thickness starts embedded (the grains in its place are left out)
and moves at constant speed along gamma, its centre passing the set depth at mid-travel. Then

    alpha = F / (L |z|)        (N/m^3; F per unit width, |z| the plate centre's current depth)

averaged over the second half of the travel. Angles as :mod:`intrusim.laws.rft`: beta the
orientation (a plate rotated by theta = -beta from horizontal), gamma = atan2(-v_z, -v_x)
(+pi/2: straight down, 0: towards -x).
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass

import numpy as np

from intrusim._checks import InputError
from intrusim.laws.rft import wrap_beta

from .config import (
    CONTACTS,
    DEFAULT_CONTACT,
    BedConfig,
    DomainConfig,
    FluidityConfig,
    IntruderConfig,
    MaterialConfig,
    MPMConfig,
    OutputConfig,
    PrescribedMotion,
    Rectangle,
    TimeConfig,
)  # fmt: skip
from .plate import plate_polygon, window_mask


@dataclass
class PlateMapCase:
    """One plate of the map: orientation ``beta`` moving along ``gamma`` (rad), SI units."""

    beta: float
    gamma: float
    depth: float = 0.04  # m, plate centre below the initial surface at mid-travel
    plate_length: float = 0.025  # m
    plate_thickness: float = 0.005  # m
    speed: float = (
        0.05  # m/s (quasistatic: rho v^2 = 1.6 Pa, 2e-4 of the push-down stress, ~1 % of the weakest entries)
    )
    travel: float = 0.02  # m
    cell_size: float = 0.0025  # m
    domain: tuple[float, float] = (0.30, 0.20)  # m
    bed_height: float = 0.15  # m
    rho_c: float = 638.0  # kg/m^3, poppy seeds (Table S1), as the MPM wheel
    mu_s: float = 0.56
    mu_w: float = 0.35
    youngs_modulus: float = 1.0e6  # Pa
    # MPMConfig.contact: the MPM's default ("nodes"). The 25 mm plate pushed down: "nodes" 198k and 206k
    # N/m^3 at 5 and 2.5 mm cells, the band contact with band 0 185k and 182k, "surface" 328k and 289k
    # (docs/mpm.md)
    contact: str = DEFAULT_CONTACT
    contact_band_cells: float = 0.0  # cells, for contact = "band"
    ramp_time: float = 0.02  # s
    # the path is shifted by this many cells in +x and -z: a plate whose faces lie whole cells
    # apart then never rests with a face on a grid line, where (band 0) a node counts as inside
    # or not by rounding (unshifted, a vertical plate pushed straight down felt a sideways force
    # of 50-60 % of its lift)
    grid_offset: float = 0.5
    # m: the nonlocal granular fluidity with grains of this diameter in place of the paper's
    # Drucker-Prager return (FluidityConfig's other defaults); None = the paper's law
    fluidity_diameter: float | None = None

    def __post_init__(self) -> None:
        for name in ("depth", "plate_length", "plate_thickness", "speed", "travel", "cell_size", "bed_height"):
            v = getattr(self, name)
            if not (math.isfinite(v) and v > 0):
                raise InputError(f"{name} must be a finite number > 0, got {v!r}")
        d = self.fluidity_diameter
        if d is not None and not (math.isfinite(d) and d > 0):
            raise InputError(f"fluidity_diameter must be None or a finite number > 0, got {d!r}")
        if self.contact not in CONTACTS:
            raise InputError(f"contact must be one of {', '.join(CONTACTS)}, got {self.contact!r}")
        if not (math.isfinite(self.beta) and math.isfinite(self.gamma)):
            raise InputError(f"beta and gamma must be finite, got {self.beta!r}, {self.gamma!r}")
        half = 0.5 * self.plate_length * abs(math.sin(self.beta)) + 0.5 * self.plate_thickness
        top = self.depth - 0.5 * self.travel * abs(math.sin(self.gamma)) - half  # the offset only lowers it
        if top <= self.cell_size:
            raise InputError(
                f"the plate comes within one cell of the surface (top {top * 1e3:.1f} mm deep): "
                "increase depth or reduce travel / plate_length"
            )
        sweep = 0.5 * self.travel * abs(math.sin(self.gamma))
        bottom = self.bed_height - self.depth - self.grid_offset * self.cell_size - sweep - half
        reach = 0.5 * self.travel * abs(math.cos(self.gamma)) + 0.5 * self.plate_length
        if bottom < 2 * self.plate_length or reach > 0.5 * self.domain[0] - 2 * self.plate_length:
            raise InputError("the plate comes within two plate lengths of the floor or a side wall")
        if self.bed_height >= self.domain[1]:
            raise InputError("bed_height must be below the top of the domain")

    @property
    def velocity(self) -> tuple[float, float]:
        """(v_x, v_z), m/s: gamma = atan2(-v_z, -v_x)."""
        return -self.speed * math.cos(self.gamma), -self.speed * math.sin(self.gamma)

    def start(self) -> tuple[float, float]:
        """Plate centre at t = 0 (x, z), m: it passes (domain centre, bed - depth), shifted by
        ``grid_offset`` cells in +x and -z, at mid-travel."""
        vx, vz = self.velocity
        half_t = 0.5 * self.travel / self.speed
        shift = self.grid_offset * self.cell_size
        return 0.5 * self.domain[0] + shift - vx * half_t, self.bed_height - self.depth - shift - vz * half_t

    def config(self, directory: str | None = None, **backend) -> MPMConfig:
        t_end = self.travel / self.speed + 0.5 * self.ramp_time  # the ramp loses half its time
        cells = (round(self.domain[0] / self.cell_size), round(self.domain[1] / self.cell_size))
        x0, z0 = self.start()
        vx, vz = self.velocity
        return MPMConfig(
            domain=DomainConfig(size=self.domain, cells=cells),
            material=MaterialConfig(
                rho_c=self.rho_c,
                mu_s=self.mu_s,
                youngs_modulus=self.youngs_modulus,
                fluidity=None
                if self.fluidity_diameter is None
                else FluidityConfig(grain_diameter=self.fluidity_diameter),
            ),
            bed=BedConfig(rectangles=[Rectangle(x0=0, z0=0, x1=self.domain[0], z1=self.bed_height)]),
            intruders=[
                IntruderConfig(
                    vertices=plate_polygon(self.plate_length, self.plate_thickness, vertical=False),
                    width=1.0,
                    mu_w=self.mu_w,
                    x=x0,
                    z=z0,
                    theta=-self.beta,
                    motion=PrescribedMotion(vx=vx, vz=vz, ramp_time=self.ramp_time),
                )
            ],
            contact=self.contact,
            contact_band_cells=self.contact_band_cells,
            time=TimeConfig(t_end=t_end, v_max_expected=max(self.speed, 0.5)),
            output=OutputConfig(directory=directory, record_every=t_end / 200),
            backend=backend or {},
        )


def alpha_history(rows: list[dict], case: PlateMapCase) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The run's record times (s), alpha = F / (L |z|) at each (N/m^3, columns x and z) and the
    plate centre's depth |z| (m)."""
    t = np.array([r["time"] for r in rows])
    f = np.array([[r["fx"], r["fz"]] for r in rows])
    depth = case.bed_height - np.array([r["z"] for r in rows])
    if np.any(depth <= 0):
        raise InputError("the plate centre rose above the initial surface")
    return t, f / (case.plate_length * depth[:, None]), depth


def in_window(t: np.ndarray, window: tuple[float, float]) -> np.ndarray:
    """The records in the fraction ``window`` of the run (t[-1] its end); InputError if none."""
    sel = window_mask(t, window)
    if not sel.any():
        raise InputError(f"no records in the window {window} of the run")
    return sel


def measure_alpha(rows: list[dict], case: PlateMapCase, window: tuple[float, float] = (0.5, 1.0)) -> dict:
    """alpha = F / (L |z|) over a fraction ``window`` of the run (N/m^3): mean and standard deviation."""
    t, a, depth = alpha_history(rows, case)
    sel = in_window(t, window)
    return {
        "alpha_x": float(a[sel, 0].mean()),
        "alpha_z": float(a[sel, 1].mean()),
        "alpha_x_std": float(a[sel, 0].std()),
        "alpha_z_std": float(a[sel, 1].std()),
        "depth_mean": float(depth[sel].mean()),
    }


def map_cases(betas: list[float], gammas: list[float], **common) -> list[PlateMapCase]:
    """Every (beta, gamma) pair, beta = +-pi/2 counted once (the same vertical plate)."""
    out, seen = [], set()
    for b in betas:
        key_b = round(float(wrap_beta(b)), 9)  # beta and beta + pi are the same plate
        for g in gammas:
            if (key_b, round(g, 9)) in seen:
                continue
            seen.add((key_b, round(g, 9)))
            out.append(PlateMapCase(beta=b, gamma=g, **common))
    return out


def case_record(case: PlateMapCase) -> dict:
    """The case's parameters as a flat dict (for CSV rows: :func:`alpha_map_row` names their units)."""
    d = asdict(case)
    d["domain"] = f"{case.domain[0]}x{case.domain[1]}"
    return d


# alpha_map.csv: the unit of each key of a plate's record (case_record, measure_alpha, steps), SI,
# written into the column's name (``alpha_z`` -> ``alpha_z_N_m3``; docs/getting-started.md "CSV
# files"); "" = dimensionless, a count or text. The records keep the short keys; a map written
# before the units were in the names has them as its header, and :func:`read_alpha_map` reads both.
ALPHA_MAP_UNITS: dict[str, str] = {
    "beta": "rad", "gamma": "rad", "depth": "m", "plate_length": "m", "plate_thickness": "m", "speed": "m_s",
    "travel": "m", "cell_size": "m", "domain": "m", "bed_height": "m", "rho_c": "kg_m3", "mu_s": "", "mu_w": "",
    "youngs_modulus": "Pa", "contact": "", "contact_band_cells": "", "ramp_time": "s", "grid_offset": "cells",
    "fluidity_diameter": "m", "alpha_x": "N_m3", "alpha_z": "N_m3", "alpha_x_std": "N_m3", "alpha_z_std": "N_m3",
    "depth_mean": "m", "steps": "", "wall_s": "",
}  # fmt: skip
ALPHA_MAP_TEXT = ("contact", "domain")  # read back as text (domain: "WIDTHxHEIGHT" in m)
_ALPHA_MAP_KEYS = {f"{k}_{u}": k for k, u in ALPHA_MAP_UNITS.items() if u}


def alpha_map_column(key: str) -> str:
    """The ``alpha_map.csv`` column of a record key: with its unit (``beta`` -> ``beta_rad``)."""
    unit = ALPHA_MAP_UNITS.get(key, "")
    return f"{key}_{unit}" if unit else key


def alpha_map_key(column: str) -> str:
    """The record key of an ``alpha_map.csv`` column, with its unit (``alpha_z_N_m3``) or, in a map
    written before the units were in the names, without (``alpha_z``): ``alpha_z`` either way."""
    return _ALPHA_MAP_KEYS.get(column, column)


def alpha_map_row(record: dict) -> dict:
    """A plate's record (short keys) under its ``alpha_map.csv`` column names (:func:`alpha_map_column`)."""
    return {alpha_map_column(k): v for k, v in record.items()}


def read_alpha_map(path) -> dict[str, np.ndarray]:
    """An ``alpha_map.csv`` (``intrusim mpm references``, ``examples/mpm_rft_map.py run``) as one array
    per column keyed by the records' short keys (``beta``, ``gamma`` rad, ``alpha_x``, ``alpha_z``
    N/m^3 ...), whether its header names the units or not (maps written before): floats (an empty
    cell NaN), :data:`ALPHA_MAP_TEXT` as text. An InputError if the file is missing or has no rows."""
    import csv
    from pathlib import Path

    path = Path(path)
    try:
        with path.open(newline="") as f:
            rows = list(csv.DictReader(f))
    except FileNotFoundError:
        raise InputError(f"{path}: no such file (an RFT map's alpha_map.csv)") from None
    if not rows:
        raise InputError(f"{path} holds no plates")
    out: dict[str, np.ndarray] = {}
    for column in rows[0]:
        key = alpha_map_key(column)
        cells = [r[column] or "" for r in rows]
        if key in ALPHA_MAP_TEXT:
            out[key] = np.array(cells, dtype=object)
        else:
            out[key] = np.array([float(c) if c.strip() else np.nan for c in cells])
    return out
