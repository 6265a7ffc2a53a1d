"""Benchmark: the fixed cost of a kernel launched from a compiled Taichi graph (docs/performance.md).

An MPM step replays its kernels as one ``ti.graph`` (mpm/step_graph.py). What one replay costs
besides the kernels' work, measured on kernels that do almost nothing (16 serial iterations):

* per kernel, with 1 and with 10 ndarray arguments (the step's kernels take 6-10 each), and
* per kernel whose loop is parallel (4096 iterations through Taichi's thread pool) instead of serial,

for graphs of 1, 3 and 8 such kernels. The baseline, in the same run, is the graph of one
1-argument serial kernel; the figures are best-of-5 means over 400 replays.

    python benchmarks/bench_launch.py               # 1 thread, then 2
    python benchmarks/bench_launch.py --threads 2
"""

import argparse
import json
import subprocess
import sys
import time

SERIAL_N, PARALLEL_N = 16, 4096  # (no "from __future__ import annotations": Taichi reads the kernel annotations)


def measure(threads: int) -> list[dict]:
    import taichi as ti

    ti.init(arch=ti.cpu, cpu_max_num_threads=threads, log_level=ti.WARN)

    def kernel(n_args: int, parallel: bool):
        n = PARALLEL_N if parallel else SERIAL_N
        if n_args == 1:

            @ti.kernel
            def one(a: ti.types.ndarray()):
                ti.loop_config(serialize=not parallel)
                for i in range(n):
                    a[i] += 1.0

            return one

        @ti.kernel
        def ten(
            a: ti.types.ndarray(),
            b: ti.types.ndarray(),
            c: ti.types.ndarray(),
            d: ti.types.ndarray(),
            e: ti.types.ndarray(),
            f: ti.types.ndarray(),
            g: ti.types.ndarray(),
            h: ti.types.ndarray(),
            k: ti.types.ndarray(),
            m: ti.types.ndarray(),
        ):
            ti.loop_config(serialize=not parallel)
            for i in range(n):
                a[i] += 1.0

        return ten

    arrays = {f"a{q}": ti.ndarray(ti.f32, shape=PARALLEL_N) for q in range(10)}
    symbols = [ti.graph.Arg(ti.graph.ArgKind.NDARRAY, name, ti.f32, ndim=1) for name in arrays]
    rows = []
    for n_args in (1, 10):
        for parallel in (False, True):
            for n_kernels in (1, 3, 8):
                builder = ti.graph.GraphBuilder()
                for _ in range(n_kernels):
                    builder.dispatch(kernel(n_args, parallel), *symbols[:n_args])
                graph = builder.compile()
                values = {name: arrays[name] for name in list(arrays)[:n_args]}
                for _ in range(20):
                    graph.run(values)
                best = float("inf")
                for _ in range(5):
                    t0 = time.perf_counter()
                    for _ in range(400):
                        graph.run(values)
                    best = min(best, (time.perf_counter() - t0) / 400)
                rows.append(
                    {
                        "threads": threads,
                        "ndarray_args": n_args,
                        "parallel": parallel,
                        "kernels": n_kernels,
                        "us_per_run": best * 1e6,
                    }
                )
    return rows


def report(rows: list[dict]) -> None:
    base = next(r["us_per_run"] for r in rows if r["ndarray_args"] == 1 and not r["parallel"] and r["kernels"] == 1)
    print(f"{rows[0]['threads']} thread(s); baseline: one 1-argument serial kernel, {base:.1f} us per graph run")
    print(f"{'ndarrays':>8} {'loop':>9} {'kernels':>7} {'us/run':>8} {'us/kernel':>9} {'x baseline':>10}")
    for r in rows:
        print(
            f"{r['ndarray_args']:8d} {'parallel' if r['parallel'] else 'serial':>9} {r['kernels']:7d} "
            f"{r['us_per_run']:8.1f} {r['us_per_run'] / r['kernels']:9.1f} {r['us_per_run'] / base:10.1f}"
        )
    per_arg = [
        (a["us_per_run"] - b["us_per_run"]) / a["kernels"] / 9
        for a in rows
        for b in rows
        if a["ndarray_args"] == 10
        and b["ndarray_args"] == 1
        and not a["parallel"]
        and not b["parallel"]
        and a["kernels"] == b["kernels"]
    ]
    print(f"per ndarray argument per serial kernel: {min(per_arg):.2f}-{max(per_arg):.2f} us")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--threads", default="1,2", help="comma-separated thread counts")
    ap.add_argument("--child", type=int, default=None, help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.child is not None:
        print(json.dumps(measure(args.child)))
        return
    for t in args.threads.split(","):  # Taichi is initialised once per process
        proc = subprocess.run([sys.executable, __file__, "--child", t], capture_output=True, text=True)
        if proc.returncode != 0:
            sys.exit(f"benchmark child ({t} threads) failed:\n{proc.stderr[-3000:]}")
        report(json.loads(proc.stdout.strip().splitlines()[-1]))


if __name__ == "__main__":
    main()
