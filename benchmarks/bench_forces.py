"""Benchmark: one full force + moment evaluation of the grousered wheel (issue: < 20 us per call).

Compares, in the same run, the compiled force model (Numba) with
  (a) a plain per-element Python/NumPy loop (the baseline), and
  (b) the vectorised NumPy path built from the pure laws (ResistiveForceModel.wrench_numpy).
Prints microseconds per call and ratios. Run: python benchmarks/bench_forces.py
[--write docs/performance.md]: ``--write`` also replaces that file's table between the markers
``<!-- bench_forces: begin -->`` / ``<!-- bench_forces: end -->`` with the one just measured.
"""

from __future__ import annotations

import argparse
import math
import time

import numpy as np
from _doc_tables import check_markers, machine_line, write_between

from intrusim.forces import make_force_model
from intrusim.geometry import grousered_wheel
from intrusim.kinematics import BodyState
from intrusim.laws.drft import structural_depth_shift
from intrusim.laws.rft import alpha


def loop_wrench(
    elements, state: BodyState, xi: float, rho: float, lam: float, radius: float
) -> tuple[float, float, float]:
    """Per-element loop over the same DRFT laws (wheel rear-half model), one element at a time."""
    c, s = math.cos(state.theta), math.sin(state.theta)
    n_el = len(elements)
    rel, pos, nrm, vel = [], [], [], []
    for i in range(n_el):
        mx, mz = elements.midpoint[i]
        rx, rz = c * mx - s * mz, s * mx + c * mz
        rel.append((rx, rz))
        pos.append((state.x + rx, state.z + rz))
        nx, nz = elements.normal[i]
        nrm.append((c * nx - s * nz, s * nx + c * nz))
        vel.append((state.vx - state.omega * rz, state.vz + state.omega * rx))
    fwd = -1.0 if state.omega > 0 else 1.0
    phis = [math.atan2(fwd * r[0], -r[1]) for r, p in zip(rel, pos) if p[1] < 0]
    mid = 0.5 * (min(phis) + max(phis)) if phis else -math.inf
    dh = structural_depth_shift(radius, state.omega)
    fx = fz = mom = 0.0
    for i in range(n_el):
        (rx, rz), (_, pz), (nx, nz), (ux, uz) = rel[i], pos[i], nrm[i], vel[i]
        vn = nx * ux + nz * uz
        depth = pz + (dh if math.atan2(fwd * rx, -rz) < mid else 0.0)
        if vn <= 0 or depth >= 0:
            continue
        beta = -math.atan2(nx, -nz)
        gamma = math.atan2(-uz, -ux)
        ax, az = alpha(np.array(beta), np.array(gamma), xi)
        dA = elements.area[i]
        ex = (float(ax) * -depth - nx * lam * rho * vn * vn) * dA
        ez = (float(az) * -depth - nz * lam * rho * vn * vn) * dA
        fx, fz, mom = fx + ex, fz + ez, mom + rx * ez - rz * ex
    return fx, fz, mom


def per_call_us(fn, repeats: int, rounds: int = 5) -> float:
    best = math.inf
    for _ in range(rounds):
        t0 = time.perf_counter()
        for _ in range(repeats):
            fn()
        best = min(best, (time.perf_counter() - t0) / repeats)
    return best * 1e6


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--write", type=str, default=None, help="replace this markdown file's bench_forces table")
    a = ap.parse_args()
    if a.write is not None:
        check_markers(a.write, "bench_forces")  # before measuring
    doc = [
        "| wheel | elements | compiled (Numba) | vectorised NumPy | per-element loop (baseline) | loop / compiled |",
        "|---|---|---|---|---|---|",
    ]
    state = BodyState(0.0, 0.085, 0.1, 0.25, 0.0, -2 * np.pi)
    print(
        f"{'wheel':>28} | {'elements':>8} | {'compiled us':>11} | {'tuple us':>8} | {'numpy-vec us':>12} | {'loop us':>9} | {'loop/compiled':>13}"
    )
    for grousers in (15, 20):
        wheel = grousered_wheel(grouser_count=grousers, grouser_height_scale=1 / 3)
        model = make_force_model("drft", wheel, structural="wheel-rear-half")
        ref = loop_wrench(wheel.elements, state, model.xi, model.rho, model.lam, wheel.radius)
        assert np.allclose(model.wrench(state).as_array(), ref, rtol=1e-9), "compiled and loop disagree"
        args = (state.x, state.z, state.theta, state.vx, state.vz, state.omega)
        t_obj = per_call_us(lambda: model.wrench(state), 20000)
        t_tup = per_call_us(lambda: model.wrench_tuple(*args), 20000)
        t_vec = per_call_us(lambda: model.wrench_numpy(state), 500)
        t_loop = per_call_us(
            lambda: loop_wrench(wheel.elements, state, model.xi, model.rho, model.lam, wheel.radius), 5, rounds=3
        )
        label = f"{grousers} grousers (Table S1: 20)"
        print(
            f"{label:>28} | {len(wheel.elements):8d} | {t_obj:11.2f} | {t_tup:8.2f} | {t_vec:12.1f} | {t_loop:9.0f} | {t_loop / t_obj:12.0f}x"
        )
        name = f"{grousers} grousers" + (" (Table S1)" if grousers == 20 else "")
        doc.append(
            f"| {name} | {len(wheel.elements)} | {t_obj:.1f} us | {t_vec:.0f} us | {t_loop:.0f} us | {t_loop / t_obj:.0f}x |"
        )
    print("target: < 20 us per full force + moment evaluation (compiled column)")
    if a.write is not None:
        write_between(a.write, "bench_forces", ["", *doc, "", machine_line(), ""])
        print(f"wrote the table into {a.write}")


if __name__ == "__main__":
    main()
