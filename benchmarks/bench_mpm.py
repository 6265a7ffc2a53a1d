"""Benchmark: one explicit MPM step (issue: >= 30x the NumPy step, within 4x of a bandwidth bound).

For a resting bed of ~64k and ~160k material points (quadratic B-splines, the default transfer:
FLIP with a PIC share per step that falls with dt; Drucker-Prager with separation, walls) it prints, all measured in the same run:

* ms per step and particle-updates per second of the Taichi solver (``Solver.step``),
* the same step in vectorised NumPy (``mpm.reference_numpy.numpy_step``, float64, best of 4) and the ratio,
* on the CPU, the same step with G2P and P2G one point per loop iteration (``BenchmarkSwitches(simd_lanes =
  False)``, intrusim.mpm.backend) against the default kernels vectorised over 8 points, in alternate rounds,
* the same step with the kernels called one by one instead of as one compiled graph, and with
  P2G by atomic adds into one grid copy (a GPU's P2G), in 64-bit fixed point (reproducible, the
  default) and in float (rounding in the threads' order),
* a memory-bandwidth bound: the bytes one step must move at least (particle state read by P2G
  and G2P and written back by G2P, grid arrays written and read once) divided by the copy
  bandwidth of this machine (the fastest of a Taichi copy kernel on the same threads, Taichi's
  runtime copy of an ndarray, a device memcpy on a GPU, and memcpy on the host),
* optionally (``--rate-laws``) the step with the mu(I) friction and with the nonlocal fluidity
  (not the paper's law), as a ratio to the paper's law's step,
* optionally (``--transfers``) the step with the other transfers, in alternate rounds with the
  default (vectorised): APIC (``transfer.flip = 0``, the former default) vectorised and with the
  one-point kernels, FLIP (``transfer.flip = 1``) on quadratic B-splines and FLIP on linear shape
  functions (``transfer.shape = "linear"``, the paper's group's mpm-2d, one-point kernels), as ratios
  to the default; ``--only-transfers`` leaves out the other comparisons (lanes, atomics, launches),
* optionally (``--wheel``) the wall time of 1 s of physical time of the paper's wheel run
  (1 m x 1 m bed, 200 x 200 grid, 2 x 2 points per cell, coupled wheel at 60 RPM), extrapolated
  from a short run, and the same step with the wheel's dynamics on the host (its impulse read
  back every step, ``BenchmarkSwitches(device_bodies=False)``) instead of on the device.

Each thread count runs in its own process (Taichi is initialised once per process):

    python benchmarks/bench_mpm.py                 # threads: 1 and all cores
    python benchmarks/bench_mpm.py --threads 2 --wheel
    python benchmarks/bench_mpm.py --arch cuda --threads all --cases 64k,160k,1M,4M   # a GPU
    python benchmarks/bench_mpm.py --threads 2 --repeat 5   # 5 runs: how often each target is met
    python benchmarks/bench_mpm.py --threads 1,2 --no-numpy --transfers --cases 64k   # FLIP, linear
    python benchmarks/bench_mpm.py --threads 2 --no-numpy --only-transfers --repeat 3   # the default vs APIC

On the shared 2-core machines one run's ratios move by up to 1.5x from run to run (the NumPy step,
the copy bandwidth and the step all vary), so a verdict counts the runs that meet each target.
"""

import argparse
import json
import os
import subprocess
import sys
import time

import numpy as np

# (label, domain (m), cells, bed height (m)): 2 x 2 points per cell, h = 5 mm
CASES = {
    "64k": ((1.0, 1.0), (200, 200), 0.4),
    "160k": ((1.0, 1.2), (200, 240), 1.0),
    # larger beds for a GPU (--cases), where 64k points leave most of the chip idle
    "1M": ((2.5, 3.0), (500, 600), 2.5),
    "4M": ((5.0, 5.5), (1000, 1100), 5.0),
}
DEFAULT_CASES = "64k,160k"
NUMPY_MAX_POINTS = 200_000  # the NumPy baseline (seconds per step above this) runs up to this size
TARGET_X_NUMPY = 30.0  # issue #4: at least 30x the NumPy step ...
TARGET_X_BOUND = 4.0  # ... and within 4x of the bandwidth bound, on 2 cores
# per point, as the solver stores it (particles.py: sigma symmetric, 3 floats): P2G reads 13 (x 2, v 2,
# C 4, m, V, sigma 3), G2P reads 9 (x 2, m, V, sigma 3, s_yy, eps_p) and writes 15 (v 2, C 4, x 2, V,
# sigma 3, s_yy, eps_p, gdot_p)
PARTICLE_FLOATS = 13 + 9 + 15
GRID_FLOATS_PER_NODE = 3 * 4  # (m, p) written by P2G, read by the grid update; v written, read by G2P


def _sync() -> None:
    import taichi as ti

    ti.sync()


def numpy_copy_bandwidth(n_bytes: int = 256 * 2**20, rounds: int = 5) -> float:
    """Copy bandwidth (bytes moved per second: read + write) of ``np.copyto`` (memcpy), best of ``rounds``."""
    a = np.ones(n_bytes // 4, np.float32)
    b = np.zeros_like(a)
    best = np.inf
    for _ in range(rounds):
        t0 = time.perf_counter()
        np.copyto(b, a)
        best = min(best, time.perf_counter() - t0)
    return 2 * a.nbytes / best


def copy_bandwidth(n_bytes: int = 256 * 2**20, rounds: int = 5, container: str = "ndarray") -> float:
    """Copy bandwidth (bytes moved per second: read + write) of a Taichi kernel, best of ``rounds``;
    ``container``: the arrays are Taichi ndarrays (as the solver's) or fields; "runtime": no kernel,
    the ndarrays copied by Taichi's runtime (``Ndarray.copy_from``: a device-to-device memcpy on a
    GPU, whose own copy engine a simple kernel may not match)."""
    import taichi as ti

    from intrusim.mpm.backend import info

    if container not in ("ndarray", "field", "runtime"):
        raise ValueError(f"container must be 'ndarray', 'field' or 'runtime', got {container!r}")
    n = n_bytes // 4
    if container == "runtime":
        a = ti.ndarray(info().real, shape=n)
        b = ti.ndarray(info().real, shape=n)
        a.fill(1.0)

        def copy():
            b.copy_from(a)
    elif container == "ndarray":
        a = ti.ndarray(info().real, shape=n)
        b = ti.ndarray(info().real, shape=n)

        @ti.kernel
        def copy_ndarray(src: ti.types.ndarray(), dst: ti.types.ndarray()):
            for i in range(src.shape[0]):
                dst[i] = src[i]

        def copy():
            copy_ndarray(a, b)
    else:
        fa, fb = ti.field(info().real, n), ti.field(info().real, n)

        @ti.kernel
        def copy():
            for i in fa:
                fb[i] = fa[i]

    copy()
    _sync()
    best = np.inf
    for _ in range(rounds):
        t0 = time.perf_counter()
        copy()
        _sync()
        best = min(best, time.perf_counter() - t0)
    return 2 * n * 4 / best


RATE_LAWS = {  # --rate-laws: the options that are not the paper's law, against it in the same run
    "mu(I)": {"mu_i": {"grain_diameter": 1e-3}},
    "nonlocal fluidity": {"fluidity": {"grain_diameter": 1e-3}},
}


TRANSFERS = {  # label: TransferConfig fields (and simd_lanes) of the --transfers variants
    "APIC (the former default), vectorised": (dict(flip=0.0), True),
    "APIC, one-point kernels": (dict(flip=0.0), False),
    "FLIP, quadratic": (dict(flip=1.0), True),
    "FLIP, linear": (dict(flip=1.0, shape="linear"), True),
}


def bed_solver(
    domain,
    cells,
    bed_height,
    arch: str,
    p2g_chunks: int | None = None,
    step_graph: bool = True,
    material: dict | None = None,
    deterministic_sums: bool = True,
    simd_lanes: bool = True,
    transfer: dict | None = None,
):
    """The solver of a resting bed; ``step_graph`` and ``simd_lanes``: the benchmarks' switches of the
    step's code paths (``intrusim.mpm.backend.BenchmarkSwitches``, not settings of a run)."""
    from intrusim.mpm.backend import BenchmarkSwitches
    from intrusim.mpm.config import BedConfig, DomainConfig, MPMConfig, Rectangle
    from intrusim.mpm.solver import Solver

    cfg = MPMConfig(
        domain=DomainConfig(size=domain, cells=cells),
        material=material or {},
        bed=BedConfig(rectangles=[Rectangle(x0=0, z0=0, x1=domain[0], z1=bed_height)]),
        transfer=transfer or {},
        backend=dict(
            arch=arch,
            deterministic_sums=deterministic_sums,
            **({} if p2g_chunks is None else {"p2g_chunks": p2g_chunks}),
        ),
    )
    return Solver(cfg, switches=BenchmarkSwitches(step_graph=step_graph, simd_lanes=simd_lanes))


def time_steps(solver, min_time: float = 2.0) -> float:
    """Seconds per step (best of 3 rounds of at least ``min_time`` / 3 s each)."""
    for _ in range(5):  # compile and warm up
        solver.step()
    _sync()
    n = 10
    while True:
        t0 = time.perf_counter()
        for _ in range(n):
            solver.step()
        _sync()
        el = time.perf_counter() - t0
        if el > min_time / 3:
            break
        n *= 2
    best = el / n
    for _ in range(2):
        t0 = time.perf_counter()
        for _ in range(n):
            solver.step()
        _sync()
        best = min(best, (time.perf_counter() - t0) / n)
    return best


def time_alternating(solvers: dict, min_time: float = 2.0, rounds: int = 5) -> dict:
    """Seconds per step of each solver, timed in alternate rounds (so the machine's drift falls on
    all of them), best round of each."""
    per_step = time_steps(next(iter(solvers.values())), min_time / 3)
    return alternate_rounds(solvers, max(10, int(min_time / (rounds * len(solvers) * per_step))), rounds)


def alternate_rounds(solvers: dict, n: int, rounds: int) -> dict:
    """Best seconds per step of each solver over ``rounds`` rounds of ``n`` steps, the solvers taking
    turns within each round (each compiled and warmed up by 5 steps first)."""
    for solver in solvers.values():
        for _ in range(5):
            solver.step()
    _sync()
    best = {key: np.inf for key in solvers}
    for _ in range(rounds):
        for key, solver in solvers.items():
            t0 = time.perf_counter()
            for _ in range(n):
                solver.step()
            _sync()
            best[key] = min(best[key], (time.perf_counter() - t0) / n)
    return best


def time_numpy_step(solver, rounds: int = 4) -> float:
    """Seconds per step of the vectorised NumPy reference on the solver's current state."""
    from intrusim.mpm.reference_numpy import numpy_step

    state = {k: np.asarray(a, np.float64) for k, a in solver.particles.to_numpy().items()}
    args = (
        solver.h,
        solver.grid.pad,
        solver.grid.shape,
        solver.cfg.domain.size[0],
        solver.dt,
        solver.gravity,
        solver.material.params,
        tuple(zip(solver.walls.kinds, solver.walls.mus)),
        solver.cfg.material.rho_floor,
    )
    best = np.inf
    for _ in range(rounds):
        t0 = time.perf_counter()
        numpy_step(state, *args)
        best = min(best, time.perf_counter() - t0)
    return best


def wheel_seconds_per_physical_second(arch: str, physical: float = 0.02, rounds: int = 3) -> dict:
    """Wall seconds per physical second of the paper's wheel run (coupled, 60 RPM), with the body's
    dynamics on the device (the default) and on the host (its impulse read back every step): the two
    solvers run the same state in alternate rounds, so the machine's drift falls on both; best round."""
    from intrusim.mpm.backend import BenchmarkSwitches
    from intrusim.mpm.solver import Solver
    from intrusim.scenarios import grousered_wheel_scenario
    from intrusim.scenarios.mpm_locomotion import mpm_config, paper_settings

    s = paper_settings("wheel").model_copy(update=dict(arch=arch))
    solvers = {}
    for on_device in (True, False):
        cfg = mpm_config(grousered_wheel_scenario(), s, 60.0, None)
        solvers[on_device] = Solver(cfg, switches=BenchmarkSwitches(device_bodies=on_device))
    best = alternate_rounds(solvers, max(1, int(round(physical / rounds / solvers[True].dt))), rounds)
    solver = solvers[True]
    return {
        "particles": solver.particles.n,
        "dt": solver.dt,
        "ms_per_step": best[True] * 1e3,
        "wall_s_per_physical_s": best[True] / solver.dt,
        "host_body_ms_per_step": best[False] * 1e3,
    }


def measure(
    threads,
    arch: str,
    wheel: bool,
    numpy_baseline: bool,
    rate_laws: bool = False,
    cases: str = DEFAULT_CASES,
    transfers: bool = False,
    others: bool = True,
) -> dict:
    """All figures for one thread count (this process initialises Taichi)."""
    from intrusim.mpm.backend import ensure_initialized

    backend = ensure_initialized(arch, "f32", threads)
    if backend.fell_back:
        raise SystemExit(f"--arch {arch}: Taichi found no such device here (it would run on the CPU)")
    arch = backend.arch
    out: dict = {"threads": threads or os.cpu_count(), "arch": arch, "cases": {}}
    # the bound uses the fastest of a Taichi copy kernel on these threads, Taichi's runtime copy of
    # an ndarray (on a GPU: device memcpy) and memcpy on the host (one thread)
    out["taichi_copy_GBs"] = copy_bandwidth() / 1e9
    out["runtime_copy_GBs"] = copy_bandwidth(container="runtime") / 1e9
    out["memcpy_GBs"] = numpy_copy_bandwidth() / 1e9
    out["copy_bandwidth_GBs"] = max(out["taichi_copy_GBs"], out["runtime_copy_GBs"], out["memcpy_GBs"])
    for label in cases.split(","):
        domain, cells, bed = CASES[label]
        solver = bed_solver(domain, cells, bed, arch)
        n = solver.particles.n
        step = time_steps(solver)
        nodes = solver.grid.shape[0] * solver.grid.shape[1]
        bytes_min = n * PARTICLE_FLOATS * 4 + nodes * GRID_FLOATS_PER_NODE * 4
        bound = bytes_min / (out["copy_bandwidth_GBs"] * 1e9)
        row = {
            "particles": n,
            "ms_per_step": step * 1e3,
            "updates_per_s": n / step,
            "bytes_per_step": bytes_min,
            "bound_ms": bound * 1e3,
            "over_bound": step / bound,
        }
        if numpy_baseline and n <= NUMPY_MAX_POINTS:
            row["numpy_ms_per_step"] = time_numpy_step(solver) * 1e3
            row["speedup_vs_numpy"] = row["numpy_ms_per_step"] / row["ms_per_step"]
        out["cases"][label] = row
        del solver
        if not others:
            pass
        elif arch == "cpu":  # G2P and P2G one point per loop iteration against the vectorised ones (8 points), same run
            pair = time_alternating(
                {lanes: bed_solver(domain, cells, bed, arch, simd_lanes=lanes) for lanes in (True, False)}
            )
            row["lanes_pair_ms_per_step"] = (pair[True] * 1e3, pair[False] * 1e3)
        if others and arch == "cpu":  # a GPU's P2G on the CPU: atomic adds into one grid (p2g_chunks = 1), fixed point
            atomic = bed_solver(domain, cells, bed, arch, p2g_chunks=1)
            row["atomic_p2g_ms_per_step"] = time_steps(atomic) * 1e3
            del atomic
        if others:  # float atomic adds (backend.deterministic_sums = False): not bit-reproducible
            floats = bed_solver(domain, cells, bed, arch, p2g_chunks=1, deterministic_sums=False)
            row["float_atomic_ms_per_step"] = time_steps(floats) * 1e3
            del floats
            # the same step with one Python call per kernel instead of one compiled graph
            direct = bed_solver(domain, cells, bed, arch, step_graph=False)
            row["direct_launch_ms_per_step"] = time_steps(direct) * 1e3
            del direct
        if transfers:  # each other transfer against the default, alternate rounds (linear: one-point kernels)
            solvers = {"default": bed_solver(domain, cells, bed, arch)}
            solvers.update(
                {
                    k: bed_solver(domain, cells, bed, arch, transfer=t, simd_lanes=lanes)
                    for k, (t, lanes) in TRANSFERS.items()
                }
            )
            best = time_alternating(solvers)
            row["transfers_ms_per_step"] = {k: ms * 1e3 for k, ms in best.items()}
            del solvers
        if rate_laws:  # each rate law's step (all its kernels run on the resting bed too)
            row["rate_laws_ms_per_step"] = {
                name: time_steps(bed_solver(domain, cells, bed, arch, material=m)) * 1e3
                for name, m in RATE_LAWS.items()
            }
    if wheel:
        out["wheel"] = wheel_seconds_per_physical_second(arch)
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--threads", default="1,all", help="comma-separated thread counts ('all' = every core)")
    ap.add_argument("--arch", default="cpu", help="cpu, cuda, vulkan, metal")
    ap.add_argument("--wheel", action="store_true", help="also time the paper-resolution wheel run")
    ap.add_argument("--no-numpy", action="store_true", help="skip the (slow) NumPy baseline")
    ap.add_argument("--repeat", type=int, default=1, help="run the whole benchmark this many times and summarise")
    ap.add_argument(
        "--rate-laws", action="store_true", help="also time the step with mu(I) and with the nonlocal fluidity"
    )
    ap.add_argument(
        "--transfers", action="store_true", help="also time the step with APIC, FLIP and linear shape functions"
    )
    ap.add_argument(
        "--only-transfers",
        action="store_true",
        help="--transfers without the other comparisons (one-point kernels, atomics, kernel calls)",
    )
    ap.add_argument(
        "--cases",
        default=DEFAULT_CASES,
        help=f"comma-separated bed sizes from {', '.join(CASES)} (NumPy baseline up to {NUMPY_MAX_POINTS:,} points)",
    )
    ap.add_argument("--child", default=None, help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.repeat < 1:
        ap.error(f"--repeat must be >= 1, got {args.repeat}")
    unknown = [c for c in args.cases.split(",") if c not in CASES]
    if unknown:
        ap.error(f"--cases: unknown {unknown}; choose from {', '.join(CASES)}")
    if args.child is not None:
        threads = None if args.child == "all" else int(args.child)
        print(
            json.dumps(
                measure(
                    threads,
                    args.arch,
                    args.wheel,
                    not args.no_numpy,
                    args.rate_laws,
                    args.cases,
                    args.transfers or args.only_transfers,
                    not args.only_transfers,
                )
            )
        )
        return
    runs = []
    for k in range(args.repeat):
        results = []
        for t in args.threads.split(","):
            cmd = [sys.executable, __file__, "--child", t, "--arch", args.arch, "--cases", args.cases]
            cmd += ["--wheel"] if args.wheel else []
            cmd += ["--no-numpy"] if args.no_numpy else []
            cmd += ["--rate-laws"] if args.rate_laws else []
            cmd += ["--transfers"] if args.transfers else []
            cmd += ["--only-transfers"] if args.only_transfers else []
            env = {**os.environ, "INTRUSIM_TI_THREADS": ""}
            proc = subprocess.run(cmd, capture_output=True, text=True, env=env)
            if proc.returncode != 0:
                sys.exit(f"benchmark child ({t} threads) failed:\n{proc.stderr[-3000:]}")
            results.append(json.loads(proc.stdout.strip().splitlines()[-1]))
        if args.repeat > 1:
            print(f"run {k + 1} of {args.repeat}:")
        report(results, results[0]["arch"])
        runs.append(results)
    if args.repeat > 1:
        summarise(runs)


def summarise(runs: list[list[dict]]) -> None:
    """Per thread count and case: the spread of each figure over the runs and how often a target is met."""
    print(f"over {len(runs)} runs (min / median / max):")
    for j, first in enumerate(runs[0]):
        for label in first["cases"]:
            rows = [run[j]["cases"][label] for run in runs]
            line = f"{first['threads']} threads, {label}: " + ", ".join(
                f"{name} {_spread([r[key] for r in rows if key in r])}"
                for key, name in (
                    ("ms_per_step", "ms/step"),
                    ("speedup_vs_numpy", "x NumPy"),
                    ("over_bound", "x bound"),
                )
                if key in rows[0]
            )
            met_bound = sum(r["over_bound"] <= TARGET_X_BOUND for r in rows)
            line += f"; within {TARGET_X_BOUND:g}x of the bound in {met_bound} of {len(rows)}"
            if all("speedup_vs_numpy" in r for r in rows):
                met_numpy = sum(r["speedup_vs_numpy"] >= TARGET_X_NUMPY for r in rows)
                line += f", >= {TARGET_X_NUMPY:g}x NumPy in {met_numpy} of {len(rows)}"
            print(line)
            if all("transfers_ms_per_step" in r for r in rows):  # each transfer's step / the default's, same run
                for name in rows[0]["transfers_ms_per_step"]:
                    if name != "default":
                        ratios = [
                            r["transfers_ms_per_step"][name] / r["transfers_ms_per_step"]["default"] for r in rows
                        ]
                        print(f"{first['threads']} threads, {label}: {name} / the default: {_spread(ratios)}")


def _spread(values: list[float]) -> str:
    v = np.sort(np.asarray(values, float))
    return f"{v[0]:.2f} / {np.median(v):.2f} / {v[-1]:.2f}"


def report(results: list[dict], arch: str) -> None:
    """Print the tables of one run (one entry of ``results`` per thread count)."""
    print(f"MPM step benchmark ({arch}); NumPy baseline: vectorised float64 step, same state, same run")
    print(
        f"{'threads':>7} {'case':>5} {'points':>7} {'ms/step':>8} {'Mupd/s':>7} {'NumPy ms':>9} "
        f"{'x NumPy':>8} {'bound ms':>9} {'x bound':>8} {'copy GB/s':>9}"
    )
    for r in results:
        for label, c in r["cases"].items():
            print(
                f"{r['threads']:>7} {label:>5} {c['particles']:>7} {c['ms_per_step']:8.2f} "
                f"{c['updates_per_s'] / 1e6:7.1f} {c.get('numpy_ms_per_step', float('nan')):9.1f} "
                f"{c.get('speedup_vs_numpy', float('nan')):8.1f} {c['bound_ms']:9.3f} "
                f"{c['over_bound']:8.1f} {r['copy_bandwidth_GBs']:9.1f}"
            )
    for r in results:
        for label, c in r["cases"].items():
            if "atomic_p2g_ms_per_step" in c:
                print(
                    f"{r['threads']} threads, {label}: P2G with atomics into one grid (p2g_chunks = 1, 64-bit "
                    f"fixed point) {c['atomic_p2g_ms_per_step']:.2f} ms/step vs {c['ms_per_step']:.2f} chunked"
                )
            if "float_atomic_ms_per_step" in c:
                print(
                    f"{r['threads']} threads, {label}: P2G with float atomics (deterministic_sums = false, not "
                    f"bit-reproducible) {c['float_atomic_ms_per_step']:.2f} ms/step vs {c['ms_per_step']:.2f} the default"
                )
    for r in results:
        for label, c in r["cases"].items():
            if "lanes_pair_ms_per_step" in c:
                lanes, scalar = c["lanes_pair_ms_per_step"]
                print(
                    f"{r['threads']} threads, {label}: G2P and P2G one point per loop iteration (simd_lanes = False) "
                    f"{scalar:.2f} ms/step vs {lanes:.2f} vectorised over 8 points (alternate rounds, best of 5): "
                    f"{scalar / lanes:.2f}x"
                )
    for r in results:
        for label, c in r["cases"].items():
            if "direct_launch_ms_per_step" not in c:
                continue
            print(
                f"{r['threads']} threads, {label}: kernels called one by one (step_graph = False) "
                f"{c['direct_launch_ms_per_step']:.2f} ms/step vs {c['ms_per_step']:.2f} as one graph"
            )
    for r in results:
        for label, c in r["cases"].items():
            for name, ms in c.get("rate_laws_ms_per_step", {}).items():
                print(
                    f"{r['threads']} threads, {label}: {name} (not the paper's law) {ms:.2f} ms/step, "
                    f"{ms / c['ms_per_step']:.2f}x the paper's law's {c['ms_per_step']:.2f}"
                )
    for r in results:
        for label, c in r["cases"].items():
            t = c.get("transfers_ms_per_step")
            if t:
                print(
                    f"{r['threads']} threads, {label}: "
                    + ", ".join(
                        f"{name} {ms:.2f} ms/step ({ms / t['default']:.2f}x)"
                        for name, ms in t.items()
                        if name != "default"
                    )
                    + f"; the default (FLIP with a PIC share per step falling with dt, quadratic, vectorised) "
                    f"{t['default']:.2f} (alternate rounds, best of 5)"
                )
    for r in results:
        print(
            f"copy bandwidth ({r['threads']} threads): Taichi kernel {r['taichi_copy_GBs']:.1f} GB/s, "
            f"Taichi runtime copy {r['runtime_copy_GBs']:.1f} GB/s, host memcpy {r['memcpy_GBs']:.1f} GB/s "
            f"(bytes read + written per second)"
        )
    base = results[0]
    for r in results[1:]:
        for label in r["cases"]:
            print(
                f"thread scaling {label}: {base['threads']} -> {r['threads']} threads: "
                f"{base['cases'][label]['ms_per_step'] / r['cases'][label]['ms_per_step']:.2f}x"
            )
    for r in results:
        if "wheel" in r:
            w = r["wheel"]
            print(
                f"paper wheel ({r['threads']} threads): {w['particles']} points, dt {w['dt']:.3g} s, "
                f"{w['ms_per_step']:.2f} ms/step -> {w['wall_s_per_physical_s']:.0f} s wall per physical second; "
                f"with its dynamics on the host (impulse read back each step) {w['host_body_ms_per_step']:.2f} ms/step, "
                f"{w['host_body_ms_per_step'] / w['ms_per_step']:.2f}x"
            )


if __name__ == "__main__":
    main()
