"""GPU check: the paper's wheel run on the CPU and on a GPU from the same state, side by side.

The MPM kernels are the same source on every Taichi backend, but a GPU sums P2G with atomic adds
(in no fixed order) where the CPU sums private grid copies in a fixed order, and its float32
arithmetic may round differently. This script measures what that does to a run, and what the GPU
buys:

* both backends run the paper's wheel (Table S1: 1 m x 1 m bed, 200 x 200 grid, 2 x 2 points per
  cell, coupled wheel, omega ramped to ``--omega-rpm``) for ``--t-end`` s of physical time, one
  process each, recording the body's state and the contact force every ``--record-every`` s;
* it prints the wall time per step and per physical second of each, and the largest difference
  between the two time series (body x, z, vx, omega, forces), also against the size of the signal.

    python benchmarks/gpu_check.py --arch cuda                       # CPU (all cores) vs CUDA, 0.25 s
    python benchmarks/gpu_check.py --arch cuda --t-end 0.5 --json out.json

A backend that is missing stops the script with a message (Taichi would fall back to the CPU).
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import time

import numpy as np

SERIES = ("x", "z", "vx", "vz", "omega", "fx", "fz", "moment")


def run_wheel(arch: str, threads: int | None, omega_rpm: float, t_end: float, record_every: float) -> dict:
    """One wheel run on ``arch`` (this process initialises Taichi): its time series and timings."""
    import taichi as ti

    from intrusim.mpm.backend import ensure_initialized
    from intrusim.mpm.solver import Solver
    from intrusim.scenarios import grousered_wheel_scenario
    from intrusim.scenarios.mpm_locomotion import mpm_config, paper_settings

    backend = ensure_initialized(arch, "f32", threads)
    if backend.fell_back:
        raise SystemExit(f"arch {arch}: Taichi found no such device here")
    s = paper_settings("wheel").model_copy(update=dict(arch=arch, cpu_threads=threads))
    s = s.model_copy(update=dict(start_depth=s.h))  # a cell into the bed: in contact from the first step
    t0 = time.perf_counter()
    solver = Solver(mpm_config(grousered_wheel_scenario(), s, omega_rpm, None))
    every = max(1, int(round(record_every / solver.dt)))
    n_end = int(round(t_end / solver.dt))
    solver.record()
    build = time.perf_counter() - t0
    t0 = time.perf_counter()
    solver.step()  # the first step compiles the kernels (or loads them from the cache): timed apart
    ti.sync()
    first = time.perf_counter() - t0
    if solver.step_count % every == 0:
        solver.record()
    t0 = time.perf_counter()
    while solver.step_count < n_end:
        solver.step()
        if solver.step_count % every == 0:
            solver.record()
    ti.sync()
    wall = time.perf_counter() - t0
    steps = max(1, solver.step_count - 1)
    series = {k: [float(r[k]) for r in solver.rows] for k in ("time", *SERIES)}
    return {
        "arch": backend.arch,
        "threads": threads or os.cpu_count(),
        "particles": solver.particles.n,
        "dt": solver.dt,
        "steps": solver.step_count,
        "build_s": build,
        "first_step_s": first,
        "ms_per_step": wall / steps * 1e3,
        "wall_s_per_physical_s": wall / steps / solver.dt,
        "series": series,
    }


def compare(a: dict, b: dict) -> dict:
    """Largest difference of each time series of run ``b`` against run ``a`` (same record times),
    absolute and over the largest magnitude of ``a``'s series."""
    n = min(len(a["series"]["time"]), len(b["series"]["time"]))
    if not np.allclose(a["series"]["time"][:n], b["series"]["time"][:n], rtol=0, atol=1e-9):
        raise ValueError("the two runs recorded at different times")
    out = {}
    for k in SERIES:
        x, y = np.asarray(a["series"][k][:n]), np.asarray(b["series"][k][:n])
        diff = float(np.max(np.abs(y - x)))
        scale = float(np.max(np.abs(x)))
        out[k] = {
            "max_abs_diff": diff,
            "max_abs": scale,
            "relative": diff / scale if scale > 0 else float("nan"),
            "end_a": float(x[-1]),
            "end_b": float(y[-1]),
        }
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--arch", default="cuda", help="the GPU backend to check against the CPU: cuda, vulkan, metal")
    ap.add_argument("--threads", type=int, default=None, help="CPU threads of the CPU run (default: all cores)")
    ap.add_argument("--omega-rpm", type=float, default=60.0)
    ap.add_argument("--t-end", type=float, default=0.25, help="physical time of each run, s")
    ap.add_argument("--record-every", type=float, default=0.005, help="s between recorded rows")
    ap.add_argument("--json", default=None, help="also write everything to this JSON file")
    ap.add_argument("--child", default=None, help=argparse.SUPPRESS)
    args = ap.parse_args()
    if not args.t_end > 0 or not args.record_every > 0:
        ap.error("--t-end and --record-every must be > 0")
    if args.child is not None:
        print(json.dumps(run_wheel(args.child, args.threads, args.omega_rpm, args.t_end, args.record_every)))
        return
    runs = []  # the CPU run, then the other backend's (--arch cpu: the CPU against itself, a determinism check)
    for arch in ("cpu", args.arch):
        cmd = [
            sys.executable,
            __file__,
            "--child",
            arch,
            "--omega-rpm",
            str(args.omega_rpm),
            "--t-end",
            str(args.t_end),
            "--record-every",
            str(args.record_every),
        ]
        if args.threads is not None:
            cmd += ["--threads", str(args.threads)]
        proc = subprocess.run(cmd, capture_output=True, text=True, env={**os.environ, "INTRUSIM_TI_ARCH": ""})
        if proc.returncode != 0:
            sys.exit(f"{arch} run failed:\n{proc.stderr[-3000:]}")
        runs.append(json.loads(proc.stdout.strip().splitlines()[-1]))
    cpu, gpu = runs
    diff = compare(cpu, gpu)
    print(
        f"paper wheel, {args.omega_rpm:g} RPM, {cpu['particles']} points, dt {cpu['dt']:.3g} s, "
        f"{args.t_end:g} s of physical time ({cpu['steps']} steps)"
    )
    for r in (cpu, gpu):
        print(
            f"  {r['arch']:>6} ({r['threads']} CPU threads): {r['ms_per_step']:.3f} ms/step, "
            f"{r['wall_s_per_physical_s']:.1f} s wall per physical second "
            f"(build {r['build_s']:.1f} s, first step {r['first_step_s']:.1f} s)"
        )
    print(f"  {args.arch} / cpu speed: {cpu['ms_per_step'] / gpu['ms_per_step']:.2f}x")
    print(f"  largest difference {args.arch} - cpu over the run (absolute, / largest |cpu value|; values at the end):")
    for k, d in diff.items():
        print(
            f"    {k:>6}: {d['max_abs_diff']:.4g} ({d['relative']:.2%}); end cpu {d['end_a']:.5g}, {args.arch} {d['end_b']:.5g}"
        )
    if args.json:
        with open(args.json, "w") as f:
            json.dump({"runs": runs, "difference": diff, "args": vars(args)}, f)


if __name__ == "__main__":
    main()
