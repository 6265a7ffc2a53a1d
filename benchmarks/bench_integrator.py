"""Locomotion integrator: the default time step's error against the dt -> 0 answer, and its speed.

Run:  python benchmarks/bench_integrator.py [--repeat N] [--write docs/locomotion.md]

For each body (the Table S1 wheel, the half-size wheel of Fig S1, the four-flap runner, and the
Table S1 wheel with the calibrated bulldozing term of docs/results.md) and omega,
the DRFT steady state (v, sinkage) is computed

* with the defaults: BDF2, the step of ``RunConfig.dt`` (k + 0.618 steps per lug pitch, at least
  ``steps_per_revolution`` a revolution and at most ``dt_max``);
* with the former defaults: backward Euler, min(10 ms, revolution / 100);
* as the reference: BDF2 at 1/16 of the default step, averaged over 8 revolutions.

The errors are relative to the reference. "x real time" is simulated time over the wall time of
the whole default ``run_steady`` call (set-up and steady-state analysis included), best of
``--repeat``, one core. ``--write FILE`` replaces the table between the markers
``<!-- bench_integrator: begin -->`` / ``<!-- bench_integrator: end -->`` of FILE.
"""

from __future__ import annotations

import argparse
import time

from _doc_tables import check_markers, machine_line, write_between

from intrusim.analysis.calibration import with_mpm_push, with_parameters
from intrusim.analysis.steady import run_steady, run_until_steady
from intrusim.bodies import IntegratorSettings
from intrusim.scenarios.locomotor import four_flap_runner_scenario, grousered_wheel_scenario, small_wheel_scenario

BODIES = {
    "Table S1 wheel": (grousered_wheel_scenario, (10.0, 30.0, 50.0, 70.0, 90.0)),
    "small wheel (Fig S1)": (small_wheel_scenario, (10.0, 30.0, 50.0, 70.0, 90.0)),
    "four-flap runner": (four_flap_runner_scenario, (10.0, 30.0, 90.0, 150.0, 300.0)),
    "wheel + bulldozing, k_b 4.38": (lambda: bulldozing_wheel(4.38), (10.0, 30.0, 60.0)),
}


def bulldozing_wheel(k_b: float):
    """The calibrated body-level bulldozing variant of the Table S1 wheel (tests/regression/test_bulldozing_calibration.py):
    the paper's DRFT (the shipped wheel's rear-half structural correction), the MPM runs' forward push and k_b."""
    return with_parameters(with_mpm_push(grousered_wheel_scenario()), {"bulldozing": k_b})


REFINE = 16  # the reference step: the default / REFINE
FORMER_STEPS, FORMER_DT_MAX = 100, 0.01  # the former default step: min(10 ms, revolution / 100)


def with_run(scenario, **update):
    return scenario.model_copy(update={"run": scenario.run.model_copy(update=update)})


def former(scenario, rpm: float):
    """The steady state with the former defaults: backward Euler, min(10 ms, revolution / 100)."""
    drive, shape = scenario.drive(rpm), scenario.rft_shape()
    dt = min(FORMER_DT_MAX, scenario.run.period(drive.omega) / FORMER_STEPS)
    return run_until_steady(
        scenario.build_model("drft"), shape, scenario.rigid_body(), drive, scenario.initial_state(shape), scenario.run,
        settings=IntegratorSettings(dt=dt, scheme="implicit"),
    )  # fmt: skip


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--write", type=str, default=None, help="replace this markdown file's bench_integrator table")
    a = ap.parse_args()
    if a.write is not None:
        check_markers(a.write, "bench_integrator")
    run_steady(grousered_wheel_scenario(), "drft", 30.0)  # load the compiled loop
    rows = []
    worst: dict[str, float] = {}  # the largest |error| of each body
    print(f"{'body':<22} {'RPM':>4} {'dt ms':>7} {'steps/rev':>9} | {'v err %':>8} {'sink err %':>10} | "
          f"{'former v %':>10} {'former sink %':>13} | {'x real time':>11}")  # fmt: skip
    for label, (make, omegas) in BODIES.items():
        scen = make()
        for rpm in omegas:
            times = []
            for _ in range(a.repeat):
                t0 = time.perf_counter()
                st = run_steady(scen, "drft", rpm)
                times.append(time.perf_counter() - t0)
            rt = float(st.trajectory.t[-1]) / min(times)
            dt = st.meta["dt"]
            period = scen.run.period(st.omega)
            fine = with_run(scen, steps_per_revolution=int(round(REFINE * period / dt)), dt_max=dt / REFINE,
                            average_revolutions=8)  # fmt: skip
            ref = run_steady(fine, "drft", rpm)
            old = former(scen, rpm)
            ev, es = 100 * (st.velocity / ref.velocity - 1), 100 * (st.sinkage / ref.sinkage - 1)
            ov, os_ = 100 * (old.velocity / ref.velocity - 1), 100 * (old.sinkage / ref.sinkage - 1)
            worst[label] = max(worst.get(label, 0.0), abs(ev), abs(es))
            rows.append((label, rpm, dt, period / dt, ev, es, ov, os_, rt, ref))
            print(f"{label:<22} {rpm:4.0f} {dt * 1e3:7.3f} {period / dt:9.1f} | {ev:+8.3f} {es:+10.3f} | "
                  f"{ov:+10.2f} {os_:+13.2f} | {rt:10.0f}x", flush=True)  # fmt: skip
    summary = "Largest default error (target < 0.2 %): " + "; ".join(f"{k} {v:.3f} %" for k, v in worst.items()) + "."
    print(summary)
    if a.write is not None:
        doc = [
            "",
            "DRFT steady states; errors against BDF2 at 1/16 of the default step over 8 "
            f"revolutions; real time: the whole `run_steady` call at the default, one core, best of {a.repeat}:",
            "",
            "| body | RPM | default dt (ms) | steps / rev | v error | sinkage error | former default: v, sinkage "
            "error | x real time |",
            "|---|---|---|---|---|---|---|---|",
        ]
        for label, rpm, dt, spr, ev, es, ov, os_, rt, _ in rows:
            doc.append(f"| {label} | {rpm:g} | {dt * 1e3:.2f} | {spr:.1f} | {ev:+.3f} % | {es:+.3f} % "
                       f"| {ov:+.2f} %, {os_:+.2f} % | {rt:.0f}x |")  # fmt: skip
        doc += ["", summary, "", machine_line(), ""]
        write_between(a.write, "bench_integrator", doc)
        print(f"wrote the table into {a.write}")


if __name__ == "__main__":
    main()
