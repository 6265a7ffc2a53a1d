"""Benchmark: the particle arrays' layout, one element per point against blocks of 8 points (docs/performance.md).

The vectorised G2P (the default; ``BenchmarkSwitches.simd_lanes``) computes 8 points per loop
iteration. With one array element per point (the former layout: ``x`` an ndarray of 2-vectors, ``sigma``
of 2 x 2 matrices, ...) each lane of each component is its own scalar load and vector insert, and
its own extract and store. With the points in blocks of 8 per component (``particles.py``: an
ndarray of shape (blocks, components) whose element is an 8-vector) a block's component is one
vector load or store.

This script times only that traffic, the G2P's particle reads and writes (reads x 2, m, V, sigma 3,
s_yy, eps_p; writes v 2, C 4, x 2, V, sigma 3, s_yy, eps_p, gdot_p: 24 floats per point) with a
few operations between them, in both layouts, vectorised over 8 points and compiled alike
(``backend.unscalarized``). Both store the same numbers (checked in each run). The baseline in the
same run is the per-point layout; interleaved rounds of ~0.3 s, min and median per launch.

    python benchmarks/bench_layout.py --threads 2
"""

import argparse
import json
import subprocess
import sys
import time

import numpy as np

SIZES = (64_000, 160_000, 1_000_000)


def kernels():
    import taichi as ti

    from intrusim.mpm.particles import LANES

    @ti.func
    def lanes(a: ti.template(), p0, c: ti.template()):
        return ti.Vector([a[p0 + k][c] for k in ti.static(range(LANES))])

    @ti.kernel
    def per_point(
        x: ti.types.ndarray(),
        v: ti.types.ndarray(),
        C: ti.types.ndarray(),
        mass: ti.types.ndarray(),
        vol: ti.types.ndarray(),
        sigma: ti.types.ndarray(),
        s_yy: ti.types.ndarray(),
        eps_p: ti.types.ndarray(),
        gdot_p: ti.types.ndarray(),
    ):
        for blk in range(x.shape[0] // LANES):
            p0 = blk * LANES
            x0, x1, m, vp = lanes(x, p0, 0), lanes(x, p0, 1), lanes(mass, p0, 0), lanes(vol, p0, 0)
            s0, s1, s2, sy, ep = (
                lanes(sigma, p0, 0),
                lanes(sigma, p0, 1),
                lanes(sigma, p0, 2),
                lanes(s_yy, p0, 0),
                lanes(eps_p, p0, 0),
            )
            a, b, d = x0 * 1.0001 + s0 * 1e-9, x1 * 0.9999 + s1 * 1e-9, m / vp
            for k in ti.static(range(LANES)):
                p = p0 + k
                v[p] = ti.Vector([a[k], b[k]])
                C[p] = ti.Vector([a[k], b[k], d[k], s2[k]])
                x[p] = ti.Vector([a[k], b[k]])
                vol[p] = ti.Vector([vp[k]])
                sigma[p] = ti.Vector([s0[k], s1[k], s2[k] + d[k]])
                s_yy[p] = ti.Vector([sy[k] + d[k]])
                eps_p[p] = ti.Vector([ep[k] + d[k]])
                gdot_p[p] = ti.Vector([d[k]])

    @ti.kernel
    def blocks(
        x: ti.types.ndarray(),
        v: ti.types.ndarray(),
        C: ti.types.ndarray(),
        mass: ti.types.ndarray(),
        vol: ti.types.ndarray(),
        sigma: ti.types.ndarray(),
        s_yy: ti.types.ndarray(),
        eps_p: ti.types.ndarray(),
        gdot_p: ti.types.ndarray(),
    ):
        for blk in range(x.shape[0]):
            x0, x1, m, vp = x[blk, 0], x[blk, 1], mass[blk, 0], vol[blk, 0]
            s0, s1, s2, sy, ep = sigma[blk, 0], sigma[blk, 1], sigma[blk, 2], s_yy[blk, 0], eps_p[blk, 0]
            a, b, d = x0 * 1.0001 + s0 * 1e-9, x1 * 0.9999 + s1 * 1e-9, m / vp
            v[blk, 0], v[blk, 1] = a, b
            C[blk, 0], C[blk, 1], C[blk, 2], C[blk, 3] = a, b, d, s2
            x[blk, 0], x[blk, 1] = a, b
            vol[blk, 0] = vp
            sigma[blk, 0], sigma[blk, 1], sigma[blk, 2] = s0, s1, s2 + d
            s_yy[blk, 0] = sy + d
            eps_p[blk, 0] = ep + d
            gdot_p[blk, 0] = d

    return per_point, blocks


def measure(threads: int, rounds: int) -> list[dict]:
    import taichi as ti

    from intrusim.mpm.backend import ensure_initialized, unscalarized
    from intrusim.mpm.particles import COMPONENTS, FIELDS, LANES, from_blocks, to_blocks

    ensure_initialized("cpu", "f32", threads)
    widths = {k: COMPONENTS.get(k, 1) for k in FIELDS}  # the solver's fields, in the kernels' argument order
    per_point, blocks = kernels()
    rows = []
    for n in SIZES:
        rng = np.random.default_rng(0)
        host = {k: rng.uniform(1.0, 2.0, (n, c)).astype(np.float32) for k, c in widths.items()}
        flat = {k: ti.Vector.ndarray(c, ti.f32, shape=n) for k, c in widths.items()}
        blk = {k: ti.Vector.ndarray(LANES, ti.f32, shape=(n // LANES, c)) for k, c in widths.items()}

        def reset():
            for k in widths:
                flat[k].from_numpy(host[k])
                blk[k].from_numpy(to_blocks(host[k]))

        args_flat = [flat[k] for k in widths]
        args_blk = [blk[k] for k in widths]
        reset()
        with unscalarized():  # both compiled as vector code, as the solver's G2P
            per_point(*args_flat)
            blocks(*args_blk)
        mismatch = max(float(np.abs(flat[k].to_numpy() - from_blocks(blk[k].to_numpy(), n)).max()) for k in widths)
        reset()

        def timed(kernel, args, count):
            ti.sync()
            t0 = time.perf_counter()
            for _ in range(count):
                kernel(*args)
            ti.sync()
            return (time.perf_counter() - t0) / count

        count = max(5, int(0.3 / timed(per_point, args_flat, 5)))
        flat_ms, blk_ms = [], []
        for _ in range(rounds):
            flat_ms.append(1e3 * timed(per_point, args_flat, count))
            blk_ms.append(1e3 * timed(blocks, args_blk, count))
        bytes_moved = n * 4 * (9 + 15)
        rows.append(
            {
                "threads": threads,
                "points": n,
                "flat_ms": flat_ms,
                "blocks_ms": blk_ms,
                "mismatch": mismatch,
                "bytes": bytes_moved,
            }
        )
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
    print("G2P's particle reads and writes (24 floats per point), vectorised over 8 points: one array element")
    print("per point (baseline) vs blocks of 8 points per component (the solver's layout)")
    print(
        "| threads | points | per point ms (min / median) | blocks ms (min / median) | per point / blocks (medians) "
        "| blocks GB/s | max mismatch |"
    )
    print("|---|---|---|---|---|---|---|")
    for t in args.threads.split(","):
        out = subprocess.run(
            [sys.executable, __file__, "--child", t, "--rounds", str(args.rounds)], capture_output=True, text=True
        )
        if out.returncode != 0:
            sys.exit(f"benchmark child ({t} threads) failed:\n{out.stderr[-3000:]}")
        for r in json.loads(out.stdout.strip().splitlines()[-1]):
            f, b = np.array(r["flat_ms"]), np.array(r["blocks_ms"])
            print(
                f"| {r['threads']} | {r['points']:,} | {f.min():.3f} / {np.median(f):.3f} | {b.min():.3f} / "
                f"{np.median(b):.3f} | {np.median(f) / np.median(b):.2f}x | {r['bytes'] / b.min() / 1e6:.1f} | "
                f"{r['mismatch']:.1e} |"
            )


if __name__ == "__main__":
    main()
