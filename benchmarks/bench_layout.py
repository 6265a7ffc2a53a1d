"""Benchmark: does packing each point's state into one record speed up G2P? (docs/performance.md)

The solver keeps the particle state as a structure of arrays: 9 Taichi ndarrays (x, v, C, mass,
vol, sigma, s_yy, eps_p, gdot_p), of which G2P reads 6 and writes 8. The alternative is an array
of structures: one 16-float (64-byte) record per point,

    x0 x1 v0 v1 C00 C01 C10 C11 mass vol s_xx s_xz s_zz s_yy eps_p gdot_p

(sigma stored once, it is symmetric), so a point's state is one cache line. This script times the
solver's G2P kernel (``transfer.g2p_kernel``, the SoA layout) against a copy of it on the packed
record, on the benchmark's 64k and 160k resting beds (bench_mpm.CASES) after a few steps of the
solver: --rounds interleaved rounds of ~0.3 s of launches of each (min and median per launch).
Both compute the same numbers (checked in each run: the largest difference relative to each
field's magnitude is printed). The baseline in the same run is the SoA kernel.

    python benchmarks/bench_layout.py --threads 2
"""


import argparse
import json
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

def packed_g2p_kernel(stress_update):
    """The solver's G2P + density + stress update on one 16-float record per point."""
    import taichi as ti

    from intrusim.mpm import backend
    from intrusim.mpm.transfer import exp_near_zero, g2p_point

    @ti.kernel
    def g2p_packed(rec: ti.types.ndarray(), gv: ti.types.ndarray(), h: float, pad: int, dt: float,
                   prm: ti.types.vector(4, float), inv_rho_floor: float):
        ti.loop_config(serialize=backend.SERIAL_LOOPS)  # as the solver's kernel
        for p in range(rec.shape[0]):
            xp = ti.Vector([rec[p][0], rec[p][1]])
            new_v, L = g2p_point(xp, gv, h, pad)
            xp += dt * new_v
            mass = rec[p][8]
            vol = ti.min(rec[p][9] * exp_near_zero(dt * L.trace()), mass * inv_rho_floor)
            sigma = ti.Matrix([[rec[p][10], rec[p][11]], [rec[p][11], rec[p][12]]])
            sig, syy, dgamma = stress_update(sigma, rec[p][13], L, mass / vol, dt, prm)
            rec[p][0], rec[p][1], rec[p][2], rec[p][3] = xp[0], xp[1], new_v[0], new_v[1]
            rec[p][4], rec[p][5], rec[p][6], rec[p][7] = L[0, 0], L[0, 1], L[1, 0], L[1, 1]
            rec[p][9], rec[p][10], rec[p][11], rec[p][12] = vol, sig[0, 0], sig[0, 1], sig[1, 1]
            rec[p][13], rec[p][14], rec[p][15] = syy, rec[p][14] + dgamma, dgamma / dt

    return g2p_packed


def pack(state: dict) -> np.ndarray:
    n = len(state["x"])
    rec = np.empty((n, 16), np.float32)
    rec[:, 0:2], rec[:, 2:4] = state["x"], state["v"]
    rec[:, 4:8] = state["C"].reshape(n, 4)
    rec[:, 8], rec[:, 9] = state["mass"], state["vol"]
    rec[:, 10], rec[:, 11], rec[:, 12] = state["sigma"][:, 0, 0], state["sigma"][:, 0, 1], state["sigma"][:, 1, 1]
    rec[:, 13], rec[:, 14], rec[:, 15] = state["s_yy"], state["eps_p"], state["gdot_p"]
    return rec


def measure(threads: int, rounds: int) -> list[dict]:
    sys.path.insert(0, str(Path(__file__).parent))
    import taichi as ti
    from bench_mpm import CASES, bed_solver

    from intrusim.mpm.backend import ensure_initialized

    ensure_initialized("cpu", "f32", threads)
    rows = []
    for label, (domain, cells, bed) in CASES.items():
        solver = bed_solver(domain, cells, bed, "cpu")
        for _ in range(20):  # a bed that has started to settle: grid velocities are not all zero
            solver.step()
        p, g = solver.particles, solver.grid
        g2p_soa = solver._g2p
        g2p_rec = packed_g2p_kernel(solver.material.taichi_update)
        prm = ti.Vector(list(solver.material.params))
        inv_floor = 1.0 / solver.cfg.material.rho_floor
        state0 = p.to_numpy()
        rec = ti.Vector.ndarray(16, ti.f32, shape=p.n)
        # the grid velocities stay fixed, so the repeats move each copy of the state on by
        # v dt per launch (~1e-7 m at rest): the same work in every launch
        soa_args = (p.x, p.v, p.C, p.mass, p.vol, p.sigma, p.s_yy, p.eps_p, p.gdot_p, g.v, g.h, g.pad, solver.dt, prm, inv_floor)
        rec_args = (rec, g.v, g.h, g.pad, solver.dt, prm, inv_floor)
        # same numbers: one launch of each from the same state
        rec.from_numpy(pack(state0))
        g2p_soa(*soa_args)
        g2p_rec(*rec_args)
        diff = np.abs(pack(p.to_numpy()) - rec.to_numpy()).max(axis=0)
        scale = np.maximum(np.abs(pack(p.to_numpy())).max(axis=0), 1e-12)
        mismatch = float((diff / scale).max())
        p.load(state0)
        rec.from_numpy(pack(state0))

        def timed(kernel, args, n):
            ti.sync()
            t0 = time.perf_counter()
            for _ in range(n):
                kernel(*args)
            ti.sync()
            return (time.perf_counter() - t0) / n

        # warm up and choose launches per round (~0.3 s)
        timed(g2p_soa, soa_args, 3), timed(g2p_rec, rec_args, 3)
        n = max(5, int(0.3 / timed(g2p_soa, soa_args, 5)))
        soa, packed = [], []
        for _ in range(rounds):
            soa.append(timed(g2p_soa, soa_args, n))
            packed.append(timed(g2p_rec, rec_args, n))
        rows.append({"threads": threads, "case": label, "points": p.n, "launches": n,
                     "soa_ms": [1e3 * t for t in soa], "packed_ms": [1e3 * t for t in packed],
                     "max_rel_mismatch": mismatch})
        del solver
    return rows


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--threads", default="1,2")
    ap.add_argument("--rounds", type=int, default=5)
    ap.add_argument("--child", type=int, default=None, help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.child is not None:
        print(json.dumps(measure(args.child, args.rounds)))
        return
    print("G2P: structure of arrays (the solver's kernel; baseline) vs one 16-float record per point")
    print("| threads | points | SoA ms (min / median) | packed ms (min / median) | packed / SoA (medians) | max rel. mismatch |")
    print("|---|---|---|---|---|---|")
    for t in args.threads.split(","):
        out = subprocess.run([sys.executable, __file__, "--child", t, "--rounds", str(args.rounds)],
                             capture_output=True, text=True, check=True)
        for r in json.loads(out.stdout.strip().splitlines()[-1]):
            s, q = np.array(r["soa_ms"]), np.array(r["packed_ms"])
            print(f"| {r['threads']} | {r['points']:,} | {s.min():.3f} / {np.median(s):.3f} | {q.min():.3f} / "
                  f"{np.median(q):.3f} | {np.median(q) / np.median(s):.3f} | {r['max_rel_mismatch']:.1e} |", flush=True)


if __name__ == "__main__":
    main()
