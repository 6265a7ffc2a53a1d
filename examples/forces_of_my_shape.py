"""RFT and DRFT forces on your own shape: a polygon in the body frame, pushed through the bed.

    python examples/forces_of_my_shape.py --out runs/my_shape

The shape is a 30 x 60 mm wedge foot, 50 mm wide (edit ``FOOT``); it moves forward at 0.3 m/s while
its tip sinks from 5 to 40 mm. Quasistatic RFT (Eq. 3) and DRFT's inertial term (Eq. 4, lambda 1)
give the drag Fx and lift Fz; the table goes to the terminal and OUT/forces.csv.
"""

from __future__ import annotations

import argparse
import csv
from pathlib import Path

import numpy as np

from intrusim.forces import make_force_model
from intrusim.geometry import polygon_shape
from intrusim.kinematics import BodyState

FOOT = [(-0.03, 0.0), (0.03, 0.0), (0.0, -0.06)]  # (x, z) vertices, m: a downward wedge


def main(argv: list[str] | None = None) -> list[dict]:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--speed", type=float, default=0.3, help="forward speed, m/s")
    ap.add_argument("--depths-mm", default="5,10,20,40", help="tip depths below the surface, mm")
    ap.add_argument("--out", type=Path, default=None, help="folder for forces.csv")
    args = ap.parse_args(argv)
    foot = polygon_shape(FOOT, width=0.05, name="wedge foot")
    models = {kind: make_force_model(kind, foot) for kind in ("rft", "drft-inertial")}
    rows = []
    for depth in (float(d) * 1e-3 for d in args.depths_mm.split(",")):
        state = BodyState(0.0, 0.06 - depth, 0.0, args.speed, 0.0, 0.0)  # x, z, theta, vx, vz, omega
        for kind, model in models.items():
            w = model.wrench(state)
            rows.append({"depth_mm": depth * 1e3, "model": kind, "fx_N": w.fx, "fz_N": w.fz, "moment_Nm": w.moment})
    print(f"{'depth mm':>8} | {'model':>13} | {'Fx N':>8} | {'Fz N':>8}")
    for r in rows:
        print(f"{r['depth_mm']:8.1f} | {r['model']:>13} | {r['fx_N']:8.3f} | {r['fz_N']:8.3f}")
    if args.out is not None:
        args.out.mkdir(parents=True, exist_ok=True)
        with (args.out / "forces.csv").open("w", newline="") as f:
            writer = csv.DictWriter(f, fieldnames=list(rows[0]))
            writer.writeheader()
            writer.writerows(rows)
    assert all(np.isfinite(r["fx_N"]) for r in rows)
    return rows


if __name__ == "__main__":
    main()
