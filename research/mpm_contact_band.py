"""Cell size and contact band of the MPM wheel and plate (docs/mpm.md, "The contact band").

Grid contact puts every node closer than `band` cells outside the body in contact, so on the grid
the body acts about that much larger. This script runs the Table S1 wheel at a chosen cell size
and band, tabulates finished wheel runs over one common window, and fits the Fig 6 plate-drag
law with a chosen band.

    python research/mpm_contact_band.py wheel 30 --cell-mm 5 --band 0      # ~6 min, one thread
    python research/mpm_contact_band.py wheel 30 --cell-mm 2.5 --band 0    # ~35 min, one thread
    python research/mpm_contact_band.py wheel 90 --cell-mm 2.5 --small     # the Fig S1 wheel, ~32 min
    python research/mpm_contact_band.py wheel 90 --cell-mm 1.25 --small --band 0 --domain 0.6 0.5 --t-max 1.25  # ~1 h
    python research/mpm_contact_band.py wheel 30 --cell-mm 2.5 --band 0 --domain 1.0 0.4 --bed-depth 0.15 \
        --start-depth-mm 46 --t-max 4.0 --out runs/embedded  # starts embedded, ~23 min on 1 thread
    python research/mpm_contact_band.py wheel 30 --cell-mm 2.5 --band 0 --domain 1.0 0.4 --bed-depth 0.15 \
        --lug-count 30 --t-max 3.0 --out runs/lugs   # a 30-grouser wheel, ~30 min on 1 thread
    python research/mpm_contact_band.py wheel 30 --cell-mm 2.5 --band 0 --domain 1.0 0.4 --bed-depth 0.15 \
        --mass-z 9.45 --t-max 3.0 --out runs/load   # the wheel 1.5x as heavy
    python research/mpm_contact_band.py wheel 30 --cell-mm 2.5 --band 0 --domain 1.0 0.4 --bed-depth 0.15 \
        --push 0 --t-max 3.0 --out runs/push   # no forward push (Table S1's MPM runs: 4 N)
    python research/mpm_contact_band.py wheel 30 --cell-mm 2.5 --band 0 --domain 1.0 0.4 --bed-depth 0.15 \
        --fluidity-diameter 6e-3 --t-max 3.0 --threads 2 --out runs/coupled_ngf   # nonlocal law, 6 mm grains, ~20 min
    python research/mpm_contact_band.py wheel 42.4264 --small --cell-mm 2.5 --band 0 --domain 0.5 0.2 \
        --bed-depth 0.075 --fluidity-diameter 3e-3 --treadmill 0.325 0.25 --start-x 0.08 --youngs-modulus 5e5 \
        --ramp-time 0.10606602 --chunk 0.035355339 --t-max 3.2 --threads 2 --out runs/twin_scaled  # a Froude twin
    python research/mpm_contact_band.py table runs/band runs/mpm-2p5 runs/mpm9-graph
    python research/mpm_contact_band.py table runs/band --merge docs/figures/wheel_resolution.csv
    python research/mpm_contact_band.py sweep --band 0 --out research/outputs/mpm_band0/grousered_wheel_mpm_sweep.csv
    python research/mpm_contact_band.py sweep --band 0 --wheel small --out research/outputs/mpm_band0/small_grousered_wheel_mpm_sweep.csv
    python research/mpm_contact_band.py plate --band 0                     # 15 runs, ~11 min
    python research/mpm_contact_band.py plate --band 0 --cell-mm 5         # ~2 min

`table` reads every run folder under the given folders (their locomotion.json gives cell size and
band), averages v and sinkage over t = 0.65 s to --t-cut (default 2 s, the shortest runs' end),
prints a Markdown table and writes docs/figures/wheel_resolution.{png,csv} (the CSV has both
wheels, the figure the Table S1 wheel). With --merge, the rows
of an earlier table CSV are kept unless a run folder gives the same wheel, omega, cells and band
(run folders are not kept in git; the CSV is).

`sweep` turns a table CSV into an MPM sweep CSV (the format of `intrusim mpm sweep`, read by
`intrusim calibrate --mpm` and, in a --runs folder, by `intrusim reproduce --mpm`): for each omega
of one wheel, the row with the given band and the finest cells; a row whose velocity drifts by more
than --max-drift (default 0.3) between the window's halves is marked not ok (a wheel digging in).
"""

from __future__ import annotations

import argparse
import csv
import dataclasses
import json
from pathlib import Path

import numpy as np
from pydantic import ValidationError

from intrusim.mpm.config import SHAPES, FluidityConfig
from intrusim.scenarios import grousered_wheel_scenario, small_wheel_scenario
from intrusim.scenarios.locomotor import with_lug_count, with_mass_z
from intrusim.scenarios.mpm_locomotion import MPMSettings, paper_settings, run_mpm_steady, summarise_run, write_result


def run(args: argparse.Namespace) -> None:
    scenario = small_wheel_scenario() if args.small else grousered_wheel_scenario()
    try:
        if args.lug_count is not None:  # another wheel of the same hub, grousers and inertias
            scenario = with_lug_count(scenario, args.lug_count)
        if args.mass_z is not None:  # another load: the vertical mass (weight m_z g); m_x and the push kept
            scenario = with_mass_z(scenario, args.mass_z)
    except ValidationError as e:
        raise SystemExit(f"bad wheel: {e}") from None
    base = paper_settings("wheel")
    domain = tuple(args.domain) if args.domain else base.domain
    cells = tuple(round(L / (args.cell_mm * 1e-3)) for L in domain)
    settings = base.model_copy(update=dict(
        domain=domain, cells=cells, t_max=args.t_max, cpu_threads=args.threads, contact_band_cells=args.band))  # fmt: skip
    if args.bed_depth is not None:
        settings = settings.model_copy(update=dict(bed_depth=args.bed_depth))
    if args.start_depth_mm:
        settings = settings.model_copy(update=dict(start_depth=1e-3 * args.start_depth_mm))
    if args.push is not None:  # another constant forward push (Table S1: 4 N; < 0: a drawbar load)
        settings = settings.model_copy(update=dict(forward_force=args.push))
    if args.fluidity_diameter is not None:  # nonlocal fluidity with grains of this size (not the paper's law)
        try:
            fluidity = FluidityConfig(grain_diameter=args.fluidity_diameter)
        except ValidationError as e:
            raise SystemExit(f"bad --fluidity-diameter: {e}") from None
        settings = settings.model_copy(update=dict(fluidity=fluidity))
    scaled = {k: v for k, v in dict(start_x=args.start_x, youngs_modulus=args.youngs_modulus, ramp_time=args.ramp_time,
                                     chunk=args.chunk, cfl=args.cfl, flip=args.flip,
                                     shape=args.shape).items() if v is not None}  # fmt: skip
    if scaled:  # the set-up a Froude twin scales too: start, stiffness, spin-up, run-control interval (and C)
        try:
            settings = settings.validated_copy(**scaled)
        except ValidationError as e:
            raise SystemExit(f"bad setting: {e}") from None
    if args.treadmill is not None:  # a moving window: fresh bed comes in ahead, the rut leaves behind
        try:
            settings = settings.validated_copy(treadmill=tuple(args.treadmill))
        except ValidationError as e:
            raise SystemExit(f"bad --treadmill: {e}") from None
    tag = "" if args.domain is None else f"_{domain[0]:g}x{domain[1]:g}m"
    tag += "" if args.bed_depth is None else f"_bed{args.bed_depth:g}m"
    tag += f"_start{args.start_depth_mm:g}mm" if args.start_depth_mm else ""
    tag += "" if args.mass_z is None else f"_mz{args.mass_z:g}kg"
    tag += "" if args.push is None else f"_push{args.push:g}N"
    tag += "" if args.fluidity_diameter is None else f"_nonlocal{1e3 * args.fluidity_diameter:g}mm"
    tag += "" if args.treadmill is None else f"_treadmill{args.treadmill[0]:g}-{args.treadmill[1]:g}m"
    tag += "" if args.start_x is None else f"_x{args.start_x:g}m"
    tag += "" if args.youngs_modulus is None else f"_E{args.youngs_modulus:g}Pa"
    tag += "" if args.ramp_time is None else f"_ramp{args.ramp_time:g}s"
    tag += "" if args.chunk is None else f"_chunk{args.chunk:g}s"
    tag += "" if args.cfl is None else f"_cfl{args.cfl:g}"
    tag += "" if args.flip is None else f"_flip{args.flip:g}"
    tag += "" if args.shape is None else f"_{args.shape}"
    out = Path(args.out) / f"{scenario.name}_{args.rpm:g}rpm_{args.cell_mm:g}mm_band{args.band:g}{tag}"
    st = run_mpm_steady(
        scenario,
        settings,
        args.rpm,
        out,
        lambda d: print(json.dumps({k: round(v, 4) for k, v in d.items()}), flush=True),
    )
    write_result(out, st)
    print(json.dumps({k: round(v, 5) for k, v in st.summary().items()}))


def plate(args: argparse.Namespace) -> None:
    from intrusim.figures.mpm_plates import drag_fit, drag_points

    def vary(case):
        cells = tuple(round(L / (args.cell_mm * 1e-3)) for L in case.domain)
        return dataclasses.replace(case, contact_band_cells=args.band, cells=cells)

    tag = f"{args.cell_mm:g}mm_band{args.band:g}"
    out = Path(args.out)
    pts = drag_points(False, out / f"plate_points_{tag}", vary=vary)  # each point cached there
    K, lam, K_slow = drag_fit(pts)
    res = {"band_cells": args.band, "K_N_per_m": K, "lambda": lam, "K_slowest_N_per_m": K_slow, "points": pts,
           "cell_mm": args.cell_mm}  # fmt: skip
    (out / f"plate_drag_{tag}.json").write_text(json.dumps(res, indent=1))
    print(
        f"band {args.band:g}: K = {K:.0f} N/m, lambda = {lam:.2f}, K from the slowest runs = {K_slow:.0f} N/m (paper 580, 1.1)"
    )


def window_row(run_dir: Path, t_cut: float) -> dict[str, float | str] | None:
    """Steady state of one finished run over t = ramp + settle .. t_cut (None if not a wheel run)."""
    info_path, res_path = run_dir / "locomotion.json", run_dir / "result.json"
    if not (info_path.exists() and res_path.exists()):
        return None
    info = json.loads(info_path.read_text())
    if info["body"] != "wheel":
        return None
    s = MPMSettings.model_validate(info["settings"])
    st = summarise_run(run_dir, t_end=t_cut)
    res = json.loads(res_path.read_text())
    rpm = st.omega * 60 / (2 * np.pi)
    return {
        "wheel": "small" if st.radius < 0.08 else "large", "omega_rpm": round(rpm, 3), "cell_mm": 1e3 * s.h,
        "band_cells": s.contact_band_cells, "velocity": st.velocity, "sinkage": st.sinkage, "slip": st.slip,
        "drift": st.drift, "surface_drop_run": res.get("surface_drop", np.nan), "window_end": st.window[1],
        "run": str(run_dir),
    }  # fmt: skip


def _key(row: dict) -> tuple:
    return row["wheel"], round(float(row["omega_rpm"]), 3), float(row["cell_mm"]), float(row["band_cells"])


def read_table(path: str | Path) -> list[dict[str, float | str]]:
    """Rows of a table CSV (docs/figures/wheel_resolution.csv), numbers as floats."""
    with Path(path).open(newline="") as f:
        return [{k: (v if k in ("wheel", "run") else float(v)) for k, v in r.items()} for r in csv.DictReader(f)]


def sweep(args: argparse.Namespace) -> None:
    from intrusim.analysis.sweep import SweepResult

    best: dict[float, dict] = {}
    for r in read_table(args.table):
        if r["wheel"] == args.wheel and r["band_cells"] == args.band:
            w = r["omega_rpm"]
            if w not in best or r["cell_mm"] < best[w]["cell_mm"]:
                best[w] = r
    if not best:
        raise SystemExit(f"{args.table}: no {args.wheel}-wheel row with band {args.band:g}")

    def record(w: float, r: dict) -> dict:
        steady = r["drift"] <= args.max_drift
        return {
            "omega_rpm": w,
            "ok": steady,
            "velocity": r["velocity"],
            "sinkage": r["sinkage"],
            "slip": r["slip"],
            "drift": r["drift"],
            "surface_drop": r["surface_drop_run"],
            "cell_mm": r["cell_mm"],
            "error": "" if steady else f"not steady: v drifts by {r['drift']:.2f} over the window",
        }

    records = [record(w, r) for w, r in sorted(best.items())]
    name = "small_grousered_wheel" if args.wheel == "small" else "grousered_wheel"
    Path(args.out).parent.mkdir(parents=True, exist_ok=True)
    out = SweepResult(name, "mpm", None, records).to_csv(args.out)
    for r in records:
        if not r["ok"]:
            print(f"{r['omega_rpm']:g} RPM marked not ok: {r['error']}")
    print(f"wrote {out}: " + ", ".join(f"{w:g} RPM ({r['cell_mm']:g} mm)" for w, r in sorted(best.items())))


def table(args: argparse.Namespace) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    rows = [
        r for d in args.folders for p in sorted(Path(d).iterdir()) if p.is_dir() and (r := window_row(p, args.t_cut))
    ]
    if args.merge:
        new = {_key(r) for r in rows}
        rows += [r for r in read_table(args.merge) if _key(r) not in new]
    rows.sort(key=lambda r: (r["wheel"], r["omega_rpm"], r["band_cells"], -r["cell_mm"]))
    with_rpm = sorted({r["omega_rpm"] for r in rows}) if args.rpm is None else sorted(args.rpm)
    shown = [r for r in rows if r["omega_rpm"] in with_rpm]  # the CSV keeps every row
    print("| wheel | RPM | cells (mm) | band (cells) | v (m/s) | sinkage (mm) | slip | v drift | dh (mm, run window) |")
    print("|---|---|---|---|---|---|---|---|---|")
    for r in shown:
        print(
            f"| {r['wheel']} | {r['omega_rpm']:g} | {r['cell_mm']:g} | {r['band_cells']:g} | {r['velocity']:.4f} | {r['sinkage'] * 1e3:.1f} | "
            f"{r['slip']:.3f} | {r['drift']:.2f} | {r['surface_drop_run'] * 1e3:.1f} |"
        )
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    with (out / "wheel_resolution.csv").open("w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    fig, axes = plt.subplots(1, 2, figsize=(8.4, 3.6))
    colors = plt.cm.viridis(np.linspace(0, 0.9, len(with_rpm)))
    for rpm, color in zip(with_rpm, colors):
        for cell, marker, fill in ((5.0, "o", color), (2.5, "s", "none")):
            sel = sorted(
                (
                    r
                    for r in shown
                    if r["wheel"] == "large" and r["omega_rpm"] == rpm and abs(r["cell_mm"] - cell) < 1e-6
                ),
                key=lambda r: r["band_cells"],
            )
            if not sel:
                continue
            b = [r["band_cells"] * r["cell_mm"] for r in sel]  # physical band width, mm
            kw = dict(marker=marker, mfc=fill, color=color, ls="-" if cell == 5.0 else "--")
            axes[0].plot(b, [r["velocity"] for r in sel], label=f"{rpm:g} RPM, {cell:g} mm cells", **kw)
            axes[1].plot(b, [r["sinkage"] * 1e3 for r in sel], **kw)
    for ax, lab in zip(axes, ("v (m/s)", "sinkage (mm)")):
        ax.set(xlabel="contact band width = band x cell (mm)", ylabel=lab, xlim=(-0.3, 5.3))
    axes[0].legend(fontsize=6, ncol=2)
    fig.suptitle(f"Table S1 wheel: cell size and contact band (window 0.65-{args.t_cut:g} s)", fontsize=9)
    fig.tight_layout()
    fig.savefig(out / "wheel_resolution.png", dpi=120)
    print(f"wrote {out / 'wheel_resolution.png'} and .csv")


ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
sub = ap.add_subparsers(dest="cmd", required=True)
r = sub.add_parser("wheel", help="one wheel run")
r.add_argument("rpm", type=float)
r.add_argument("--cell-mm", type=float, default=5.0)
r.add_argument("--band", type=float, default=1.0, help="contact band, cells")
r.add_argument("--t-max", type=float, default=2.0)
r.add_argument("--threads", type=int, default=1)
r.add_argument("--small", action="store_true", help="the half-size wheel of Fig S1")
r.add_argument(
    "--domain",
    type=float,
    nargs=2,
    metavar=("LX", "LZ"),
    default=None,
    help="domain length and height, m (default: the paper's 1 m x 1 m); the bed depth is --bed-depth",
)
r.add_argument(
    "--bed-depth",
    type=float,
    default=None,
    metavar="M",
    help="undisturbed bed height, m (default: the scenario's, 0.3 m for the wheels)",
)
r.add_argument(
    "--start-depth-mm",
    type=float,
    default=0.0,
    metavar="MM",
    help="start with the wheel's lowest point MM below the surface, embedded (default: resting on it)",
)
r.add_argument(
    "--lug-count",
    type=int,
    default=None,
    metavar="N",
    help="N grousers instead of Table S1's (same size, hub and inertias): a new wheel for DRFT to predict",
)
r.add_argument(
    "--mass-z",
    type=float,
    default=None,
    metavar="KG",
    help="vertical mass of the wheel, kg (its weight m_z g; default: the scenario's, 6.3 kg for Table S1)",
)
r.add_argument(
    "--push",
    type=float,
    default=None,
    metavar="N",
    help="constant forward push on the wheel, N (default: Table S1's 4 N scaled by m_x; < 0 pulls back)",
)
r.add_argument(
    "--fluidity-diameter",
    type=float,
    default=None,
    metavar="D",
    help="nonlocal granular fluidity with grains of diameter D, m, in place of the paper's law (docs/mpm.md)",
)
r.add_argument(
    "--treadmill",
    type=float,
    nargs=2,
    metavar=("X_TRIGGER", "X_TARGET"),
    default=None,
    help="moving window: each time the wheel centre passes X_TRIGGER (m), the scene moves back to put it at "
    "X_TARGET, the rut leaving on the left and fresh bed coming in on the right; the run lasts --t-max",
)
r.add_argument(
    "--start-x", type=float, default=None, metavar="M", help="initial x of the wheel centre, m (default 0.16)"
)
r.add_argument(
    "--youngs-modulus",
    type=float,
    default=None,
    metavar="PA",
    help="the bed's numerical Young's modulus, Pa (default 1e6; sets dt = C h sqrt(rho_c / E))",
)
r.add_argument("--ramp-time", type=float, default=None, metavar="S", help="linear spin-up of omega, s (default 0.15)")
r.add_argument(
    "--chunk",
    type=float,
    default=None,
    metavar="S",
    help="run-control interval, s: progress lines, treadmill checks, snapshots (default 0.05)",
)
r.add_argument("--cfl", type=float, default=None, metavar="C", help="C of dt = C h sqrt(rho_c / E) (default 0.3)")
r.add_argument(
    "--flip",
    type=float,
    default=None,
    metavar="S",
    help="FLIP's share of the points' velocity update, 0-1 (default 0: APIC; docs/mpm.md)",
)
r.add_argument(
    "--shape",
    choices=SHAPES,
    default=None,
    help="shape functions of the transfers (default quadratic; linear: the cell's bilinear functions, "
    "as the paper's group's mpm-2d, with --flip 1)",
)
r.add_argument("--out", default="runs/resolution")
t = sub.add_parser("table", help="tabulate finished runs")
t.add_argument("folders", nargs="+")
t.add_argument("--t-cut", type=float, default=2.0)
t.add_argument(
    "--rpm",
    type=float,
    nargs="+",
    default=None,
    help="omegas printed and plotted (default: all); the CSV keeps every row",
)
t.add_argument("--out", default="docs/figures")
t.add_argument("--merge", help="an earlier table CSV whose rows are kept unless a run folder replaces them")
w = sub.add_parser("sweep", help="an MPM sweep CSV (for intrusim calibrate) from a table CSV")
w.add_argument("--table", default="docs/figures/wheel_resolution.csv")
w.add_argument("--band", type=float, default=0.0, help="contact band, cells")
w.add_argument(
    "--wheel", choices=("large", "small"), default="large", help="the Table S1 wheel or the half-size one of Fig S1"
)
w.add_argument(
    "--max-drift", type=float, default=0.3, help="rows whose v drifts more over the window are marked not ok"
)
w.add_argument("--out", required=True)
p = sub.add_parser("plate", help="the Fig 6 plate-drag fit (2.5 mm cells) with a given band")
p.add_argument("--band", type=float, default=1.0, help="contact band, cells")
p.add_argument("--cell-mm", type=float, default=2.5, help="cell size, mm (Fig 6 runs: 2.5)")
p.add_argument("--out", default="runs/band")
args = ap.parse_args()
{"wheel": run, "table": table, "plate": plate, "sweep": sweep}[args.cmd](args)
