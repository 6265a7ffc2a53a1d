"""MPM plate intrusions: Fig 6A (horizontal drag, with the K|z| + lambda rho A v^2 fit) and
Fig S3B (vertical intrusion of a 0.16 m plate).

Each MPM run is kept as a small JSON under ``runs`` (default ``runs/plates`` or
``runs/plates-quick``) so a figure is re-plotted without re-running; a missing point is computed.

Measurements (forces per metre of width, plane strain):

* drag: the mean horizontal resistance over the second half of the drag (after the plate has
  moved ``travel / 2`` at full speed), with |z| the depth of the plate centre;
* vertical: the resistance F_z(t) at each recorded time, against the depth of the plate's lower
  face below the initial surface; the slowest run is the static part F_static(z) (the way the
  paper's Fig S2 extracts t_static from the slowest data) and lambda fits the excess of the
  faster runs, F - F_static = lambda rho A v^2, over depths >= ``min_depth``.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from intrusim.analysis.plates import fit_drag_law  # noqa: E402
from intrusim.figures._output import save_figure  # noqa: E402
from intrusim.mpm.io import cached_json  # noqa: E402

PAPER_DRAG = {"K": 580.0, "lambda": 1.1, "rho": 900.0, "length": 0.016}
PAPER_VERTICAL = {"lambda": 2.8, "rho": 2500.0, "length": 0.16, "mu": 0.62}
DRAG_DEPTHS = (0.02, 0.03, 0.04)
DRAG_SPEEDS = (0.04, 0.08, 0.16, 0.32, 0.64)
DRAG_SPEEDS_QUICK = (0.04, 0.16, 0.64)
VERTICAL_SPEEDS = (0.1, 0.5, 1.0, 2.0)
VERTICAL_SPEEDS_QUICK = (0.1, 1.0, 2.0)


def _root(runs: Path | None, quick: bool) -> Path:
    return Path(runs) if runs is not None else Path("runs") / ("plates-quick" if quick else "plates")


def drag_case(depth: float, speed: float, quick: bool):
    """The Fig 6 drag run: 2.5 mm cells (quick: 5 mm), 0.04 m of travel (quick 0.03 m)."""
    from intrusim.mpm.plate import PlateDragCase

    if quick:
        return PlateDragCase(depth=depth, speed=speed, travel=0.03, cells=(60, 30))
    return PlateDragCase(depth=depth, speed=speed, travel=0.04, cells=(120, 60))


def drag_points(quick: bool, runs: Path | None, progress: bool = True, vary=None) -> list[dict[str, float]]:
    """Steady drag force per metre of width at every (depth, speed) of Fig 6A.

    ``vary``: optional function applied to each run's :class:`PlateDragCase` (another cell size,
    contact band ...); give such runs their own ``runs`` folder, where each point is cached.
    """
    from tqdm import tqdm

    from intrusim.mpm.plate import steady_force
    from intrusim.mpm.solver import Solver

    speeds = DRAG_SPEEDS_QUICK if quick else DRAG_SPEEDS
    grid = [(d, v) for d in DRAG_DEPTHS for v in speeds]
    out = []
    for d, v in tqdm(grid, desc="MPM plate drag", disable=not progress):
        case = drag_case(d, v, quick)
        case = case if vary is None else vary(case)

        def run() -> dict[str, float]:
            rows = Solver(case.config()).run()
            return {
                "depth_m": d,
                "speed_m_s": v,
                "force_N_per_m": -steady_force(rows, "fx"),
                "lift_N_per_m": steady_force(rows, "fz"),
                "h_m": case.domain[0] / case.cells[0],
            }

        out.append(cached_json(_root(runs, quick) / f"drag_d{d * 1e3:.0f}mm_v{v:g}.json", run))
    return out


def drag_fit(pts: list[dict[str, float]]) -> tuple[float, float, float]:
    """K (N/m) and lambda of F = K|z| + lambda rho A v^2 over the points of :func:`drag_points`,
    and K of the slowest runs alone (F = K |z| through the origin)."""
    d, v, f = (np.array([p[k] for p in pts]) for k in ("depth_m", "speed_m_s", "force_N_per_m"))
    K, lam = fit_drag_law(d, v, f, PAPER_DRAG["rho"], PAPER_DRAG["length"])
    slow = v == v.min()
    return K, lam, float(np.sum(f[slow] * d[slow]) / np.sum(d[slow] ** 2))


def fig6a_mpm(
    out: Path, quick: bool = False, parallel: bool = True, runs: Path | None = None, mpm: bool = True
) -> list[Path]:
    """Fig 6A with MPM: drag vs speed at |z| = 20/30/40 mm, and the fit F = K|z| + lambda rho A v^2."""

    pts = drag_points(quick, runs)
    d, v, f = (np.array([p[k] for p in pts]) for k in ("depth_m", "speed_m_s", "force_N_per_m"))
    rho, area = PAPER_DRAG["rho"], PAPER_DRAG["length"]
    K, lam, K_slow = drag_fit(pts)
    fig, ax = plt.subplots(figsize=(5.2, 3.8))
    vv = np.linspace(0, v.max(), 100)
    rows = []
    for depth in DRAG_DEPTHS:
        sel = np.isclose(d, depth)
        (line,) = ax.plot(v[sel], f[sel], "o", label=f"MPM |z| = {depth * 1e3:.0f} mm")
        ax.plot(vv, K * depth + lam * rho * area * vv**2, ":", color=line.get_color())
        ax.plot(
            vv, PAPER_DRAG["K"] * depth + PAPER_DRAG["lambda"] * rho * area * vv**2, "-", lw=0.6, color=line.get_color()
        )
    for p in pts:
        rows.append({**p, "fit_K_N_per_m": K, "fit_lambda": lam, "slowest_K_N_per_m": K_slow,
                     "paper_K_N_per_m": PAPER_DRAG["K"], "paper_lambda": PAPER_DRAG["lambda"]})  # fmt: skip
    ax.set(xlabel="drag speed v (m/s)", ylabel="drag force per metre width (N/m)")
    ax.set_title(
        f"Fig 6A (MPM): fit K = {K:.0f} N/m, lambda = {lam:.2f}; dotted: fit, thin: paper (580, 1.1)", fontsize=7
    )
    ax.legend(fontsize=7)
    fig.tight_layout()
    return save_figure(fig, out, "fig6a_mpm", rows)


def vertical_case(speed: float, quick: bool):
    """The Fig S3B run: 0.16 m plate, rho 2500, mu 0.62; 5 mm cells (quick: 1 cm), 0.08 m travel."""
    from intrusim.mpm.plate import VerticalPlateCase

    if quick:
        return VerticalPlateCase(speed=speed, travel=0.06, cells=(80, 40))
    return VerticalPlateCase(speed=speed)


def vertical_series(quick: bool, runs: Path | None, progress: bool = True) -> list[dict[str, Any]]:
    """Resistance vs depth of the plate's lower face, one record per speed."""
    from tqdm import tqdm

    from intrusim.mpm.solver import Solver

    out = []
    for v in tqdm(VERTICAL_SPEEDS_QUICK if quick else VERTICAL_SPEEDS, desc="MPM vertical plate", disable=not progress):
        case = vertical_case(v, quick)

        def run() -> dict[str, Any]:
            rows = Solver(case.config()).run()
            z0 = rows[0]["z"]
            gap = z0 - case.plate_thickness / 2 - case.bed_height  # initial clearance above the surface
            depth = [z0 - r["z"] - gap for r in rows]
            return {
                "speed_m_s": v,
                "depth_m": depth,
                "force_N_per_m": [r["fz"] for r in rows],
                "time_s": [r["time"] for r in rows],
                "h_m": case.domain[0] / case.cells[0],
            }

        out.append(cached_json(_root(runs, quick) / f"vertical_v{v:g}.json", run))
    return out


def static_plus_inertial_lambda(
    series: list[dict[str, Any]], rho: float, area: float, min_depth: float
) -> tuple[float, np.ndarray, np.ndarray]:
    """lambda of F(z, v) = F_static(z) + lambda rho A v^2 with F_static the slowest run (as the paper's
    Fig S2 extracts t_static from the slowest data), least squares over depths >= ``min_depth``.

    Returns (lambda, depth grid, F_static on it)."""
    slow = min(series, key=lambda s: s["speed_m_s"])
    ds, fs = np.array(slow["depth_m"]), np.array(slow["force_N_per_m"])
    grid = np.linspace(min_depth, min(max(s["depth_m"]) for s in series), 40)
    f_static = np.interp(grid, ds, fs)
    num = den = 0.0
    for s in series:
        if s is slow:
            continue
        excess = np.interp(grid, s["depth_m"], s["force_N_per_m"]) - f_static
        q = rho * area * s["speed_m_s"] ** 2
        num += float(np.sum(excess * q))
        den += float(len(grid) * q * q)
    return (num / den if den > 0 else float("nan")), grid, f_static


def figs3b(
    out: Path,
    quick: bool = False,
    parallel: bool = True,
    runs: Path | None = None,
    mpm: bool = True,
    min_depth: float = 0.01,
) -> list[Path]:
    """Fig S3B: vertical plate intrusion (MPM); lambda of F = F_static(z) + lambda rho A v^2 (paper 2.8)."""

    series = vertical_series(quick, runs)
    rho, area = PAPER_VERTICAL["rho"], PAPER_VERTICAL["length"]
    lam, grid, f_static = static_plus_inertial_lambda(series, rho, area, min_depth)
    fig, ax = plt.subplots(figsize=(5.2, 3.8))
    rows = []
    for s in series:
        d, f, v = np.array(s["depth_m"]), np.array(s["force_N_per_m"]), s["speed_m_s"]
        (line,) = ax.plot(d * 1e3, f / 1e3, ".", ms=3, label=f"MPM v = {v:g} m/s")
        ax.plot(grid * 1e3, (f_static + lam * rho * area * v**2) / 1e3, ":", color=line.get_color())
        ax.plot(
            grid * 1e3,
            (f_static + PAPER_VERTICAL["lambda"] * rho * area * v**2) / 1e3,
            "-",
            lw=0.6,
            color=line.get_color(),
        )
        rows += [{"speed_m_s": v, "depth_m": di, "force_N_per_m": fi, "fit_lambda": lam, "paper_lambda": PAPER_VERTICAL["lambda"],
                  "h_m": s["h_m"]} for di, fi in zip(d, f)]  # fmt: skip
    ax.set(xlabel="depth of the plate's lower face (mm)", ylabel="resistance per metre width (kN/m)")
    ax.set_title(f"Fig S3B (MPM): F_static(z) + lambda rho A v^2, lambda = {lam:.2f} (dotted), paper 2.8 (thin)",
                 fontsize=7)  # fmt: skip
    ax.legend(fontsize=7)
    fig.tight_layout()
    return save_figure(fig, out, "figs3b", rows)
