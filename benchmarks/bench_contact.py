"""Benchmark: the MPM step with the default contact at the body's surface against the band contact.

The paper's grousered wheel (Table S1, coupled, 60 RPM) on a bed of ~64k and ~160k points (5 mm
cells, 2 x 2 points per cell: beds 0.4 m and 1.0 m deep), the two contacts ("surface", the default;
"band" 1 cell, the default before it) in alternate rounds in one process, best round each:

    python benchmarks/bench_contact.py --threads 2
"""

import argparse

from bench_mpm import alternate_rounds  # noqa: E402  (run from benchmarks/ or with it on sys.path)

CASES = {"64k": ((1.0, 0.8), (200, 160), 0.4), "160k": ((1.0, 1.4), (200, 280), 1.0)}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--steps", type=int, default=40, help="steps per round")
    ap.add_argument("--rounds", type=int, default=3)
    args = ap.parse_args()
    from intrusim.mpm.backend import ensure_initialized
    from intrusim.mpm.solver import Solver
    from intrusim.scenarios import grousered_wheel_scenario
    from intrusim.scenarios.mpm_locomotion import mpm_config, paper_settings

    ensure_initialized("cpu", "f32", args.threads)
    for label, (domain, cells, bed) in CASES.items():
        solvers = {}
        for contact in ("surface", "band"):
            s = paper_settings("wheel").model_copy(
                update=dict(
                    domain=domain,
                    cells=cells,
                    bed_depth=bed,
                    contact=contact,
                    contact_band_cells=1.0,
                    cpu_threads=args.threads,
                )
            )
            solvers[contact] = Solver(mpm_config(grousered_wheel_scenario(), s, 60.0, None))
        for solver in solvers.values():  # the wheel into the bed first
            for _ in range(200):
                solver.step()
        best = alternate_rounds(solvers, args.steps, args.rounds)
        n = solvers["surface"].particles.n
        print(
            f"{label}: {n} points, {args.threads} threads: surface {best['surface'] * 1e3:.2f} ms/step, "
            f"band {best['band'] * 1e3:.2f} ms/step, ratio {best['surface'] / best['band']:.3f}",
            flush=True,
        )


if __name__ == "__main__":
    main()
