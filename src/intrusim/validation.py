"""Checks of the input shared by every entry point (files and command-line flags alike).

- :func:`reject_bool_numbers`: a pydantic "before" validator: ``true`` / ``false`` are not numbers
  (pydantic would read ``t_end = true`` as 1.0 s);
- :func:`polygon_problem`: a polygon must be simple (no self-crossing), of positive area, with
  finite vertices (shapely);
- :func:`check_mpm_geometry`: every body, obstacle and bed polygon of an MPM configuration lies
  inside the box [0, Lx] x [0, Lz] (not above its open top, not through a wall);
- :func:`check_run_size`: the grid's cells and the run's steps (t_end / dt), estimated before any
  compute, stay below limits the user can raise (``time.max_steps``), so that a huge spin, a tiny
  cfl or dt, or a cell of a nanometre is refused at once instead of running for ever.
"""

from __future__ import annotations

import math
from typing import Any, get_args

import numpy as np

from intrusim.errors import InputError

MAX_CELLS = 50_000_000  # grid cells nx * nz: ~ 10 GB of grid copies and points beyond it
TOUCH = 1e-9  # relative tolerance of "inside the box" (a body may rest on a wall or the floor)


def _admits_bool(annotation: Any) -> bool:
    if annotation is bool:
        return True
    return any(_admits_bool(a) for a in get_args(annotation))


def _has_bool(value: Any) -> bool:
    if isinstance(value, bool):
        return True
    if isinstance(value, (list, tuple)):
        return any(_has_bool(v) for v in value)
    return False


def reject_bool_numbers(cls: Any, data: Any) -> Any:
    """``model_validator(mode="before")`` body: refuse true/false given for a number field."""
    if isinstance(data, dict):
        for name, value in data.items():
            field = cls.model_fields.get(name) if isinstance(name, str) else None
            if field is not None and _has_bool(value) and not _admits_bool(field.annotation):
                raise ValueError(f"{name} must be a number, not true/false (got {value!r})")
    return data


def polygon_problem(vertices: Any) -> str | None:
    """Why ``vertices`` (N x 2, m) is not a usable polygon, or None: at least 3 finite vertices,
    simple (no edge crosses another), positive area."""
    from shapely.geometry import Polygon
    from shapely.validation import explain_validity

    v = np.asarray(vertices, dtype=float)
    if v.ndim != 2 or v.shape[1] != 2 or len(v) < 3:
        return f"needs at least 3 (x, z) vertices, got shape {v.shape}"
    if not np.all(np.isfinite(v)):
        return "has a non-finite vertex"
    poly = Polygon(v)
    scale = max(float(np.ptp(v[:, 0])), float(np.ptp(v[:, 1])))
    if not scale > 0 or not poly.area > 1e-12 * scale * scale:
        return f"has zero area (area {poly.area:.3g} m^2)"
    if not poly.is_valid:  # e.g. a self-intersection ("bow tie")
        return f"is not a simple polygon ({explain_validity(poly)})"
    return None


def world_polygon(vertices: Any, x: float, z: float, theta: float) -> np.ndarray:
    """Body-frame ``vertices`` rotated by ``theta`` (ccw) and moved to (x, z)."""
    v = np.asarray(vertices, dtype=float)
    c, s = math.cos(theta), math.sin(theta)
    return np.column_stack([x + c * v[:, 0] - s * v[:, 1], z + s * v[:, 0] + c * v[:, 1]])


def outside_box(v: np.ndarray, lx: float, lz: float) -> str | None:
    """How the polygon ``v`` leaves the box [0, lx] x [0, lz], or None."""
    tol = TOUCH * max(lx, lz)
    lo, hi = v.min(axis=0), v.max(axis=0)
    if lo[0] < -tol or hi[0] > lx + tol:
        return f"crosses a side wall (x from {lo[0]:.4g} to {hi[0]:.4g} m; box 0 to {lx:g} m)"
    if lo[1] < -tol:
        return f"crosses the floor (lowest z {lo[1]:.4g} m)"
    if hi[1] > lz + tol:
        return f"reaches above the top of the box (highest z {hi[1]:.4g} m; top {lz:g} m)"
    return None


def check_mpm_geometry(cfg: Any) -> None:
    """Raise ValueError naming the first bad polygon of an MPMConfig (intruders in their initial
    pose, obstacles, bed polygons): not simple, zero area, or not inside the box."""
    lx, lz = cfg.domain.size
    if cfg.contact_band_cells > min(cfg.domain.cells):  # every node would be in contact: the body fills the box
        raise ValueError(
            f"contact_band_cells: {cfg.contact_band_cells:g} cells is wider than the grid "
            f"({cfg.domain.cells[0]} x {cfg.domain.cells[1]} cells)"
        )
    items = [(f"intruders.{k}.vertices", ic.vertices, (ic.x, ic.z, ic.theta)) for k, ic in enumerate(cfg.intruders)]
    items += [(f"obstacles.{k}.vertices", o.vertices, None) for k, o in enumerate(cfg.obstacles)]
    items += [(f"bed.polygons.{k}", p, None) for k, p in enumerate(cfg.bed.polygons)]
    for name, vertices, pose in items:
        problem = polygon_problem(vertices)
        if problem is None:
            world = world_polygon(vertices, *pose) if pose is not None else np.asarray(vertices, dtype=float)
            problem = outside_box(world, lx, lz)
            if problem is not None and pose is not None:
                problem = f"at x={pose[0]:g}, z={pose[1]:g} " + problem
        if problem is not None:
            raise ValueError(f"{name}: the polygon {problem}")


def check_run_size(cfg: Any, dt: float) -> None:
    """Refuse (InputError) an MPM run whose grid or step count is beyond reach, before any compute:
    nx nz > MAX_CELLS, or t_end / dt > ``time.max_steps``."""
    nx, nz = cfg.domain.cells
    if nx * nz > MAX_CELLS:
        raise InputError(
            f"domain.cells: {nx} x {nz} = {nx * nz:.3g} cells is more than {MAX_CELLS:.3g} "
            f"(cell size {cfg.domain.h:.3g} m); use larger cells"
        )
    if not (math.isfinite(dt) and dt > 0):
        raise InputError(f"time step: dt = {dt!r} s (check material.youngs_modulus, time.cfl, the bodies' speeds)")
    steps = cfg.time.t_end / dt
    if steps > cfg.time.max_steps:
        raise InputError(
            f"time.t_end: {cfg.time.t_end:g} s at dt = {dt:.3g} s is {steps:.3g} steps, more than "
            f"time.max_steps = {cfg.time.max_steps:.3g} (dt is set by the cell size, time.cfl, "
            f"time.dt and the fastest body: a spin or speed this large, or a cfl or dt this small, "
            f"would run for ever); raise time.max_steps (--max-steps, or --set max_steps=N on mpm steady/sweep) to run it anyway"
        )
