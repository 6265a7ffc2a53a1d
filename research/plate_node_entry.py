"""The RFT-map plate pushed down (beta 0, gamma 90) at three time steps, with each contact: why its
load moves with dt.

A plate pushed through the grid meets a new row of grid nodes every h / v. With the grid-node
contacts ("nodes", the default, and "band" at band 0) the load drops when a row enters the plate
and recovers over a few hundredths of a second; the mean alpha_z over the second half of the
travel (``intrusim.mpm.rft_map.measure_alpha``) carries those drops. This script runs the plate at
dt = C h sqrt(rho_c / E) for each C and each contact (and other plates with ``--plates``), writes
the mean alpha, its standard deviation, the depth of the deepest drop of the larger component
below the window's median, and a plot of the first plate's alpha(t)
(docs/convergence.md, "The RFT map's plates").

    python research/plate_node_entry.py --out docs/figures/plate_node_entry   # 5 mm cells, ~2 min on 1 core
    python research/plate_node_entry.py --cell-mm 2.5 --contacts nodes --cfl 0.3 0.15 \
        --plates '0,90 90,0 30,60 -60,60 0,0' --out runs/pne25                # 8 min
"""

from __future__ import annotations

import argparse
import csv
import math
from pathlib import Path

import numpy as np


def deepest_drop(t: np.ndarray, alpha: np.ndarray, window: tuple[float, float]) -> float:
    """How far the lowest alpha in the window (fractions of the run, as measure_alpha) lies below
    the window's median, as a fraction of that median."""
    from intrusim.mpm.rft_map import in_window

    t, alpha = np.asarray(t, float), np.asarray(alpha, float)
    sel = in_window(t, window)
    med = float(np.median(alpha[sel]))
    return (med - float(alpha[sel].min())) / med


def plate(text: str) -> tuple[float, float]:
    """'BETA,GAMMA' (degrees) as a pair of floats."""
    try:
        beta, gamma = (float(v) for v in text.split(","))
    except ValueError:
        raise argparse.ArgumentTypeError(f"a plate is BETA,GAMMA in degrees, got {text!r}") from None
    return beta, gamma


def plates(text: str) -> list[tuple[float, float]]:
    """'BETA,GAMMA BETA,GAMMA ...' (degrees) as pairs."""
    out = [plate(t) for t in text.split()]
    if not out:
        raise argparse.ArgumentTypeError("give at least one plate, BETA,GAMMA")
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--cell-mm", type=float, default=5.0)
    ap.add_argument("--cfl", type=float, nargs="+", default=[0.3, 0.15, 0.075])
    ap.add_argument("--contacts", nargs="+", default=["nodes", "band", "surface"])
    ap.add_argument("--out", type=Path, required=True, help="NAME: writes NAME.csv and NAME.png")
    ap.add_argument("--plates", type=plates, default=[(0.0, 90.0)],
                    help="'BETA,GAMMA ...' in degrees, one string (default '0,90': pushed down; "
                         "--plates='-60,60 0,90' when the first is negative); the plot shows the first")  # fmt: skip
    ap.add_argument("--threads", type=int, default=1)
    args = ap.parse_args()

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from intrusim.mpm.config import MPMConfig
    from intrusim.mpm.rft_map import PlateMapCase, alpha_history, measure_alpha
    from intrusim.mpm.solver import Solver

    h = args.cell_mm / 1e3
    rows_out = []
    fig, axes = plt.subplots(len(args.contacts), 1, figsize=(9, 2.6 * len(args.contacts)), sharex=True, squeeze=False)
    for ax, contact in zip(axes[:, 0], args.contacts):
        for n, (beta, gamma) in enumerate(args.plates):
            for cfl in args.cfl:
                case = PlateMapCase(beta=math.radians(beta), gamma=math.radians(gamma), cell_size=h,
                                    plate_thickness=max(0.005, 2 * h), contact=contact)  # fmt: skip
                data = case.config(cpu_threads=args.threads).model_dump()
                data["time"]["cfl"] = cfl
                rows = Solver(MPMConfig.model_validate(data)).run()
                a = measure_alpha(rows, case)
                comp = "z" if abs(a["alpha_z"]) >= abs(a["alpha_x"]) else "x"  # the larger component
                t, history, _ = alpha_history(rows, case)
                alpha = history[:, "xz".index(comp)]
                drop = deepest_drop(t, np.sign(a["alpha_" + comp]) * alpha, (0.5, 1.0))
                rows_out.append({"contact": contact, "cell_mm": args.cell_mm, "cfl": cfl, "beta_deg": beta,
                                 "gamma_deg": gamma, "alpha_x": round(a["alpha_x"], 1), "alpha_z": round(a["alpha_z"], 1),
                                 "alpha_x_std": round(a["alpha_x_std"], 1), "alpha_z_std": round(a["alpha_z_std"], 1),
                                 "component": comp, "deepest_drop": round(drop, 4)})  # fmt: skip
                print(f"{contact:8s} beta {beta:4g} gamma {gamma:4g} C {cfl:<6g} alpha_x {a['alpha_x'] / 1e3:7.1f} "
                      f"alpha_z {a['alpha_z'] / 1e3:7.1f} kN/m^3  alpha_{comp}: std {a[f'alpha_{comp}_std'] / 1e3:5.1f}, "
                      f"deepest drop {100 * drop:5.1f} % of the median", flush=True)  # fmt: skip
                if n == 0:  # the plot shows the first plate
                    late = t > 0.35 * t[-1]
                    ax.plot(t[late], alpha[late] / 1e3, lw=0.8, label=f"C {cfl:g}: mean {a['alpha_' + comp] / 1e3:.1f}")
        beta, gamma = args.plates[0]
        ax.set_title(f"contact {contact!r}, {args.cell_mm:g} mm cells, plate beta {beta:g} gamma {gamma:g}", fontsize=9)
        ax.set_ylabel("alpha (kN/m^3)")
        ax.legend(fontsize=7, loc="lower left")
    axes[-1, 0].set_xlabel("t (s)")
    fig.tight_layout()
    args.out.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(args.out.with_suffix(".png"), dpi=100)
    with args.out.with_suffix(".csv").open("w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows_out[0]))
        w.writeheader()
        w.writerows(rows_out)


if __name__ == "__main__":
    main()
