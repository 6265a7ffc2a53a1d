"""The Table S1 wheel held at a fixed state: is the MPM force converged in cell size?

A coupled wheel finds the state (v, sinkage) where the grains' force balances its weight and the
4 N push. When that state moves with the cell size (docs/mpm.md, "Convergence in cell size"),
it can be because the force at a given state changes, or because a small force change moves the
balance far. This script separates the two: it drives the wheel with prescribed motion (centre
height z fixed, forward speed vx and omega reached by the 0.15 s ramp of the coupled runs) from a
bed at rest with the wheel already in place, and records the force on it.

    python examples/mpm_fixed_state.py run --cell-mm 2.5 --z 0.2102 --vx 0.148 --rpm 30   # ~5 min, 2 threads
    python examples/mpm_fixed_state.py run --cell-mm 1.25 --z 0.2007 --vx 0.1095 --rpm 30  # ~40 min
    python examples/mpm_fixed_state.py table runs/fixed --out docs/figures/wheel_fixed_state

`run` writes a run folder (resumable: run the same command again after a stop) named after the
state and cell size; with --snapshot-every S also particle snapshots every S seconds (VTK + PNG,
read by examples/shear_layer.py). `table` averages fx, fz and the moment (3D, N and N m, on the wheel) over
--window (default: the last 0.5 s, five grouser periods at 30 RPM) of each run and writes
NAME.csv and NAME.png (the force histories).
"""

from __future__ import annotations

import argparse
import csv
import json
import math
import time
from pathlib import Path

import numpy as np

from intrusim.analysis.steady import interval_means
from intrusim.mpm.config import FluidityConfig, MPMConfig, MuIConfig, PrescribedMotion
from intrusim.mpm.solver import Solver
from intrusim.scenarios import grousered_wheel_scenario
from intrusim.scenarios.locomotor import without_lugs
from intrusim.scenarios.mpm_locomotion import MPMSettings, mpm_config, paper_settings

DEFAULT_SWEEP_PAIRS = FluidityConfig.model_fields["sweep_pairs"].default
DEFAULT_CFL = MPMSettings.model_fields["cfl"].default

META = "fixed_state.json"
CHECKPOINT_EVERY = 0.1  # s: a held-wheel run at 0.625 mm takes an hour for 0.4 s


def fixed_state_config(args: argparse.Namespace, out: Path) -> MPMConfig:
    """The coupled wheel's config with the body held at height z, moving at (vx, omega)."""
    scenario = grousered_wheel_scenario()
    if args.lug_width is not None:
        scenario = scenario.model_copy(update=dict(lug_width=args.lug_width))
    scenario = without_lugs(scenario) if args.smooth else scenario
    domain = tuple(args.domain)
    cells = tuple(round(L / (args.cell_mm * 1e-3)) for L in domain)
    settings = paper_settings("wheel").model_copy(update=dict(
        domain=domain, cells=cells, bed_depth=args.bed_depth, start_x=args.start_x, t_max=args.t_max,
        cpu_threads=args.threads, contact_band_cells=args.band, cfl=args.cfl))  # fmt: skip
    payload = mpm_config(scenario, settings, args.rpm, out).model_dump()
    body = payload["intruders"][0]
    radius = float(np.max(np.linalg.norm(np.asarray(body["vertices"]), axis=1)))
    if not (settings.h < args.z - radius and args.z + radius < domain[1] - settings.h):
        raise SystemExit(f"--z {args.z} puts the wheel (radius {radius:.3g} m) outside the {domain[1]:g} m high domain")
    if args.z - radius >= args.bed_depth:
        raise SystemExit(f"--z {args.z} puts the wheel above the bed surface ({args.bed_depth:g} m): no contact")
    if args.snapshot_every is not None:
        payload["output"]["snapshot_every"] = args.snapshot_every
    payload["output"]["checkpoint_every"] = CHECKPOINT_EVERY
    payload["material"]["viscosity"] = args.viscosity
    if args.mu_i_diameter is not None:
        payload["material"]["mu_i"] = MuIConfig(grain_diameter=args.mu_i_diameter).model_dump()
    if args.fluidity_diameter is not None:
        payload["material"]["fluidity"] = FluidityConfig(grain_diameter=args.fluidity_diameter,
                                                         sweep_pairs=args.fluidity_sweep_pairs).model_dump()
    body["z"] = args.z
    body["motion"] = PrescribedMotion(
        vx=args.vx, omega=-args.rpm * 2 * math.pi / 60, ramp_time=settings.ramp_time).model_dump()  # fmt: skip
    return MPMConfig.model_validate(payload)


def run(args: argparse.Namespace) -> None:
    tag = f"z{1e3 * args.z:.1f}mm_v{1e3 * args.vx:.1f}mm_s_{args.rpm:g}rpm_{args.cell_mm:g}mm_band{args.band:g}"
    tag += "_smooth" if args.smooth else ""
    tag += f"_lug{1e3 * args.lug_width:g}mm" if args.lug_width is not None else ""
    tag += f"_eta{args.viscosity:g}" if args.viscosity > 0.0 else ""
    tag += f"_muI{1e3 * args.mu_i_diameter:g}mm" if args.mu_i_diameter is not None else ""
    tag += f"_ngf{1e3 * args.fluidity_diameter:g}mm" if args.fluidity_diameter is not None else ""
    tag += f"_sweeps{args.fluidity_sweep_pairs}" if args.fluidity_diameter is not None and args.fluidity_sweep_pairs != DEFAULT_SWEEP_PAIRS else ""
    tag += f"_cfl{args.cfl:g}" if args.cfl != DEFAULT_CFL else ""
    out = Path(args.out) / tag
    cfg = fixed_state_config(args, out)
    solver = Solver(cfg)
    if solver.continue_in_run_dir():
        print(f"resumed {out} at t = {solver.t:.3f} s", flush=True)
    out.mkdir(parents=True, exist_ok=True)
    meta = {"z": args.z, "vx": args.vx, "omega_rpm": args.rpm, "cell_mm": args.cell_mm, "band_cells": args.band,
            "bed_depth": args.bed_depth, "domain": list(args.domain), "smooth": args.smooth, "cfl": args.cfl,
            "lug_width": args.lug_width if args.lug_width is not None else grousered_wheel_scenario().lug_width}  # fmt: skip
    # (the material law, viscosity, mu_i or fluidity, is in the run folder's config.json)
    (out / META).write_text(json.dumps(meta, indent=1))

    def progress(s: Solver) -> None:
        r = s.rows[-1]
        if s.step_count % max(1, int(round(0.1 / s.dt))) < max(1, int(round(0.01 / s.dt))):
            print(f"t {r['time']:.2f} s  fx {r['fx']:+.2f} N  fz {r['fz']:.2f} N  M {r['moment']:+.3f} N m", flush=True)

    start = time.perf_counter()
    solver.run(progress=progress)
    meta["wall_s"] = time.perf_counter() - start  # this invocation only (a resumed run: since the resume)
    (out / META).write_text(json.dumps(meta, indent=1))
    print(f"wrote {out} in {meta['wall_s']:.0f} s")


def window_means(t: np.ndarray, window: float) -> dict[str, float]:
    """Mean force, moment and their ahead parts over the last ``window`` seconds of a time series."""
    t_end = float(t["time"][-1])
    cols = ("fx", "fz", "moment", "fx_ahead", "fz_ahead", "moment_ahead")
    # the samples after t_end - window (spaced 0.01 s: none within 2e-9 s of it)
    row = interval_means(t["time"], {c: t[c] for c in cols}, t_end - window + 2e-9, t_end)
    half = interval_means(t["time"], {c: t[c] for c in ("fx", "fz")}, t_end - 0.5 * window + 2e-9, t_end)
    row["fx_last_half"], row["fz_last_half"] = half["fx"], half["fz"]
    row["t_end"] = t_end
    return row


def table(args: argparse.Namespace) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    rows, series = [], []
    for folder in args.folders:
        for meta_path in sorted(Path(folder).glob(f"*/{META}")):
            run_dir = meta_path.parent
            if not (run_dir / "timeseries.csv").exists():
                continue
            meta = json.loads(meta_path.read_text())
            t = np.genfromtxt(run_dir / "timeseries.csv", delimiter=",", names=True)
            rows.append({**meta, **window_means(t, args.window), "run": str(run_dir)})
            series.append((meta, t))
    if not rows:
        raise SystemExit("no fixed-state run folders found")
    rows.sort(key=lambda r: (r.get("smooth", False), r["z"], r["vx"], -r["cell_mm"]))
    out = Path(args.out)
    out.parent.mkdir(parents=True, exist_ok=True)
    keys = list(dict.fromkeys(k for r in rows for k in r if k != "domain"))
    with out.with_suffix(".csv").open("w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=keys, extrasaction="ignore")
        w.writeheader()
        w.writerows(rows)
    print(f"| wheel | z (mm) | vx (m/s) | RPM | cells (mm) | fx (N) | fz (N) | moment (N m) | fx ahead | fz ahead | t end (s) |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        print(f"| {'smooth rim' if r.get('smooth') else 'grousered'} | {1e3 * r['z']:.1f} | {r['vx']:.4f} | {r['omega_rpm']:g} | {r['cell_mm']:g} | {r['fx']:+.2f} | "
              f"{r['fz']:.2f} | {r['moment']:+.3f} | {r['fx_ahead']:+.2f} | {r['fz_ahead']:.2f} | {r['t_end']:.2f} |")

    fig, axes = plt.subplots(2, 1, figsize=(8, 6.5), sharex=True)
    styles = {}
    for meta, t in series:
        state = (meta["z"], meta["vx"], meta["omega_rpm"], meta.get("smooth", False))
        styles.setdefault(state, ["-", "--", ":", "-."][len(styles) % 4])
        label = f"z {1e3 * meta['z']:.1f} mm, v {meta['vx']:.3f} m/s, {meta['cell_mm']:g} mm cells"
        label += ", smooth rim" if meta.get("smooth") else ""
        color = {5.0: "C0", 2.5: "C1", 1.25: "C2"}.get(float(meta["cell_mm"]), "C3")
        k = max(1, int(round(0.1 / np.median(np.diff(t["time"])))))  # one grouser period at 30 RPM
        smooth = lambda y: np.convolve(y, np.ones(k) / k, mode="valid")
        tt = smooth(t["time"])
        axes[0].plot(tt, smooth(t["fx"]), styles[state], color=color, label=label)
        axes[1].plot(tt, smooth(t["fz"]), styles[state], color=color)
    axes[0].axhline(-4.0, color="k", lw=0.8)
    axes[1].axhline(6.3 * 9.81, color="k", lw=0.8)
    axes[0].set_ylabel("fx on wheel (N)\n(balance: -4 N push)")
    axes[1].set_ylabel("fz on wheel (N)\n(balance: weight 61.8 N)")
    axes[1].set_xlabel("t (s), 0.1 s running mean")
    axes[0].legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(out.with_suffix(".png"), dpi=120)
    print(f"wrote {out.with_suffix('.csv')} and {out.with_suffix('.png')}")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = ap.add_subparsers(dest="cmd", required=True)
    r = sub.add_parser("run", help="one wheel held at (z, vx, omega)")
    r.add_argument("--z", type=float, required=True, help="wheel centre height above the floor, m")
    r.add_argument("--vx", type=float, required=True, help="forward speed, m/s")
    r.add_argument("--rpm", type=float, default=30.0)
    r.add_argument("--cell-mm", type=float, default=2.5)
    r.add_argument("--band", type=float, default=0.0, help="contact band, cells")
    r.add_argument("--t-max", type=float, default=1.5)
    r.add_argument("--domain", type=float, nargs=2, default=(0.7, 0.4), metavar=("LX", "LZ"))
    r.add_argument("--bed-depth", type=float, default=0.15)
    r.add_argument("--start-x", type=float, default=0.15)
    r.add_argument("--threads", type=int, default=2)
    r.add_argument("--smooth", action="store_true", help="the wheel's outer radius without grousers")
    r.add_argument("--lug-width", type=float, default=None, metavar="W",
                   help="m, grouser thickness (default: Table S1's; a check of the grousers' resolution)")
    r.add_argument("--snapshot-every", type=float, default=None, metavar="S",
                   help="s: particle snapshots (VTK + PNG, for examples/shear_layer.py)")
    r.add_argument("--viscosity", type=float, default=0.0, metavar="ETA",
                   help="Pa s: viscous overstress at yield (MaterialConfig.viscosity; a diagnostic, not the paper's law)")
    r.add_argument("--mu-i-diameter", type=float, default=None, metavar="D",
                   help="m: inertial-number friction mu(I) with grains of diameter D (MaterialConfig.mu_i, other "
                        "parameters at their defaults; not the paper's law)")
    r.add_argument("--fluidity-diameter", type=float, default=None, metavar="D",
                   help="m: nonlocal granular fluidity with grains of diameter D (MaterialConfig.fluidity, other "
                        "parameters at their defaults; not the paper's law)")
    r.add_argument("--fluidity-sweep-pairs", type=int, default=DEFAULT_SWEEP_PAIRS, metavar="N",
                   help="pairs of Jacobi sweeps of the fluidity per step (FluidityConfig.sweep_pairs)")
    r.add_argument("--cfl", type=float, default=DEFAULT_CFL, metavar="C",
                   help="time step dt = C h sqrt(rho_c / E) (MPMSettings.cfl; smaller: a check of the time step)")
    r.add_argument("--out", default="runs/fixed")
    t = sub.add_parser("table", help="window means of finished runs, CSV and figure")
    t.add_argument("folders", nargs="+")
    t.add_argument("--window", type=float, default=0.5, help="s, averaged at the end of each run")
    t.add_argument("--out", default="docs/figures/wheel_fixed_state")
    args = ap.parse_args()
    run(args) if args.cmd == "run" else table(args)


if __name__ == "__main__":
    main()
