"""Locomotion integrator: the default time step's error against the dt -> 0 answer, and its speed.

Run:  python benchmarks/bench_integrator.py [--repeat N] [--write docs/locomotion.md]

For each body (the Table S1 wheel, the half-size wheel of Fig S1, the four-flap runner, the
Table S1 wheel with the calibrated bulldozing term of docs/results.md, and the Table S1 wheel with
a rough calibration: xi 0.545, lambda 0.09, psi 0.311 + 0.604 x in the effective rear-half zone,
``benchmarks/data/rough_zone_wheel.model.json``, an earlier blind-prediction fit; and with the
blind calibration of docs/results.md, ``docs/figures/blind.model.json``) and omega,
the DRFT steady state (v, sinkage) is computed

* with the defaults: BDF2, the step of ``RunConfig.dt`` (k + 0.618 steps per lug pitch, at least
  ``steps_per_revolution`` a revolution and at most ``dt_max``);
* with the former defaults: backward Euler, min(10 ms, revolution / 100);
* as the dt -> 0 reference: BDF2 at 1/16 of the default step, averaged over 8 revolutions;
* as the converged reference: the same with 4 x the RFT elements on every rim segment and lug
  face (``LocomotorScenario.finer_elements``): the model's answer once both the step and the
  elements are fine.

The errors are relative to the references. "x real time" is simulated time over the wall time of
the whole default ``run_steady`` call (set-up and steady-state analysis included), best of
``--repeat``, one core. ``--write FILE`` replaces the table between the markers
``<!-- bench_integrator: begin -->`` / ``<!-- bench_integrator: end -->`` of FILE.
"""

from __future__ import annotations

import argparse
import time

from _doc_tables import ROOT, check_markers, machine_line, write_between

from intrusim.analysis.calibration import with_mpm_push, with_parameters
from intrusim.analysis.model_file import read_model
from intrusim.analysis.steady import run_steady, run_until_steady
from intrusim.bodies import IntegratorSettings
from intrusim.scenarios.locomotor import four_flap_runner_scenario, grousered_wheel_scenario, small_wheel_scenario

BODIES = {
    "Table S1 wheel": (grousered_wheel_scenario, (10.0, 30.0, 50.0, 70.0, 90.0)),
    "small wheel (Fig S1)": (small_wheel_scenario, (10.0, 30.0, 50.0, 70.0, 90.0)),
    "four-flap runner": (four_flap_runner_scenario, (10.0, 30.0, 90.0, 150.0, 300.0)),
    "wheel + bulldozing, k_b 4.38": (lambda: bulldozing_wheel(4.38), (10.0, 30.0, 60.0)),
    "wheel, rough calibration": (lambda: blind_wheel(ROUGH_MODEL), (10.0, 30.0, 60.0, 90.0)),
    "wheel, blind calibration": (lambda: blind_wheel(BLIND_MODEL), (10.0, 30.0, 50.0, 70.0, 80.0, 90.0)),
}
ROUGH_MODEL = ROOT / "benchmarks" / "data" / "rough_zone_wheel.model.json"
BLIND_MODEL = ROOT / "docs" / "figures" / "blind.model.json"  # docs/results.md, "Blind prediction"


def bulldozing_wheel(k_b: float):
    """The calibrated body-level bulldozing variant of the Table S1 wheel (tests/regression/test_bulldozing_calibration.py):
    the paper's DRFT (the shipped wheel's rear-half structural correction), the MPM runs' forward push and k_b."""
    return with_parameters(with_mpm_push(grousered_wheel_scenario()), {"bulldozing": k_b})


def blind_wheel(path):
    """The Table S1 wheel driven by a calibrated model file: the rough calibration (xi, psi, lambda and the
    effective rear-half zone fitted to an earlier MPM sweep) or docs/results.md's blind calibration."""
    return read_model(path).apply(grousered_wheel_scenario())


REFINE = 16  # the reference step: the default / REFINE
ELEMENTS = 4  # the converged reference's elements: the default x ELEMENTS
FORMER_STEPS, FORMER_DT_MAX = 100, 0.01  # the former default step: min(10 ms, revolution / 100)


def former(scenario, rpm: float):
    """The steady state with the former defaults: backward Euler, min(10 ms, revolution / 100)."""
    drive, shape = scenario.drive(rpm), scenario.rft_shape()
    dt = min(FORMER_DT_MAX, scenario.run.period(drive.omega) / FORMER_STEPS)
    return run_until_steady(
        scenario.build_model("drft"), shape, scenario.rigid_body(), drive, scenario.initial_state(shape), scenario.run,
        settings=IntegratorSettings(dt=dt, scheme="implicit"),
    )  # fmt: skip


def pct(a: float, b: float) -> float:
    return 100.0 * (a / b - 1.0)


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--write", type=str, default=None, help="replace this markdown file's bench_integrator table")
    ap.add_argument("--only", type=str, default=None, help="comma-separated body labels to run (not with --write)")
    a = ap.parse_args()
    bodies = BODIES
    if a.only is not None:
        if a.write is not None:
            ap.error("--only measures part of the table: not with --write")
        bodies = {k: v for k, v in BODIES.items() if k in [x.strip() for x in a.only.split(",")]}
        if not bodies:
            ap.error(f"--only names none of {list(BODIES)}")
    if a.write is not None:
        check_markers(a.write, "bench_integrator")
    run_steady(grousered_wheel_scenario(), "drft", 30.0)  # load the compiled loop
    rows = []
    worst: dict[str, list[float]] = {}  # the largest |error| of each body: against dt -> 0, against converged
    print(f"{'body':<26} {'RPM':>4} {'dt ms':>7} {'steps/rev':>9} | {'v err %':>8} {'sink err %':>10} | "
          f"{'conv v %':>8} {'conv sink %':>11} | {'former v %':>10} {'former sink %':>13} | {'x real time':>11}")  # fmt: skip
    for label, (make, omegas) in bodies.items():
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
            ref = run_steady(scen.finer_steps(dt, st.omega, REFINE), "drft", rpm)
            conv = run_steady(scen.finer_elements(ELEMENTS).finer_steps(dt, st.omega, REFINE), "drft", rpm)
            old = former(scen, rpm)
            err = (pct(st.velocity, ref.velocity), pct(st.sinkage, ref.sinkage),
                   pct(st.velocity, conv.velocity), pct(st.sinkage, conv.sinkage),
                   pct(old.velocity, ref.velocity), pct(old.sinkage, ref.sinkage))  # fmt: skip
            w = worst.setdefault(label, [0.0, 0.0])
            w[0], w[1] = max(w[0], abs(err[0]), abs(err[1])), max(w[1], abs(err[2]), abs(err[3]))
            rows.append((label, rpm, dt, period / dt, *err, rt))
            print(f"{label:<26} {rpm:4.0f} {dt * 1e3:7.3f} {period / dt:9.1f} | {err[0]:+8.3f} {err[1]:+10.3f} | "
                  f"{err[2]:+8.3f} {err[3]:+11.3f} | {err[4]:+10.2f} {err[5]:+13.2f} | {rt:10.0f}x", flush=True)  # fmt: skip
    summary = (
        "Largest default error (target < 0.2 %), against dt -> 0 / against the converged model: "
        + "; ".join(f"{k} {v[0]:.3f} / {v[1]:.3f} %" for k, v in worst.items())
        + "."
    )
    print(summary)
    if a.write is not None:
        doc = [
            "",
            f"DRFT steady states; errors against BDF2 at 1/{REFINE} of the default step over 8 revolutions (dt -> 0), "
            f"and against the same with {ELEMENTS} x the RFT elements (converged); real time: the whole `run_steady` "
            f"call at the default, one core, best of {a.repeat}:",
            "",
            "| body | RPM | default dt (ms) | steps / rev | v, sinkage error (dt -> 0) | v, sinkage error (converged) "
            "| former default: v, sinkage error (dt -> 0) | x real time |",
            "|---|---|---|---|---|---|---|---|",
        ]
        for label, rpm, dt, spr, ev, es, cv, cs, ov, os_, rt in rows:
            doc.append(f"| {label} | {rpm:g} | {dt * 1e3:.2f} | {spr:.1f} | {ev:+.3f} %, {es:+.3f} % | {cv:+.3f} %, {cs:+.3f} % "
                       f"| {ov:+.2f} %, {os_:+.2f} % | {rt:.0f}x |")  # fmt: skip
        doc += ["", summary, "", machine_line(), ""]
        write_between(a.write, "bench_integrator", doc)
        print(f"wrote the table into {a.write}")


if __name__ == "__main__":
    main()
