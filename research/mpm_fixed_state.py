"""The Table S1 wheel held at a fixed state: is the MPM force converged in cell size?

A coupled wheel finds the state (v, sinkage) where the grains' force balances its weight and the
4 N push. When that state moves with the cell size (docs/mpm.md, "Convergence in cell size"),
it can be because the force at a given state changes, or because a small force change moves the
balance far. This script separates the two: it drives the wheel with prescribed motion (centre
height z fixed, forward speed vx and omega reached by the 0.15 s ramp of the coupled runs) from a
bed at rest with the wheel already in place, and records the force on it.

    python research/mpm_fixed_state.py run --cell-mm 2.5 --z 0.2102 --vx 0.148 --rpm 30   # ~5 min, 2 threads
    python research/mpm_fixed_state.py run --cell-mm 1.25 --z 0.2007 --vx 0.1095 --rpm 30  # ~40 min
    python research/mpm_fixed_state.py table runs/fixed --out research/outputs/wheel_fixed_state

`switch` starts from a free (coupled) run's last checkpoint instead of a bed at rest: the wheel
keeps its height, its forward speed is held at the free run's mean over --window (times --vx-scale),
and omega is set to --rpm; the free run's bed, wake and treadmill come with it. Held at the free
state with the free run's omega it is the control (its force should stay at the free balance);
at another omega (with --vx-scale keeping the slip) it measures whether the force at that state
depends on omega:

    python research/mpm_fixed_state.py switch runs/nl10/RUN --rpm 30 --vx-scale 3 --duration 1.0 --out runs/switch10

`run` writes a run folder (resumable: run the same command again after a stop) named after the
state and cell size; with --snapshot-every S also particle snapshots every S seconds (VTK + PNG,
read by research/shear_layer.py). `table` averages fx, fz and the moment (3D, N and N m, on the wheel) over
--window (default: the last 0.5 s, five grouser periods at 30 RPM) of each run and writes
NAME.csv and NAME.png (the force histories); with --after-switch S, for `switch` runs, also
NAME_after_switch.csv, the means over consecutive S-second windows from the switch (how the held
force settles).
"""

from __future__ import annotations

import argparse
import csv
import json
import math
import time
from pathlib import Path

import numpy as np

from intrusim.analysis.steady import interval_means, window_means
from intrusim.mpm import io as mpm_io
from intrusim.mpm.config import FluidityConfig, MPMConfig, MuIConfig, PrescribedMotion
from intrusim.mpm.solver import CHECKPOINT, Solver
from intrusim.scenarios import grousered_wheel_scenario
from intrusim.scenarios.locomotor import without_lugs
from intrusim.scenarios.mpm_locomotion import MPMSettings, mpm_config, paper_settings, treadmill_shift

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
        payload["material"]["fluidity"] = FluidityConfig(
            grain_diameter=args.fluidity_diameter, sweep_pairs=args.fluidity_sweep_pairs
        ).model_dump()
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
    tag += (
        f"_sweeps{args.fluidity_sweep_pairs}"
        if args.fluidity_diameter is not None and args.fluidity_sweep_pairs != DEFAULT_SWEEP_PAIRS
        else ""
    )
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


def held_from_free(
    free: Path, rpm: float, vx_scale: float, window: float, duration: float, out_root: Path, threads: int | None = None
) -> tuple[Solver, dict, Path, dict, tuple]:
    """The solver of a wheel held from ``free``'s last checkpoint (not yet restored), its META, its
    folder, the free run's locomotion.json and its checkpoint as read (arrays, meta).

    Held: the coupled motion with x and z frozen (free_x, free_z False), so the body keeps the
    velocity it is given and moves with the treadmill's shifts; omega ``rpm`` (the free run's sense
    of rotation); forward speed = ``vx_scale`` x the free run's mean vx over its last ``window`` s."""
    cfg_path, ckpt = free / "config.json", free / CHECKPOINT
    if not cfg_path.exists() or not ckpt.exists():
        raise SystemExit(f"{free}: not a run folder with a checkpoint (config.json, {CHECKPOINT})")
    payload = json.loads(cfg_path.read_text())["config"]
    body = payload["intruders"][0]
    if body["motion"]["kind"] != "coupled":
        raise SystemExit(f"{free}: the body is not coupled (free); nothing to hold")
    if not (rpm > 0 and vx_scale > 0 and window > 0 and duration > 0):
        raise SystemExit("--rpm, --vx-scale, --window and --duration must be positive")
    checkpoint = mpm_io.load_checkpoint(ckpt)
    meta_ck = checkpoint[1]
    t0 = meta_ck["step_count"] * meta_ck["dt"]
    ts = mpm_io.read_timeseries(free / "timeseries.csv")
    if ts["time"][0] > t0 - window:
        raise SystemExit(f"{free}: the window {window:g} s is longer than the run before its checkpoint ({t0:.3f} s)")
    means = interval_means(ts["time"], {"vx": ts["vx"], "z": ts["z"]}, t0 - window + 2e-9, t0 + 1e-9)
    state = meta_ck["bodies"][0]
    sign = math.copysign(1.0, body["motion"]["omega"])
    body["motion"].update(omega=sign * rpm * 2 * math.pi / 60, free_x=False, free_z=False)
    payload["time"]["t_end"] = t0 + duration
    if threads is not None:
        payload["backend"]["cpu_threads"] = threads
    loco = json.loads((free / "locomotion.json").read_text())
    vx = vx_scale * means["vx"]
    out = out_root / f"{free.name}_held{rpm:g}rpm_v{1e3 * vx:.1f}mm_s"
    payload["output"]["directory"] = str(out)
    settings = loco["settings"]
    free_rpm = float(loco["omega_rpm"])
    info = {"z": state["z"], "vx": vx, "omega_rpm": rpm, "cell_mm": 1e3 * settings["domain"][0] / settings["cells"][0],
            "band_cells": settings["contact_band_cells"], "bed_depth": settings["bed_depth"], "domain": settings["domain"],
            "smooth": False, "cfl": settings["cfl"], "lug_width": loco["scenario"]["lug_width"],
            "from_run": str(free), "t_switch": t0, "free_rpm": free_rpm, "free_vx_mean": means["vx"],
            "free_z_mean": means["z"], "free_window": window, "vx_scale": vx_scale,
            "treadmill": settings.get("treadmill")}  # fmt: skip
    return Solver(MPMConfig.model_validate(payload)), info, out, loco, checkpoint


def switch(args: argparse.Namespace) -> None:
    free = Path(args.free_run)
    solver, info, out, loco, checkpoint = held_from_free(
        free, args.rpm, args.vx_scale, args.window, args.duration, Path(args.out), args.threads)  # fmt: skip
    body = solver.intruders[0]
    if solver.continue_in_run_dir():
        print(f"resumed {out} at t = {solver.t:.3f} s", flush=True)
    else:
        solver.restore(*checkpoint)
        body.state.vx, body.state.vz = info["vx"], 0.0  # the next row averages from the free run's last record
    out.mkdir(parents=True, exist_ok=True)
    # the free run's locomotion.json at the held omega, so that the tools that read a locomotion run
    # folder (drft_at_mpm_state.py: DRFT's force along the held motion) read this one too
    (out / "locomotion.json").write_text(json.dumps({**loco, "omega_rpm": args.rpm, "held": info}, indent=1))
    t_end, chunk = info["t_switch"] + args.duration, 0.05
    if solver.t >= t_end - 0.5 * solver.dt:
        print(f"{out}: already held to t = {solver.t:.3f} s")  # its fixed_state.json (and wall time) kept
        return
    (out / META).write_text(json.dumps(info, indent=1))
    treadmill = info["treadmill"]
    treadmill_shift(
        solver, body, treadmill
    )  # resumed at a chunk's end from the checkpoint written before that chunk's shift
    start = time.perf_counter()
    t_next = info["t_switch"] + chunk * math.floor((solver.t - info["t_switch"]) / chunk + 0.5)
    while solver.t < t_end - 0.5 * solver.dt:
        t_next = min(t_next + chunk, t_end)
        solver.run(t_end=t_next, checkpoint_end=False)
        r = solver.rows[-1]
        print(
            json.dumps(
                {
                    "t": round(solver.t, 4),
                    "x": round(body.state.x + solver.x_offset, 4),
                    "z": round(body.state.z, 5),
                    "fx": round(r["fx"], 3),
                    "fz": round(r["fz"], 3),
                    "wall": round(time.perf_counter() - start, 1),
                }
            ),
            flush=True,
        )
        treadmill_shift(solver, body, treadmill)
    solver.checkpoint_run_folder()
    info["wall_s"] = time.perf_counter() - start  # this invocation only (a resumed run: since the resume)
    (out / META).write_text(json.dumps(info, indent=1))
    print(f"wrote {out} in {info['wall_s']:.0f} s")


def last_window_means(t: dict[str, np.ndarray], window: float) -> dict[str, float]:
    """Mean force, moment and their ahead parts over the last ``window`` seconds of a time series."""
    t_end = float(t["time"][-1])
    cols = ("fx", "fz", "moment", "fx_ahead", "fz_ahead", "moment_ahead")
    # the samples after t_end - window (spaced 0.01 s: none within 2e-9 s of it)
    row = interval_means(t["time"], {c: t[c] for c in cols}, t_end - window + 2e-9, t_end)
    half = interval_means(t["time"], {c: t[c] for c in ("fx", "fz")}, t_end - 0.5 * window + 2e-9, t_end)
    row["fx_last_half"], row["fz_last_half"] = half["fx"], half["fz"]
    row["t_end"] = t_end
    return row


def after_switch_means(t: dict[str, np.ndarray], t_switch: float, every: float) -> list[dict[str, float]]:
    """Mean force and moment over consecutive ``every``-second windows (t0, t1] from the switch: how
    the held wheel's force settles (``t_start``, ``t_end`` in seconds since the switch). Windows the
    series covers to within one record interval only (the last record falls up to one interval
    before the end of the hold)."""
    if not every > 0.0:
        raise SystemExit(f"--after-switch must be positive, got {every}")
    cols = {c: t[c] for c in ("fx", "fz", "moment")}
    return window_means(t["time"], cols, every, origin=t_switch, right_closed=True, whole_only=True)


def table(args: argparse.Namespace) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    rows, series, windows = [], [], []
    for folder in args.folders:
        for meta_path in sorted(Path(folder).glob(f"*/{META}")):
            run_dir = meta_path.parent
            if not (run_dir / "timeseries.csv").exists():
                continue
            meta = json.loads(meta_path.read_text())
            t = mpm_io.read_timeseries(run_dir / "timeseries.csv")
            rows.append({**meta, **last_window_means(t, args.window), "run": str(run_dir)})
            series.append((meta, t))
            if args.after_switch is not None and "t_switch" in meta:
                windows.extend({"omega_rpm": meta["omega_rpm"], "vx": meta["vx"], "z": meta["z"], **w}
                               for w in after_switch_means(t, meta["t_switch"], args.after_switch))  # fmt: skip
    if not rows:
        raise SystemExit("no fixed-state run folders found")
    if args.after_switch is not None and not windows:
        raise SystemExit("--after-switch: no held (`switch`) run among the folders, or none held a whole window")
    rows.sort(key=lambda r: (r.get("smooth", False), r["z"], r["vx"], -r["cell_mm"]))
    out = Path(args.out)
    out.parent.mkdir(parents=True, exist_ok=True)
    keys = list(dict.fromkeys(k for r in rows for k in r if k != "domain"))
    with out.with_suffix(".csv").open("w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=keys, extrasaction="ignore")
        w.writeheader()
        w.writerows(rows)
    if windows:
        path = out.with_name(out.name + "_after_switch.csv")
        with path.open("w", newline="") as f:
            w = csv.DictWriter(f, fieldnames=list(windows[0]))
            w.writeheader()
            w.writerows(windows)
        print(f"wrote {path}: {len(windows)} windows of {args.after_switch:g} s after the switch")
    print(
        "| wheel | z (mm) | vx (m/s) | RPM | cells (mm) | fx (N) | fz (N) | moment (N m) | fx ahead | fz ahead | t end (s) |"
    )
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        print(
            f"| {'smooth rim' if r.get('smooth') else 'grousered'} | {1e3 * r['z']:.1f} | {r['vx']:.4f} | {r['omega_rpm']:g} | {r['cell_mm']:g} | {r['fx']:+.2f} | "
            f"{r['fz']:.2f} | {r['moment']:+.3f} | {r['fx_ahead']:+.2f} | {r['fz_ahead']:.2f} | {r['t_end']:.2f} |"
        )

    fig, axes = plt.subplots(2, 1, figsize=(8, 6.5), sharex=True)
    styles = {}
    for meta, t in series:
        state = (meta["z"], meta["vx"], meta["omega_rpm"], meta.get("smooth", False))
        styles.setdefault(state, ["-", "--", ":", "-."][len(styles) % 4])
        label = f"z {1e3 * meta['z']:.1f} mm, v {meta['vx']:.3f} m/s, {meta['cell_mm']:g} mm cells"
        label += ", smooth rim" if meta.get("smooth") else ""
        color = {5.0: "C0", 2.5: "C1", 1.25: "C2"}.get(float(meta["cell_mm"]), "C3")
        k = max(1, int(round(0.1 / np.median(np.diff(t["time"])))))  # one grouser period at 30 RPM

        def smooth(y, k=k):
            return np.convolve(y, np.ones(k) / k, mode="valid")

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
    r.add_argument(
        "--lug-width",
        type=float,
        default=None,
        metavar="W",
        help="m, grouser thickness (default: Table S1's; a check of the grousers' resolution)",
    )
    r.add_argument(
        "--snapshot-every",
        type=float,
        default=None,
        metavar="S",
        help="s: particle snapshots (VTK + PNG, for research/shear_layer.py)",
    )
    r.add_argument(
        "--viscosity",
        type=float,
        default=0.0,
        metavar="ETA",
        help="Pa s: viscous overstress at yield (MaterialConfig.viscosity; a diagnostic, not the paper's law)",
    )
    r.add_argument(
        "--mu-i-diameter",
        type=float,
        default=None,
        metavar="D",
        help="m: inertial-number friction mu(I) with grains of diameter D (MaterialConfig.mu_i, other "
        "parameters at their defaults; not the paper's law)",
    )
    r.add_argument(
        "--fluidity-diameter",
        type=float,
        default=None,
        metavar="D",
        help="m: nonlocal granular fluidity with grains of diameter D (MaterialConfig.fluidity, other "
        "parameters at their defaults; not the paper's law)",
    )
    r.add_argument(
        "--fluidity-sweep-pairs",
        type=int,
        default=DEFAULT_SWEEP_PAIRS,
        metavar="N",
        help="pairs of Jacobi sweeps of the fluidity per step (FluidityConfig.sweep_pairs)",
    )
    r.add_argument(
        "--cfl",
        type=float,
        default=DEFAULT_CFL,
        metavar="C",
        help="time step dt = C h sqrt(rho_c / E) (MPMSettings.cfl; smaller: a check of the time step)",
    )
    r.add_argument("--out", default="runs/fixed")
    s = sub.add_parser("switch", help="a free run's wheel held from its last checkpoint, at its own or another omega")
    s.add_argument("free_run", help="run folder of a free (coupled) wheel, with its checkpoint")
    s.add_argument("--rpm", type=float, required=True, help="omega of the held wheel")
    s.add_argument("--vx-scale", type=float, default=1.0, help="held forward speed / the free run's mean")
    s.add_argument("--window", type=float, default=1.0, help="s: the free run's mean vx over its last WINDOW s")
    s.add_argument("--duration", type=float, default=1.0, help="s held")
    s.add_argument("--threads", type=int, default=None)
    s.add_argument("--out", default="runs/switch")
    t = sub.add_parser("table", help="window means of finished runs, CSV and figure")
    t.add_argument("folders", nargs="+")
    t.add_argument("--window", type=float, default=0.5, help="s, averaged at the end of each run")
    t.add_argument(
        "--after-switch",
        type=float,
        default=None,
        metavar="S",
        help="also write OUT_after_switch.csv: means over consecutive S-second windows from the switch",
    )
    t.add_argument("--out", default="research/outputs/wheel_fixed_state")
    args = ap.parse_args()
    {"run": run, "switch": switch, "table": table}[args.cmd](args)


if __name__ == "__main__":
    main()
