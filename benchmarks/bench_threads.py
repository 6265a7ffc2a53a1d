"""Benchmark: what a second thread buys on this machine, for a kernel with nothing to share.

The MPM step's thread scaling (1 -> 2 threads) is set by the step and by the machine. This times
a Taichi kernel of pure arithmetic (each of 96,000 iterations runs a dependent chain of
``--work`` multiply-adds on its own value: no memory traffic, no atomics, ~100 tasks of equal
size) on 1 and on 2 threads, in separate processes, interleaved over ``--rounds`` rounds, so that
the scaling of this ideal loop is measured in the same minutes as the MPM step's. Per thread count
it prints the per-launch time (min / median of the rounds) and the CPU time of each thread,
as a share of the wall time (a worker below 100 % waited for work).

    python benchmarks/bench_threads.py                 # work 100 and 1000, 5 rounds
    python benchmarks/bench_threads.py --work 100 --rounds 9
"""

import argparse
import json
import os
import subprocess
import sys
import time
from pathlib import Path

N_ITEMS = 96_000  # the 2.5 mm wheel's point count (the Table S1 wheel in a 1 m x 0.15 m bed)


def _thread_cpu() -> dict[str, float]:
    """CPU seconds (user + system) of each thread of this process, from /proc."""
    tick = os.sysconf("SC_CLK_TCK")
    out = {}
    for task in Path("/proc/self/task").iterdir():
        fields = (
            (task / "stat").read_text().rsplit(")", 1)[1].split()
        )  # after "(comm)": utime, stime (fields 14, 15 of proc(5))
        out[task.name] = (int(fields[11]) + int(fields[12])) / tick
    return out


def measure(threads: int, work: int, seconds: float) -> dict:
    """Launch the kernel for ``seconds``: ms per launch and each busy thread's share of the wall time."""
    import taichi as ti

    ti.init(arch=ti.cpu, cpu_max_num_threads=threads, log_level=ti.WARN)
    a = ti.ndarray(ti.f32, shape=N_ITEMS)

    @ti.kernel
    def chain(a: ti.types.ndarray(), work: int):
        for i in range(a.shape[0]):  # x <- 0.999 x + 0.001, work times: latency-bound arithmetic
            x = a[i]
            for _ in range(work):
                x = x * 0.999 + 0.001
            a[i] = x

    chain(a, work)
    ti.sync()
    c0, t0, n = _thread_cpu(), time.perf_counter(), 0
    while time.perf_counter() - t0 < seconds:
        chain(a, work)
        n += 1
    ti.sync()
    wall = time.perf_counter() - t0
    c1 = _thread_cpu()
    shares = sorted(((c1[k] - c0.get(k, 0.0)) / wall for k in c1), reverse=True)
    return {
        "threads": threads,
        "work": work,
        "ms_per_launch": wall / n * 1e3,
        "launches": n,
        "busy_thread_shares": [round(s, 3) for s in shares if s > 0.02],
    }


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--work", default="100,1000", help="multiply-adds per item, comma-separated")
    ap.add_argument("--rounds", type=int, default=5)
    ap.add_argument("--seconds", type=float, default=2.0, help="per measurement")
    ap.add_argument("--child", nargs=2, type=int, metavar=("THREADS", "WORK"), help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.child:
        print(json.dumps(measure(*args.child, args.seconds)))
        return
    try:
        works = [int(w) for w in args.work.split(",")]
    except ValueError:
        ap.error(f"--work takes comma-separated integers, got {args.work!r}")
    if args.rounds < 1 or args.seconds <= 0 or min(works) < 1:
        ap.error("--rounds and every --work must be at least 1, --seconds positive")
    results: dict[tuple[int, int], list[dict]] = {}
    for r in range(args.rounds):
        for work in works:
            for threads in (1, 2):  # interleaved: each round measures both in the same minute
                out = subprocess.run(
                    [sys.executable, __file__, "--child", str(threads), str(work), "--seconds", str(args.seconds)],
                    capture_output=True,
                    text=True,
                    check=True,
                )
                results.setdefault((work, threads), []).append(json.loads(out.stdout.strip().splitlines()[-1]))
        print(f"round {r + 1}/{args.rounds} done", file=sys.stderr, flush=True)
    print(
        f"{'work':>6} {'threads':>7} {'ms/launch min':>13} {'median':>8} {'busy threads (share of wall), median run':>42}"
    )
    for work in works:
        med = {}
        for threads in (1, 2):
            rows = sorted(results[(work, threads)], key=lambda d: d["ms_per_launch"])
            ms = [d["ms_per_launch"] for d in rows]
            med[threads] = ms[len(ms) // 2]
            print(
                f"{work:6d} {threads:7d} {ms[0]:13.3f} {med[threads]:8.3f} {str(rows[len(rows) // 2]['busy_thread_shares']):>42}"
            )
        ratios = sorted(a["ms_per_launch"] / b["ms_per_launch"] for a, b in zip(results[(work, 1)], results[(work, 2)]))
        print(
            f"{'':6} 1 -> 2 threads: {med[1] / med[2]:.2f}x (median of the medians); per round "
            f"{ratios[0]:.2f}-{ratios[-1]:.2f}x"
        )


if __name__ == "__main__":
    main()
