"""Benchmark: the default MPM step of a body in the grains against the band contact and the former defaults.

The paper's grousered wheel (Table S1, coupled, 60 RPM) on a bed of ~64k and ~160k points (5 mm
cells, 2 x 2 points per cell: beds 0.4 m and 1.0 m deep), three set-ups in alternate rounds in one
process, best round each:

* ``default``: the contact "nodes" (the grid nodes inside the body projected, the points at its
  surface corrected), FLIP with a PIC share that falls with dt (the defaults),
* ``surface``: the contact "surface" (the points at the body's surface enforced on the grid by 8
  serial sweeps, the default before "nodes") with the default transfer,
* ``band``: the band contact (1 cell) with the default transfer,
* ``former``: the band contact (1 cell) with APIC (``flip = 0``), the defaults before these two.

``--write docs/performance.md`` also replaces that file's ``bench_contact`` table (between its markers).

    python benchmarks/bench_contact.py --threads 2 --write docs/performance.md

"""

import argparse

from _doc_tables import check_markers, machine_line, write_between
from bench_mpm import alternate_rounds  # noqa: E402  (run from benchmarks/ or with it on sys.path)

CASES = {"64k": ((1.0, 0.8), (200, 160), 0.4), "160k": ((1.0, 1.4), (200, 280), 1.0)}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--steps", type=int, default=40, help="steps per round")
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--write", default=None, help="replace this markdown file's bench_contact table")
    args = ap.parse_args()
    if args.write is not None:
        check_markers(args.write, "bench_contact")  # before measuring
    from intrusim.mpm.backend import ensure_initialized
    from intrusim.mpm.solver import Solver
    from intrusim.scenarios import grousered_wheel_scenario
    from intrusim.scenarios.mpm_locomotion import mpm_config, paper_settings

    ensure_initialized("cpu", "f32", args.threads)
    doc = [
        "| bed | points | default (ms/step) | contact surface | band contact | former defaults | default / band | default / former |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for label, (domain, cells, bed) in CASES.items():
        solvers = {}
        for name, contact, flip in (
            ("default", "nodes", None),
            ("surface", "surface", None),
            ("band", "band", None),
            ("former", "band", 0.0),
        ):
            s = paper_settings("wheel").validated_copy(
                domain=domain,
                cells=cells,
                bed_depth=bed,
                contact=contact,
                contact_band_cells=1.0,
                flip=flip,
                cpu_threads=args.threads,
            )
            solvers[name] = Solver(mpm_config(grousered_wheel_scenario(), s, 60.0, None))
        for solver in solvers.values():  # the wheel into the bed first
            for _ in range(200):
                solver.step()
        best = alternate_rounds(solvers, args.steps, args.rounds)
        n = solvers["default"].particles.n
        ms = ", ".join(f"{k} {v * 1e3:.2f}" for k, v in best.items())
        print(
            f"{label}: {n} points, {args.threads} threads: ms/step {ms}; default / band "
            f"{best['default'] / best['band']:.3f}, default / former {best['default'] / best['former']:.3f}",
            flush=True,
        )
        doc.append(
            f"| {label} | {n} | {best['default'] * 1e3:.2f} | {best['surface'] * 1e3:.2f} | {best['band'] * 1e3:.2f} | "
            f"{best['former'] * 1e3:.2f} | "
            f"{best['default'] / best['band']:.2f}x | {best['default'] / best['former']:.2f}x |"
        )
    if args.write is not None:
        write_between(args.write, "bench_contact", ["", *doc, "", machine_line(), ""])
        print(f"wrote the table into {args.write}")


if __name__ == "__main__":
    main()
