"""Plate drag (Fig 6) against the distance dragged: is the MPM's lambda a start-up transient?

The Fig 6 runs average the drag over the second half of 0.04 m of travel. This script drags the
same 16 mm plate at one depth (default 30 mm) much further (default 0.16 m, in a 0.45 m box so the
wedge ahead stays clear of the far wall) and reports the mean drag per metre over windows of
travel, and for each faster speed the lambda of the excess over the slowest run,

    lambda = (F(v) - F(v_slow)) / (rho A (v^2 - v_slow^2)),   A = plate length x 1 m,

window by window (research/notes/results_log.md, "Fig 6A: plate drag"). Each run is cached as JSON under --out.

    python research/plate_drag_travel.py --band 1                      # ~3 min on 2 cores
    python research/plate_drag_travel.py --band 0 --youngs-modulus 4e6 # ~6 min
    python research/plate_drag_travel.py --band 0 --speeds 0.04 0.16 0.64 --travel 0.08 \
        --windows 0.02 0.04 0.08 --cfl 0.15 --flip 1   # the time step and the transfer (docs/mpm.md)
    python research/plate_drag_travel.py --band 0 --speeds 0.04 0.16 0.64 --travel 0.08 \
        --windows 0.02 0.04 0.08 --flip 1 --shape linear   # mpm-2d's shape functions
"""

from __future__ import annotations

import argparse
import csv
from pathlib import Path

import numpy as np

from intrusim.mpm.config import SHAPES

PLATE_RHO, PLATE_LENGTH = 900.0, 0.016  # Fig 6: rho 900 kg/m^3, 16 mm plate


def window_means(x: np.ndarray, force: np.ndarray, edges: np.ndarray) -> np.ndarray:
    """Mean of ``force`` over each travel window (edges[i], edges[i + 1]]; NaN for an empty one."""
    x, force, edges = (np.asarray(a, float) for a in (x, force, edges))
    if x.shape != force.shape or edges.ndim != 1 or len(edges) < 2 or np.any(np.diff(edges) <= 0):
        raise ValueError("x and force must have one shape, and edges must rise (at least two)")
    out = np.full(len(edges) - 1, np.nan)
    for i, (a, b) in enumerate(zip(edges[:-1], edges[1:])):
        sel = (x > a) & (x <= b)
        if sel.any():
            out[i] = force[sel].mean()
    return out


def excess_lambda(
    f_fast: np.ndarray,
    f_slow: np.ndarray,
    v_fast: float,
    v_slow: float,
    rho: float = PLATE_RHO,
    area: float = PLATE_LENGTH,
) -> np.ndarray:
    """lambda of the drag excess of a faster run over the slowest: dF / (rho A (v^2 - v_slow^2))."""
    if not v_fast > v_slow > 0:
        raise ValueError(f"need v_fast > v_slow > 0, got {v_fast} and {v_slow}")
    return (np.asarray(f_fast, float) - np.asarray(f_slow, float)) / (rho * area * (v_fast**2 - v_slow**2))


def _step_tag(args: argparse.Namespace) -> str:
    """The time step's and the transfer's part of a file name (empty for the defaults)."""
    return (
        ("" if args.cfl == 0.3 else f"_cfl{args.cfl:g}")
        + ("" if args.flip == 0 else f"_flip{args.flip:g}")
        + ("" if args.shape == "quadratic" else f"_{args.shape}")
    )


def run_one(speed: float, args: argparse.Namespace) -> dict:
    """One drag run (cached): time, travel and drag per metre at each record."""
    from intrusim.mpm.io import cached_json
    from intrusim.mpm.plate import PlateDragCase
    from intrusim.mpm.solver import Solver

    h = args.cell_mm * 1e-3
    tag = (
        f"d{args.depth_mm:g}mm_v{speed:g}_travel{args.travel:g}m_band{args.band:g}_E{args.youngs_modulus:g}"
        f"_h{args.cell_mm:g}mm{_step_tag(args)}"
    )

    def run() -> dict:
        domain = (0.45, 0.15)
        case = PlateDragCase(depth=args.depth_mm * 1e-3, speed=speed, travel=args.travel, domain=domain,
                             cells=(round(domain[0] / h), round(domain[1] / h)), contact_band_cells=args.band,
                             youngs_modulus=args.youngs_modulus, cfl=args.cfl, flip=args.flip, shape=args.shape)  # fmt: skip
        rows = Solver(case.config(cpu_threads=args.threads)).run()
        t = np.array([r["time"] for r in rows])
        return {"speed": speed, "time": t.tolist(), "travel": (speed * t).tolist(),
                "drag": (-np.array([r["fx"] for r in rows])).tolist()}  # fmt: skip

    return cached_json(Path(args.out) / f"{tag}.json", run)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument(
        "--speeds", type=float, nargs="+", default=[0.04, 0.16, 0.32, 0.64], help="m/s; the first is the slow reference"
    )
    ap.add_argument("--depth-mm", type=float, default=30.0, help="plate centre depth, mm (Fig 6: 20, 30, 40)")
    ap.add_argument("--travel", type=float, default=0.16, help="distance dragged, m (Fig 6 runs: 0.04)")
    ap.add_argument(
        "--windows", type=float, nargs="+", default=[0.02, 0.04, 0.08, 0.12, 0.16], help="travel window edges, m"
    )
    ap.add_argument("--band", type=float, default=1.0, help="contact band, cells")
    ap.add_argument("--cell-mm", type=float, default=2.5)
    ap.add_argument("--youngs-modulus", type=float, default=1.0e6, help="Pa")
    ap.add_argument("--cfl", type=float, default=0.3, help="C in dt = C h sqrt(rho / E) (default 0.3, as every run)")
    ap.add_argument(
        "--flip", type=float, default=0.0, help="FLIP's share of the velocity update, 0-1 (default 0: APIC)"
    )
    ap.add_argument(
        "--shape",
        choices=SHAPES,
        default="quadratic",
        help="shape functions of the transfers (default quadratic; linear: mpm-2d's, with --flip 1)",
    )
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("--out", default="runs/plate-travel")
    args = ap.parse_args()
    speeds = sorted(args.speeds)
    edges = np.array(args.windows)
    if len(speeds) < 2 or speeds[0] <= 0 or len(set(speeds)) != len(speeds):
        ap.error("--speeds: at least two different positive speeds")
    if len(edges) < 2 or np.any(np.diff(edges) <= 0) or edges[0] < 0 or edges[-1] > args.travel:
        ap.error("--windows: rising edges within [0, --travel]")
    if not (
        0 < args.depth_mm
        and args.cell_mm > 0
        and args.band >= 0
        and args.youngs_modulus > 0
        and args.threads >= 1
        and 0 < args.cfl <= 1
        and 0 <= args.flip <= 1
    ):
        ap.error(
            "--depth-mm, --cell-mm and --youngs-modulus must be positive, --band >= 0, --threads >= 1, "
            "0 < --cfl <= 1, 0 <= --flip <= 1"
        )

    means = {v: window_means(np.array(d["travel"]), np.array(d["drag"]), edges)
             for v, d in ((v, run_one(v, args)) for v in speeds)}  # fmt: skip
    out = Path(args.out)
    travel = "" if args.travel == 0.16 else f"{args.travel:g}m"  # the default travel is left out of the name
    stem = f"plate_drag_travel{travel}_band{args.band:g}_E{args.youngs_modulus:g}_h{args.cell_mm:g}mm{_step_tag(args)}"
    csv_path, png_path = out / f"{stem}.csv", out / f"{stem}.png"  # not with_suffix: "2.5mm" has a dot
    labels = [f"{a:g}-{b:g} m" for a, b in zip(edges[:-1], edges[1:])]
    with csv_path.open("w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["speed_m_s", "quantity", *labels])
        for v in speeds:
            w.writerow([v, "drag_N_per_m", *(f"{x:.3f}" for x in means[v])])
        for v in speeds[1:]:
            w.writerow([v, "lambda", *(f"{x:.3f}" for x in excess_lambda(means[v], means[speeds[0]], v, speeds[0]))])
    print(f"band {args.band:g}, E {args.youngs_modulus:g} Pa, {args.cell_mm:g} mm cells, depth {args.depth_mm:g} mm;"
          f" drag per metre (N/m) over the travel windows {', '.join(labels)}:")  # fmt: skip
    for v in speeds:
        print(f"  v = {v:5.2f} m/s: " + "  ".join(f"{x:6.2f}" for x in means[v]))
    for v in speeds[1:]:
        lam = excess_lambda(means[v], means[speeds[0]], v, speeds[0])
        print(f"  lambda at {v:4.2f} m/s: " + "  ".join(f"{x:6.2f}" for x in lam))

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(5.2, 3.6))
    mid = 0.5 * (edges[:-1] + edges[1:])
    for v in speeds:
        ax.plot(mid * 1e3, means[v], "o-", label=f"v = {v:g} m/s")
    ax.set(xlabel="travel (mm, window centre)", ylabel="drag per metre (N/m)")
    ax.set_title(
        f"16 mm plate at {args.depth_mm:g} mm, band {args.band:g}, E {args.youngs_modulus:g} Pa, C {args.cfl:g}, FLIP {args.flip:g}, {args.shape}",
        fontsize=8,
    )
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(png_path, dpi=130)
    print(f"wrote {csv_path} and {png_path}")


if __name__ == "__main__":
    main()
