"""Benchmark (not in CI): a rough rigid strip footing's bearing capacity, as N_gamma, against theory.

A rigid strip footing of width B = 0.06 m, rough (grain-footing friction 5), is pushed down at
0.05 m/s into a bed of the Table S1 material (mu_s = 0.56, rho_c = 638 kg/m^3, E = 1 MPa) 3 B deep
and 7 B wide (``intrusim.mpm.footing.FootingCase``). q = F_z / B and N_gamma = q / (0.5 rho_c g B)
are averaged over settlement windows s / B; the theory's phi has sin(phi) = mu_s. The table gives
N_gamma at each number of cells across the footing and time step (dt = the stable limit, dt / 2),
then Hansen's, Vesic's and Martin's (2005, exact, rough footing, associated flow) values.

    python benchmarks/footing.py                          # 10 and 20 cells, dt
    python benchmarks/footing.py --cells 10,20,40 --dt-halving --threads 2
    python benchmarks/footing.py --contact band           # the band contact, for comparison
"""

import argparse
import math
import time

from intrusim.mpm.footing import (
    FootingCase,
    n_gamma_at,
    n_gamma_hansen,
    n_gamma_martin,
    n_gamma_vesic,
)
from intrusim.mpm.solver import Solver, time_step_limits

WINDOWS = ((0.02, 0.04), (0.04, 0.08), (0.08, 0.1))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--cells", default="10,20", help="cells across the footing, comma separated")
    ap.add_argument("--dt-halving", action="store_true", help="also run each at dt / 2")
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("--contact", default="surface", choices=("surface", "band"))
    ap.add_argument("--band", type=float, default=1.0, help="contact band, cells (--contact band)")
    args = ap.parse_args()
    cells = [int(c) for c in args.cells.split(",")]
    header = (
        "| cells across | dt (s) | "
        + " | ".join(f"N_gamma, s/B {a:g}-{b:g}" for a, b in WINDOWS)
        + " | points | wall (s) |"
    )
    print(header)
    print("|" + "---|" * (header.count("|") - 1))
    case = None
    for c in cells:
        case = FootingCase(cells_across=c, contact=args.contact, contact_band_cells=args.band)
        limits = time_step_limits(case.config())
        dt0 = min(limits["dt_elastic"], limits["dt_motion"])
        for dt in [dt0, dt0 / 2] if args.dt_halving else [dt0]:
            case = FootingCase(cells_across=c, contact=args.contact, contact_band_cells=args.band, dt=dt)
            t0 = time.perf_counter()
            solver = Solver(case.config(cpu_threads=args.threads))
            rows = solver.run()
            wall = time.perf_counter() - t0
            ng = [n_gamma_at(case, rows, w) for w in WINDOWS]
            print(
                f"| {c} | {dt:.3g} | " + " | ".join(f"{v:.1f}" for v in ng) + f" | {solver.particles.n} | {wall:.0f} |",
                flush=True,
            )
    phi = math.asin(case.mu_s)
    print(
        f"\nphi = asin({case.mu_s}) = {math.degrees(phi):.2f} deg: N_gamma Hansen {n_gamma_hansen(phi):.1f}, "
        f"Vesic {n_gamma_vesic(phi):.1f}, Martin (exact, rough) {n_gamma_martin(phi):.1f}"
    )


if __name__ == "__main__":
    main()
