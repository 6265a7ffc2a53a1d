"""Benchmark: how fast a Taichi CPU kernel streams memory, against memcpy in the same run.

The bound of `bench_mpm.py` divides the bytes a step must move by the copy bandwidth (the faster
of memcpy and a Taichi copy kernel). This asks what that bound asks of Taichi itself: a kernel
that only copies one f32 array into another (``b[i] = a[i]``, a field and an ndarray version),
at a size that sits in the last-level cache and at one that does not, on each thread count,
against ``np.copyto`` (memcpy, one thread) on the same arrays' sizes (both copies are
``bench_mpm.py``'s, the ones its bound uses):

    python benchmarks/bench_copy.py                       # threads 1 and all cores; 4 and 256 MiB
    python benchmarks/bench_copy.py --threads 2 --sizes 1,4,16,256

Prints GB/s (bytes read + written per second, best of --rounds) and the ratio memcpy / Taichi: the
factor by which the simplest Taichi loop is already slower than the copy the MPM bound uses.
"""

import argparse
import json
import os
import subprocess
import sys

from bench_mpm import copy_bandwidth, numpy_copy_bandwidth  # this folder: the step benchmark's copies


def measure(threads: int | None, sizes_mib: list[float], rounds: int) -> dict:
    """GB/s of memcpy and of the Taichi copy kernel (field, ndarray) at each size, on ``threads``."""
    from intrusim.mpm.backend import ensure_initialized

    ensure_initialized("cpu", "f32", threads)
    rows = []
    for mib in sizes_mib:
        n_bytes = int(mib * 2**20) // 4 * 4
        rows.append({"mib": mib, "memcpy": numpy_copy_bandwidth(n_bytes, rounds) / 1e9,
                     **{c: copy_bandwidth(n_bytes, rounds, c) / 1e9 for c in ("field", "ndarray")}})  # fmt: skip
    return {"threads": threads or os.cpu_count(), "rows": rows}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--threads", default="1,all", help="comma-separated thread counts ('all' = every core)")
    ap.add_argument("--sizes", default="4,256", help="comma-separated array sizes, MiB (each of the two arrays)")
    ap.add_argument("--rounds", type=int, default=20, help="timed copies per figure (the best counts)")
    ap.add_argument("--child", default=None, help=argparse.SUPPRESS)
    args = ap.parse_args()
    try:
        sizes = [float(s) for s in args.sizes.split(",")]
    except ValueError:
        ap.error(f"--sizes must be comma-separated numbers, got {args.sizes!r}")
    if not sizes or min(sizes) <= 0 or args.rounds < 1:
        ap.error("--sizes must be positive and --rounds >= 1")
    if args.child is not None:
        print(json.dumps(measure(None if args.child == "all" else int(args.child), sizes, args.rounds)))
        return
    print("copy of one f32 array into another (GB/s, read + write; best of", args.rounds, "rounds)")
    print(f"{'threads':>7} {'MiB':>7} {'memcpy':>8} {'field':>8} {'ndarray':>8} {'memcpy / Taichi':>16}")
    for t in args.threads.split(","):
        cmd = [sys.executable, __file__, "--child", t, "--sizes", args.sizes, "--rounds", str(args.rounds)]
        env = {**os.environ, "INTRUSIM_TI_THREADS": ""}  # the thread count is the child's argument
        proc = subprocess.run(cmd, capture_output=True, text=True, env=env)
        if proc.returncode != 0:
            sys.exit(f"benchmark child ({t} threads) failed:\n{proc.stderr[-3000:]}")
        res = json.loads(proc.stdout.strip().splitlines()[-1])
        for r in res["rows"]:
            best = max(r["field"], r["ndarray"])
            print(
                f"{res['threads']:>7} {r['mib']:>7g} {r['memcpy']:>8.1f} {r['field']:>8.1f} {r['ndarray']:>8.1f} {r['memcpy'] / best:>16.2f}"
            )


if __name__ == "__main__":
    main()
