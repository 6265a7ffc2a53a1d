"""Locomotion benchmark: one wheel steady state and a 9-point omega sweep, vs an explicit NumPy baseline.

Run:  python benchmarks/bench_locomotion.py [--repeat N] [--write docs/performance.md]

``--write`` also replaces that file's table between the markers ``<!-- bench_locomotion: begin -->``
/ ``<!-- bench_locomotion: end -->`` with the one just measured.

* "implicit, compiled loop": the package path, run_steady / sweep_omega(parallel=False) on ONE
  core: BDF2 + modified Newton at the default step (``RunConfig.dt``), the whole step loop
  compiled (Numba, ``intrusim._implicit_jit``): the elements are rotated once per step and every
  force evaluation of the step's Newton iteration reuses them (same numbers as the force kernel).
* "implicit, Python loop": the same scheme in the Python reference loop (run_steady(...,
  compiled=False)), calling the compiled kernel once per force evaluation.
* "explicit NumPy baseline": forward Euler with dt = 1 ms and the vectorised NumPy force path
  (``model.wrench_numpy``), same scenario, same duration, same steady-state window.

* ``--bulldozing K``: the cost of the bulldozing term (``laws.bulldozing``): the steady state
  with the term on at k_b = 1e-9 (the same trajectory) against off, interleaved, and the steady
  state at k_b = K (another, slower and deeper, wheel: its time per step is not the term's).

Targets (issue): >= 1000x real time for one steady state; 9-point sweep (10-90 RPM) < 1 s.
Every figure is the best of ``--repeat`` rounds (the development machine is shared); compare the
ratios, which are measured in the same run.
"""

from __future__ import annotations

import argparse
import os
import platform
import time

import numpy as np
from _doc_tables import check_markers, machine_line, write_between

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
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--kind", default="drft")
    ap.add_argument("--omega-rpm", type=float, default=30.0)
    ap.add_argument("--bulldozing", type=float, default=0.0, help="also time the steady state with this k_b")
    ap.add_argument("--write", type=str, default=None, help="replace this markdown file's bench_locomotion table")
    a = ap.parse_args()
    if a.write is not None:
        check_markers(a.write, "bench_locomotion")  # before measuring
    wheel = get_scenario("wheel")
    run_steady(wheel, a.kind, 10.0)  # warm-up: load the compiled kernel

    t_one, st = best_of(lambda: run_steady(wheel, a.kind, a.omega_rpm), a.repeat)
    # the integrator alone (no set-up, no steady-state analysis), same run
    m1, sh1, d1 = wheel.build_model(a.kind), wheel.rft_shape(), wheel.drive(a.omega_rpm)
    s1 = IntegratorSettings(dt=st.meta["dt"])
    t_int, _ = best_of(lambda: simulate(m1, wheel.rigid_body(), d1, wheel.initial_state(sh1),
                                        float(st.trajectory.t[-1]), s1), a.repeat)  # fmt: skip
    t_py, st_py = best_of(lambda: run_steady(wheel, a.kind, a.omega_rpm, compiled=False), a.repeat)
    sim_one = float(st.trajectory.t[-1])
    rpm = np.arange(10.0, 91.0, 10.0)
    t_sweep, res = best_of(lambda: sweep_omega(wheel, a.kind, rpm, parallel=False, progress=False), a.repeat)
    sim_sweep = sum(float(run_steady(wheel, a.kind, w).trajectory.t[-1]) for w in rpm)  # simulated seconds of the sweep

    # explicit NumPy baseline over the same simulated time
    model, shape, drive = wheel.build_model(a.kind), wheel.rft_shape(), wheel.drive(a.omega_rpm)

    def numpy_force(x, z, th, vx, vz, om):
        return tuple(model.wrench_numpy(BodyState(x, z, th, vx, vz, om)).as_array())

    def baseline():
        tr = simulate(numpy_force, wheel.rigid_body(), drive, wheel.initial_state(shape), sim_one,
                      IntegratorSettings(dt=BASELINE_DT, scheme="explicit"))  # fmt: skip
        return steady_state(tr, shape, wheel.run.average_revolutions)

    t_base, st_base = best_of(baseline, max(1, min(a.repeat, 2)))
    n_steps_one = len(st.trajectory.t) - 1
    n_iter = int(st.trajectory.iterations.sum())
    try:
        load = "load average %.1f %.1f %.1f" % os.getloadavg()
    except OSError:  # pragma: no cover
        load = "load average n/a"
    print(f"# bench_locomotion: wheel (Table S1), {a.kind}, {platform.processor() or platform.machine()}, "
          f"1 core, best of {a.repeat}; {os.cpu_count()} cores, {load}")  # fmt: skip
    print(f"{'case':<44} | {'wall s':>8} | {'sim s':>7} | {'sim/wall':>9} | {'v m/s':>7} | {'sink mm':>7} | note")
    rows = [
        (f"steady state {a.omega_rpm:g} RPM, implicit, compiled loop", t_one, sim_one, st,
         f"dt = {st.meta['dt'] * 1e3:g} ms, {n_steps_one} steps, {n_iter} Newton iterations"),
        (f"steady state {a.omega_rpm:g} RPM, implicit, Python loop", t_py, sim_one, st_py, "reference loop, same scheme"),
        ("9-pt sweep 10-90 RPM, implicit, compiled loop", t_sweep, sim_sweep, None, "serial, target < 1 s"),
        ("steady state, explicit NumPy baseline", t_base, sim_one, st_base, f"dt = {BASELINE_DT * 1e3:g} ms, wrench_numpy"),
    ]  # fmt: skip
    for name, t, sim, s_, note in rows:
        v = f"{s_.velocity:7.4f}" if s_ is not None else f"{'':>7}"
        sk = f"{s_.sinkage * 1e3:7.2f}" if s_ is not None else f"{'':>7}"
        print(f"{name:<44} | {t:8.4f} | {sim:7.2f} | {sim / t:9.0f} | {v} | {sk} | {note}")
    print(
        f"one steady state: {sim_one / t_one:.0f}x real time (target >= 1000x); "
        f"compiled loop vs NumPy baseline {t_base / t_one:.0f}x faster, vs Python loop {t_py / t_one:.1f}x faster"
    )
    print(f"of one steady state: integrator (simulate) {t_int * 1e3:.2f} ms, set-up + steady-state analysis "
          f"{(t_one - t_int) * 1e3:.2f} ms")  # fmt: skip
    print(f"9-point sweep: {t_sweep:.3f} s serial (target < 1 s); NumPy baseline per steady state {t_base:.2f} s")
    if a.write is not None:
        doc = [
            "",
            f"Table S1 wheel, {a.kind.upper()}, {a.omega_rpm:g} RPM, dt = {st.meta['dt'] * 1e3:g} ms "
            f"({n_steps_one} steps, {sim_one:g} s simulated), one core, best of {a.repeat}:",
            "",
            "| case | wall s | simulated / wall time | vs NumPy baseline |",
            "|---|---|---|---|",
            f"| one steady state, compiled step loop (`intrusim._implicit_jit`) | {t_one:.4f} | {sim_one / t_one:.0f}x "
            f"| {t_base / t_one:.0f}x faster |",
            f"| one steady state, Python reference loop | {t_py:.3f} | {sim_one / t_py:.0f}x | {t_base / t_py:.0f}x faster |",
            f"| 9-point sweep 10-90 RPM, serial, compiled | {t_sweep:.3f} | {sim_sweep / t_sweep:.0f}x | |",
            f"| one steady state, explicit Euler NumPy baseline (dt {BASELINE_DT * 1e3:g} ms, `wrench_numpy`) "
            f"| {t_base:.2f} | {sim_one / t_base:.1f}x | 1 |",
            "",
            machine_line(),
            "",
        ]
        write_between(a.write, "bench_locomotion", doc)
        print(f"wrote the table into {a.write}")
    if a.bulldozing > 0.0:
        from intrusim.analysis.calibration import with_parameters

        # the term's own cost: on, with a k_b too small to move the trajectory, against off, interleaved
        tiny = with_parameters(wheel, {"bulldozing": 1e-9})
        run_steady(tiny, a.kind, 10.0)
        pairs = [(best_of(lambda: run_steady(wheel, a.kind, a.omega_rpm), a.repeat)[0],
                  best_of(lambda: run_steady(tiny, a.kind, a.omega_rpm), a.repeat)[0]) for _ in range(3)]  # fmt: skip
        print(
            "bulldozing term's cost (k_b = 1e-9, same trajectory), 3 interleaved rounds, ms: "
            + ", ".join(f"{off * 1e3:.2f} off / {on * 1e3:.2f} on ({on / off:.3f})" for off, on in pairs)
        )
        bull = with_parameters(wheel, {"bulldozing": a.bulldozing})
        t_b, st_b = best_of(lambda: run_steady(bull, a.kind, a.omega_rpm), a.repeat)
        n_b = len(st_b.trajectory.t) - 1
        print(f"with bulldozing k_b = {a.bulldozing:g}: {t_b * 1e3:.2f} ms for {n_b} steps ({t_b / n_b * 1e6:.1f} us per step; "
              f"v {st_b.velocity:.4f} m/s, sinkage {st_b.sinkage * 1e3:.2f} mm: a slower, deeper wheel, more elements in contact)")  # fmt: skip
    print("sweep records:")
    print(res.table())


if __name__ == "__main__":
    main()
