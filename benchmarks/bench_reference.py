"""Benchmark: what a settled reference point of the Table S1 wheel costs, today's route against the
reference route (``--preset reference``), timed in one run and extrapolated to a settled point.

* ``today``: the route that converges today (docs/convergence.md): the nonlocal law (3 mm grains)
  at 1.25 mm cells in the paper's box (1 m x 1 m, bed 0.3 m), from rest;
* ``reference``: :func:`~intrusim.scenarios.mpm_locomotion.reference_settings` (1.2 mm cells, a
  fifth of the 6 mm grousers; 3 mm grains; a 0.72 m box on a treadmill, bed 0.15 m);
* ``reference, E/4``: the same with a 4x softer numerical stiffness (half the steps; it moves the
  answer by about 3 %, docs/convergence.md), shown as a lever, not the route's default.

Each set-up places the wheel, steps ``--warmup`` times, then the set-ups take turns for
``--rounds`` rounds of ``--steps`` steps (best round each). A set-up's cost per simulated second
is its seconds per step over dt; a settled point is that times the settling time, taken the same
for all (``--settle-s``, default 7 s: the 30 RPM wheel levels off after about 3 s at 2.5 mm, plus
the settle test's two revolutions of 2 s): so the ratio is the per-simulated-second ratio.

    python benchmarks/bench_reference.py --threads 2
"""

import argparse
import time

from bench_mpm import alternate_rounds  # noqa: E402  (run from benchmarks/ or with it on sys.path)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--steps", type=int, default=10, help="steps per round")
    ap.add_argument("--rounds", type=int, default=2)
    ap.add_argument("--warmup", type=int, default=20, help="steps before timing (the wheel into the bed)")
    ap.add_argument("--settle-s", type=float, default=7.0, help="simulated seconds to a settled point")
    ap.add_argument("--omega-rpm", type=float, default=30.0)
    args = ap.parse_args()
    from intrusim.mpm.backend import ensure_initialized
    from intrusim.mpm.solver import Solver
    from intrusim.scenarios import grousered_wheel_scenario
    from intrusim.scenarios.mpm_locomotion import mpm_config, paper_settings, reference_settings
    from intrusim.scenarios.mpm_settings import apply_settings

    ensure_initialized("cpu", "f32", args.threads)
    wheel = grousered_wheel_scenario()
    today = apply_settings(paper_settings("wheel"), [("fluidity_diameter", 3e-3), ("cell_size", 0.00125)])
    ref = reference_settings(wheel)
    setups = {
        "today": today,
        "reference": ref,
        "reference, E/4": ref.validated_copy(youngs_modulus=ref.youngs_modulus / 4),
    }
    solvers = {}
    for name, s in setups.items():
        t0 = time.perf_counter()
        solver = Solver(mpm_config(wheel, s.validated_copy(cpu_threads=args.threads), args.omega_rpm, None))
        for _ in range(args.warmup):
            solver.step()
        solvers[name] = solver
        print(f"{name}: {s.cells[0]} x {s.cells[1]} cells of {s.h * 1e3:.3g} mm, {solver.particles.n} points, "
              f"dt {solver.dt * 1e6:.3g} us (set up and {args.warmup} steps in {time.perf_counter() - t0:.0f} s)",
              flush=True)  # fmt: skip
    best = alternate_rounds(solvers, args.steps, args.rounds)
    base = best["today"] / solvers["today"].dt
    for name, solver in solvers.items():
        per_s = best[name] / solver.dt  # wall seconds per simulated second
        print(f"{name}: {best[name] * 1e3:.1f} ms/step, {per_s / 3600:.2f} h per simulated second, a settled point "
              f"({args.settle_s:g} s) {per_s * args.settle_s / 3600:.1f} h on {args.threads} threads; "
              f"today / this {base / per_s:.2f}x", flush=True)  # fmt: skip


if __name__ == "__main__":
    main()
