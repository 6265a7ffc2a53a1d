"""Locomotion benchmark: one wheel steady state and a 9-point omega sweep, vs an explicit NumPy baseline.

Run:  python benchmarks/bench_locomotion.py [--repeat N]

* "implicit (Numba)": the package path, run_steady / sweep_omega(parallel=False) on ONE core:
  backward Euler + modified Newton, dt = min(10 ms, revolution / 100), compiled force kernel.
* "explicit NumPy baseline": forward Euler with dt = 1 ms and the vectorised NumPy force path
  (``model.wrench_numpy``), same scenario, same duration, same steady-state window.

Targets (issue): >= 1000x real time for one steady state; 9-point sweep (10-90 RPM) < 1 s.
"""

from __future__ import annotations

import argparse
import platform
import time

import numpy as np

from intrusim.analysis.steady import run_steady, steady_state
from intrusim.analysis.sweep import sweep_omega
from intrusim.bodies import IntegratorSettings, simulate
from intrusim.kinematics import BodyState
from intrusim.scenarios import get_scenario

BASELINE_DT = 1e-3  # s


def best_of(fn, repeat):
    times, out = [], None
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - t0)
    return min(times), out


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--kind", default="drft")
    ap.add_argument("--omega-rpm", type=float, default=30.0)
    a = ap.parse_args()
    wheel = get_scenario("wheel")
    run_steady(wheel, a.kind, 10.0)  # warm-up: load the compiled kernel

    t_one, st = best_of(lambda: run_steady(wheel, a.kind, a.omega_rpm), a.repeat)
    sim_one = float(st.trajectory.t[-1])
    rpm = np.arange(10.0, 91.0, 10.0)
    t_sweep, res = best_of(lambda: sweep_omega(wheel, a.kind, rpm, parallel=False, progress=False), a.repeat)
    sim_sweep = sum(
        float(run_steady(wheel, a.kind, w).trajectory.t[-1]) for w in rpm
    )  # simulated seconds of the sweep

    # explicit NumPy baseline over the same simulated time
    model, shape, drive = wheel.build_model(a.kind), wheel.rft_shape(), wheel.drive(a.omega_rpm)

    def numpy_force(x, z, th, vx, vz, om):
        return tuple(model.wrench_numpy(BodyState(x, z, th, vx, vz, om)).as_array())

    def baseline():
        tr = simulate(numpy_force, wheel.rigid_body(), drive, wheel.initial_state(shape), sim_one,
                      IntegratorSettings(dt=BASELINE_DT, scheme="explicit"))  # fmt: skip
        return steady_state(tr, shape, wheel.run.average_revolutions)

    t_base, st_base = best_of(baseline, 1)
    n_steps_one = len(st.trajectory.t) - 1
    evals = None
    print(f"# bench_locomotion: wheel (Table S1), {a.kind}, {platform.processor() or platform.machine()}, 1 core, best of {a.repeat}")
    print(f"{'case':<38} | {'wall s':>8} | {'sim s':>7} | {'sim/wall':>9} | {'v m/s':>7} | {'sink mm':>7} | note")
    print(f"{'steady state ' + format(a.omega_rpm, 'g') + ' RPM, implicit (Numba)':<38} | {t_one:8.4f} | {sim_one:7.2f} | "
          f"{sim_one / t_one:9.0f} | {st.velocity:7.4f} | {st.sinkage * 1e3:7.2f} | dt = {st.meta['dt'] * 1e3:g} ms, {n_steps_one} steps")
    print(f"{'9-pt sweep 10-90 RPM, implicit (Numba)':<38} | {t_sweep:8.4f} | {sim_sweep:7.2f} | {sim_sweep / t_sweep:9.0f} | "
          f"{'':>7} | {'':>7} | serial, target < 1 s")
    print(f"{'steady state, explicit NumPy baseline':<38} | {t_base:8.4f} | {sim_one:7.2f} | {sim_one / t_base:9.0f} | "
          f"{st_base.velocity:7.4f} | {st_base.sinkage * 1e3:7.2f} | dt = {BASELINE_DT * 1e3:g} ms")
    print(f"speed-up of the package path over the baseline (one steady state): {t_base / t_one:.0f}x")
    print("sweep records:")
    print(res.table())
    del evals


if __name__ == "__main__":
    main()
