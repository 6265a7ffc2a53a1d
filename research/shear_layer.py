"""How thick are the shear zones under the wheel, and do they converge as the cells shrink?

The rate-independent Drucker-Prager law has no length of its own (no grain size, no rate), so
nothing in the continuum sets the thickness of a shear zone: in the MPM only the grid can. This
script measures the zones under the wheel held at a fixed state (`research/mpm_fixed_state.py
run ... --snapshot-every S`, one run per cell size) from the particle snapshots in a time window:

* the profile of the grains' speed along the rim's motion (backwards at the bottom of a wheel
  rolling forwards) against the radial depth below the rim, from the points within --sector-deg
  of the downward vertical through the centre, pooled over the window's snapshots, in depth bins
  of half a cell (the points' initial spacing), and the strain rate gdot_p on the same bins;
* the profile's 90-10 and 75-25 widths: the depth over which that speed falls from 90 % to 10 %
  (75 % to 25 %) of its largest value (the layer the rim drags along);
* that largest speed against the rim's own at its lowest point, omega r - v;
* the 50th, 90th and 99th percentiles of gdot_p over the points around the wheel that shear
  faster than 1/s, snapshot by snapshot, averaged over the window (the fastest shear, which
  grows as the bands thin), and the area shearing faster than 1 and 10 /s;
* the inertial number I = gdot_p d sqrt(rho_s / P) of the same points (poppy seeds: d = 1 mm,
  rho_s = 1100 kg/m^3, Table S1), 50th, 90th and 99th percentiles: the paper argues I stays small
  under intruders, so that a mu(I) law would change little;
* the mean force on the wheel over the same window (timeseries.csv);
* with the nonlocal fluidity, the cooperativity length xi = A d / sqrt(|mu - mu_s|) over the points
  around the wheel shearing faster than 10 /s at the run's last checkpoint (mu = tau / P of their
  stress), median in mm and in cells: a band is resolved when xi spans a few cells.

    python research/mpm_fixed_state.py run --cell-mm 2.5 --z 0.2102 --vx 0.148 --rpm 30 --smooth \\
        --t-max 0.5 --snapshot-every 0.025 --out runs/shear          # and 5, 1.25 mm; without --smooth
    python research/mpm_fixed_state.py run --cell-mm 0.625 ... --smooth --t-max 0.4 --domain 0.45 0.4 \\
        --snapshot-every 0.025 --out runs/shear_small                 # and 1.25 mm, the same box
    python research/mpm_fixed_state.py run ... --viscosity 10 --out runs/shear_visc       # the rate laws
    python research/mpm_fixed_state.py run ... --mu-i-diameter 1e-3 --out runs/shear_mui  # (5, 2.5, 1.25 mm,
    python research/mpm_fixed_state.py run ... --fluidity-diameter 1e-3 --out runs/shear_ngf  # grousered)
    python research/mpm_fixed_state.py run ... --fluidity-diameter 3e-3 --out runs/shear_ngf  # and at 2.5 mm:
    python research/mpm_fixed_state.py run ... --fluidity-diameter 1e-3 --fluidity-sweep-pairs 8 --out runs/shear_ngf
    python research/mpm_fixed_state.py run --cell-mm 1.25 ... --fluidity-diameter 3e-3 --fluidity-sweep-pairs 8 --out runs/shear_ngf
    python research/mpm_fixed_state.py run ... [--smooth] --fluidity-diameter 6e-3 --out runs/shear_ngf   # 5, 2.5, 1.25 mm;
    python research/mpm_fixed_state.py run ... --smooth --fluidity-diameter 3e-3 --out runs/shear_ngf     # (item 8)
    python research/mpm_fixed_state.py run --cell-mm 2.5 ... [--fluidity-diameter 3e-3] --cfl 0.15 --out runs/shear_ngf|runs/shear_dt
    python research/mpm_fixed_state.py run --cell-mm 0.625 ... --t-max 0.4 --domain 0.45 0.4 --fluidity-diameter 6e-3 \\
        --snapshot-every 0.025 --out runs/shear_ngf_small                   # and 1.25 mm, the same box (item 9)
    python research/shear_layer.py runs/shear runs/shear_small runs/shear_visc runs/shear_mui runs/shear_ngf \\
        runs/shear_dt runs/shear_ngf_small --out research/outputs/shear_layer

Writes NAME.csv (one row per run), NAME_profiles.csv (the binned profiles), NAME.png (profiles,
widths, the 99th percentile and the lift against the cell size) and NAME_fields.png (gdot_p around the
wheel at the window's last snapshot), and prints the table and the power laws c h^b fitted per
series of runs (a width the grid sets goes as h^1, a converged one as h^0).
"""

from __future__ import annotations

import argparse
import csv
import json
import sys
from pathlib import Path

import numpy as np

from intrusim.analysis.steady import interval_means
from intrusim.mpm.config import FluidityConfig
from intrusim.mpm.constitutive import pressure as mean_pressure
from intrusim.mpm.io import read_timeseries
from intrusim.mpm.solver import CHECKPOINT
from intrusim.params import RPM, table_s1
from intrusim.scenarios import grousered_wheel_scenario
from intrusim.scenarios.mpm_locomotion import MPMSettings

META = "fixed_state.json"
LUG_WIDTH = (
    grousered_wheel_scenario().lug_width
)  # m, Table S1's grouser thickness (named in a series only when not this)
RIM_RADIUS = grousered_wheel_scenario().radius  # m, the Table S1 wheel's outer radius (the smooth rim of --smooth)
DEPTH_RANGE = (-0.004, 0.06)  # m below the rim's lowest point
FIELD_BOX = (0.05, 0.2, -0.17)  # m: points within 0.2 of 0.05 ahead of the centre, above 0.17 below it
FLOW_RATES = (1.0, 10.0)  # 1/s: the area of grains shearing faster than each (cm^2 per m of width)
PERCENTILES = (50.0, 90.0, 99.0)  # of gdot_p over the points near the wheel shearing faster than 1/s
GRAIN_DIAMETER = 1.0e-3  # m, poppy seeds (~1 mm; not in Table S1)
GRAIN_DENSITY = table_s1()["poppy_seeds"]["grain_density"]  # kg/m^3
DEFAULT_SWEEP_PAIRS = FluidityConfig.model_fields["sweep_pairs"].default  # named in a series only when not this
DEFAULT_CFL = MPMSettings.model_fields["cfl"].default  # likewise
LINE_STYLES = ("-", "--", ":", "-.", (0, (5, 1)), (0, (1, 3)))  # one per cell size in the profiles
FITTED = ("width_90_10_mm", "width_75_25_mm", "gdot_p99")  # fitted as c h^b per series


class OutsideWindow(Exception):
    """A run without particle snapshots in the analysis window."""


def snapshot_steps(run_dir: Path) -> list[tuple[int, Path]]:
    """(step, path) of every VTK snapshot of a run, in step order."""
    paths = sorted((run_dir / "snapshots").glob("particles_*.vtu"))
    return [(int(p.stem.split("_")[-1]), p) for p in paths]


def width_between(depth: np.ndarray, y: np.ndarray, hi: float, lo: float) -> float:
    """Depth span over which y (peaking at depth[argmax]) falls from hi to lo times its peak,
    by linear interpolation below the peak; NaN when the profile does not fall that far."""
    k = int(np.nanargmax(y))
    peak = y[k]
    d, v = depth[k:], y[k:]

    def crossing(level: float) -> float:
        below = np.nonzero(v < level * peak)[0]
        if len(below) == 0:
            return float("nan")
        j = below[0]
        if j == 0:
            return float(d[0])
        return float(d[j - 1] + (d[j] - d[j - 1]) * (v[j - 1] - level * peak) / (v[j - 1] - v[j]))

    return crossing(lo) - crossing(hi)


def layer_profile(run_dir: Path, window: tuple[float, float], sector_deg: float) -> dict:
    """Binned rim-wise speed and gdot_p below the wheel over the window's snapshots of one run."""
    import meshio

    meta = json.loads((run_dir / META).read_text())
    resolved = json.loads((run_dir / "config.json").read_text())
    dt, material = resolved["derived"]["dt"], resolved["config"]["material"]  # the run's own material law
    ts = read_timeseries(run_dir / "timeseries.csv")  # units in the header or not
    h = float(meta["cell_mm"]) * 1e-3
    edges = np.arange(DEPTH_RANGE[0], DEPTH_RANGE[1] + 0.25 * h, 0.5 * h)
    sum_u, sum_g, count = (np.zeros(len(edges) - 1) for _ in range(3))
    used, flowing, fast, numbers, last = [], [], [], [], None
    for step, path in snapshot_steps(run_dir):
        t = step * dt
        if not window[0] - 0.5 * dt <= t <= window[1] + 0.5 * dt or step > ts["step"][-1]:
            continue
        xc = float(np.interp(step, ts["step"], ts["x"]))
        zc = float(np.interp(step, ts["step"], ts["z"]))
        mesh = meshio.read(path)
        x, z = mesh.points[:, 0], mesh.points[:, 2]
        phi = np.arctan2(x - xc, zc - z)  # angle from the downward vertical through the centre
        sel = np.abs(phi) < np.radians(sector_deg)
        depth = np.hypot(x[sel] - xc, z[sel] - zc) - RIM_RADIUS  # radially below the rim
        vel = mesh.point_data["velocity"][sel]
        u = -(vel[:, 0] * np.cos(phi[sel]) + vel[:, 2] * np.sin(phi[sel]))  # along the rim's motion (clockwise)
        k = np.digitize(depth, edges) - 1
        ok = (k >= 0) & (k < len(edges) - 1)
        np.add.at(sum_u, k[ok], u[ok])
        np.add.at(sum_g, k[ok], mesh.point_data["gdot_p"][sel][ok])
        np.add.at(count, k[ok], 1)
        near = (np.abs(x - xc - FIELD_BOX[0]) < FIELD_BOX[1]) & (z > zc + FIELD_BOX[2])
        gd = mesh.point_data["gdot_p"][near]
        flowing.append([np.count_nonzero(gd > g) * (0.5 * h) ** 2 for g in FLOW_RATES])
        is_shearing = gd > FLOW_RATES[0]
        shearing = gd[is_shearing]
        fast.append(np.percentile(shearing, PERCENTILES) if len(shearing) else np.full(len(PERCENTILES), np.nan))
        pressure = mesh.point_data["pressure"][near][is_shearing]
        inertial = shearing[pressure > 0] * GRAIN_DIAMETER * np.sqrt(GRAIN_DENSITY / pressure[pressure > 0])
        numbers.append(np.percentile(inertial, PERCENTILES) if len(inertial) else np.full(len(PERCENTILES), np.nan))
        last = {"x": x[near] - xc, "z": z[near] - zc, "gdot": gd}
        used.append(t)
    if not used:
        raise OutsideWindow(
            f"{run_dir}: no snapshot in the window {window} s (still running, or run without --snapshot-every)"
        )
    with np.errstate(invalid="ignore", divide="ignore"):
        drag, gdot = sum_u / count, sum_g / count
    centre = 0.5 * (edges[1:] + edges[:-1])
    keep = count > 0
    centre, drag, gdot, count = centre[keep], drag[keep], gdot[keep], count[keep]
    rim_speed = abs(meta["omega_rpm"]) * RPM * RIM_RADIUS - meta["vx"]  # m/s backwards, the rim's lowest point
    w90_10 = width_between(centre, drag, 0.9, 0.1)
    w75_25 = width_between(centre, drag, 0.75, 0.25)
    smooth = bool(meta.get("smooth", False))
    xi = cooperativity_length(run_dir, material, ts, h)
    return {
        "series": series_name(
            smooth,
            meta["domain"],
            material.get("viscosity", 0.0),
            material.get("mu_i"),
            material.get("fluidity"),
            meta.get("cfl", DEFAULT_CFL),
            meta.get("lug_width", LUG_WIDTH),
        ),
        "cell_mm": float(meta["cell_mm"]),
        "smooth": smooth,
        "box_x": float(meta["domain"][0]),
        "box_z": float(meta["domain"][1]),
        "viscosity": float(material.get("viscosity", 0.0)),
        "z": meta["z"],
        "vx_wheel": meta["vx"],
        "omega_rpm": meta["omega_rpm"],
        "snapshots": len(used),
        "t_first": min(used),
        "t_last": max(used),
        "rim_speed": rim_speed,
        "grain_speed_max": float(np.max(drag)),
        "grain_over_rim": float(np.max(drag)) / rim_speed,
        "width_90_10_mm": 1e3 * w90_10,
        "width_90_10_cells": w90_10 / h,
        "width_75_25_mm": 1e3 * w75_25,
        "width_75_25_cells": w75_25 / h,
        "gdot_peak": float(np.max(gdot)),
        **interval_means(ts["time"], {c: ts[c] for c in ("fx", "fz", "moment")}, *window),
        **{f"area_gdot_above_{g:g}_cm2": 1e4 * a for g, a in zip(FLOW_RATES, np.mean(flowing, axis=0))},
        **{f"gdot_p{q:g}": float(v) for q, v in zip(PERCENTILES, np.mean(fast, axis=0))},
        **{f"inertial_p{q:g}": float(v) for q, v in zip(PERCENTILES, np.mean(numbers, axis=0))},
        "xi_fast_median_mm": 1e3 * xi,
        "xi_fast_median_cells": xi / h,
        "profile": {"depth": centre, "drag": drag, "gdot": gdot, "count": count},
        "field": last,
    }


def cooperativity_length(run_dir: Path, material: dict, ts: dict[str, np.ndarray], h: float) -> float:
    """Median cooperativity length A d / sqrt(|mu - mu_s|), m, over the points around the wheel
    shearing faster than FLOW_RATES[1] at the run's last checkpoint; NaN without the nonlocal fluidity,
    or without a checkpoint (runs shorter than their checkpoint interval, before the solver kept its end state)."""
    fluidity, path = material.get("fluidity"), run_dir / CHECKPOINT
    if not fluidity or not path.exists():
        return float("nan")
    with np.load(path) as z:
        step = int(json.loads(bytes(z["meta"]).decode())["step_count"])
        x, sig, syy, gd = z["x"], z["sigma"], z["s_yy"], z["gdot_p"]
    xc, zc = (float(np.interp(step, ts["step"], ts[c])) for c in ("x", "z"))
    pressure = mean_pressure(sig, syy)
    dev = np.stack([sig[:, 0, 0] + pressure, sig[:, 1, 1] + pressure, syy + pressure])
    tau = np.sqrt(0.5 * (np.sum(dev**2, axis=0) + 2.0 * sig[:, 0, 1] ** 2))
    near = (np.abs(x[:, 0] - xc - FIELD_BOX[0]) < FIELD_BOX[1]) & (x[:, 1] > zc + FIELD_BOX[2])
    fast = near & (gd > FLOW_RATES[1]) & (pressure > 0.0)
    dmu = np.abs(tau[fast] / pressure[fast] - material["mu_s"])
    return (
        float(np.median(fluidity["amplitude"] * fluidity["grain_diameter"] / np.sqrt(dmu)))
        if fast.any()
        else float("nan")
    )


def series_name(
    smooth: bool,
    domain,
    viscosity: float = 0.0,
    mu_i: dict | None = None,
    fluidity: dict | None = None,
    cfl: float = DEFAULT_CFL,
    lug_width: float | None = None,
) -> str:
    """'grousered' (with the grouser thickness when not Table S1's) or 'smooth rim', with the box
    when it is not the default 0.7 m x 0.4 m, the viscous overstress, the mu(I) law or the nonlocal
    fluidity when there is one, and the time step's CFL number when it is not the default."""
    name = "smooth rim" if smooth else "grousered"
    name += f" ({1e3 * lug_width:g} mm grousers)" if not smooth and lug_width not in (None, LUG_WIDTH) else ""
    name += "" if tuple(domain) == (0.7, 0.4) else f", {domain[0]:g} m x {domain[1]:g} m box"
    name += f", eta {viscosity:g} Pa s" if viscosity > 0.0 else ""
    name += f", mu(I) d {1e3 * mu_i['grain_diameter']:g} mm" if mu_i else ""
    if fluidity:
        name += f", nonlocal d {1e3 * fluidity['grain_diameter']:g} mm"
        name += f", {fluidity['sweep_pairs']} sweep pairs" if fluidity["sweep_pairs"] != DEFAULT_SWEEP_PAIRS else ""
    name += f", CFL {cfl:g}" if cfl != DEFAULT_CFL else ""
    return name


def power_law(h: np.ndarray, w: np.ndarray) -> tuple[float, float]:
    """(b, c) of w = c h^b, least squares in log-log."""
    b, log_c = np.polyfit(np.log(h), np.log(w), 1)
    return float(b), float(np.exp(log_c))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("folders", nargs="+", help="folders of fixed-state run folders (or run folders)")
    ap.add_argument("--window", type=float, nargs=2, default=(0.3, 0.4), metavar=("T0", "T1"), help="s")
    ap.add_argument("--sector-deg", type=float, default=15.0, help="degrees either side of the downward vertical")
    ap.add_argument("--out", default="research/outputs/shear_layer")
    args = ap.parse_args()
    if not args.window[0] < args.window[1]:
        raise SystemExit(f"--window {args.window}: T0 must be below T1")

    run_dirs = []
    for folder in map(Path, args.folders):
        run_dirs += [
            p.parent for p in ([folder / META] if (folder / META).exists() else sorted(folder.glob(f"*/{META}")))
        ]
    run_dirs = [d for d in run_dirs if snapshot_steps(d) and (d / "timeseries.csv").exists()]
    if not run_dirs:
        raise SystemExit("no fixed-state run folder with snapshots found")
    rows = []
    for d in run_dirs:
        try:
            rows.append(layer_profile(d, tuple(args.window), args.sector_deg))
        except OutsideWindow as err:  # one run not there yet: the others still make the table
            print(f"skipped {err}", file=sys.stderr)
    if not rows:
        raise SystemExit(f"no run has snapshots in the window {tuple(args.window)} s")
    rows.sort(key=lambda r: (r["series"], r["z"], r["vx_wheel"], -r["cell_mm"]))

    out = Path(args.out)
    out.parent.mkdir(parents=True, exist_ok=True)
    keys = [k for k in rows[0] if k not in ("profile", "field")]
    with out.with_suffix(".csv").open("w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=keys, extrasaction="ignore", lineterminator="\n")
        w.writeheader()
        w.writerows([{k: (f"{v:.6g}" if isinstance(v, float) else v) for k, v in r.items() if k in keys} for r in rows])
    with out.with_name(out.name + "_profiles.csv").open("w", newline="") as f:
        w = csv.writer(f, lineterminator="\n")
        w.writerow(["series", "cell_mm", "depth_below_rim_mm", "rimwise_speed", "gdot_p", "points"])
        for r in rows:
            p = r["profile"]
            for d, u, g, n in zip(p["depth"], p["drag"], p["gdot"], p["count"]):
                w.writerow([r["series"], r["cell_mm"], f"{1e3 * d:.3f}", f"{u:.6g}", f"{g:.6g}", int(n)])

    print(
        "| wheel | cells (mm) | snapshots | area > 1/s, > 10/s (cm^2) | grains' max speed (m/s) | / rim speed | 90-10 width (mm) | (cells) | 75-25 width (mm) | "
        "(cells) | gdot peak of the profile (1/s) | gdot 99th percentile (1/s) | I 50th / 99th percentile | fx (N) | fz (N) |"
    )
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        print(
            f"| {r['series']} | {r['cell_mm']:g} | {r['snapshots']} | {r['area_gdot_above_1_cm2']:.0f}, {r['area_gdot_above_10_cm2']:.0f} | {r['grain_speed_max']:.4f} | {r['grain_over_rim']:.2f} | "
            f"{r['width_90_10_mm']:.2f} | {r['width_90_10_cells']:.2f} | {r['width_75_25_mm']:.2f} | {r['width_75_25_cells']:.2f} | "
            f"{r['gdot_peak']:.1f} | {r['gdot_p99']:.1f} | {r['inertial_p50']:.2g} / {r['inertial_p99']:.2g} | {r['fx']:+.2f} | {r['fz']:.2f} |"
        )
    fits = {}
    for series in dict.fromkeys(r["series"] for r in rows):
        sub = [r for r in rows if r["series"] == series]
        if len(sub) >= 2:
            h = np.array([r["cell_mm"] for r in sub])
            for key in FITTED:
                w_ = np.array([r[key] for r in sub])
                if np.all(np.isfinite(w_)) and np.all(w_ > 0):
                    fits[(series, key)] = power_law(h, w_)
                    b, c = fits[(series, key)]
                    print(f"{series}: {key} = {c:.3g} x (h / mm)^{b:.2f} over h = {h.min():g}-{h.max():g} mm")
    plot(rows, fits, out.with_suffix(".png"))
    plot_fields(rows, out.with_name(out.name + "_fields.png"))
    print(
        f"wrote {out.with_suffix('.csv')}, {out.name}_profiles.csv, {out.with_suffix('.png')} and {out.name}_fields.png"
    )


def plot(rows: list[dict], fits: dict, path: Path) -> None:
    """Profiles (top) and, against the cell size, the widths, the 99th percentile and the lift
    (bottom); one colour per series, one line style per cell size, one legend for all panels."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.lines import Line2D

    series = list(dict.fromkeys(r["series"] for r in rows))
    cells = sorted({r["cell_mm"] for r in rows}, reverse=True)
    colour = {name: plt.get_cmap("tab20")(i % 20) for i, name in enumerate(series)}
    fig = plt.figure(figsize=(16, 10))
    grid = fig.add_gridspec(2, 3)
    prof = [fig.add_subplot(grid[0, k]) for k in range(2)]
    conv = [fig.add_subplot(grid[1, k]) for k in range(3)]
    key_ax = fig.add_subplot(grid[0, 2])
    key_ax.set_axis_off()
    for r in rows:
        p, style = r["profile"], LINE_STYLES[cells.index(r["cell_mm"]) % len(LINE_STYLES)]
        prof[0].plot(p["drag"], 1e3 * p["depth"], linestyle=style, color=colour[r["series"]], lw=1.0)
        prof[1].plot(p["gdot"], 1e3 * p["depth"], linestyle=style, color=colour[r["series"]], lw=1.0)
    for ax in prof:
        ax.set_ylim(40, -2)
        ax.set_ylabel("depth below the rim (mm)")
        ax.axhline(0, color="k", lw=0.6)
    prof[0].set_xlabel("grains' speed along the rim's motion (m/s)")
    prof[1].set_xlabel("equivalent plastic strain rate gdot_p (1/s)")
    for name in series:
        sub = sorted((r for r in rows if r["series"] == name), key=lambda r: r["cell_mm"])
        h = np.array([r["cell_mm"] for r in sub])
        for ax, key, fill in (
            (conv[0], "width_90_10_mm", None),
            (conv[0], "width_75_25_mm", "none"),
            (conv[1], "gdot_p99", None),
            (conv[2], "fz", None),
        ):
            ax.plot(
                h, [r[key] for r in sub], "o-" if fill is None else "s--", color=colour[name], mfc=fill, lw=1.0, ms=4
            )
    for ax in conv:
        ax.set_xscale("log")
        ax.set_xlabel("cell size h (mm)")
        ax.set_xticks(cells, [f"{c:g}" for c in cells])
        ax.minorticks_off()
    conv[0].set_yscale("log")
    conv[0].set_ylabel("width of the sheared layer (mm): 90-10 (o), 75-25 (s)")
    conv[0].set_title("a width set by the grid goes as h^1; a converged one as h^0", fontsize=9)
    conv[1].set_yscale("log")
    conv[1].set_ylabel("gdot_p near the wheel (1/s)")
    conv[1].set_title("99th percentile over the points shearing > 1/s", fontsize=9)
    conv[2].set_ylabel("lift fz on the wheel (N)")
    conv[2].set_title("mean force over the window", fontsize=9)
    handles = [
        Line2D(
            [],
            [],
            color=colour[name],
            marker="o",
            lw=1.0,
            label=name
            + "".join(
                f"; {k[6:11].replace('_', '-') if k != 'gdot_p99' else '99th pct'} ~ h^{fits[(name, k)][0]:.2f}"
                for k in FITTED
                if (name, k) in fits and k != "width_75_25_mm"
            ),
        )
        for name in series
    ]
    handles += [
        Line2D([], [], color="k", linestyle=LINE_STYLES[i % len(LINE_STYLES)], label=f"profiles: {c:g} mm cells")
        for i, c in enumerate(cells)
    ]
    key_ax.legend(handles=handles, loc="center", fontsize=7, frameon=False)
    r0 = rows[0]
    fig.suptitle(
        f"The sheared layer below the wheel held at a fixed state ({r0['omega_rpm']:g} RPM, centre "
        f"{1e3 * r0['z']:.1f} mm above the floor, v {r0['vx_wheel']:.3f} m/s)",
        fontsize=10,
    )
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def plot_fields(rows: list[dict], path: Path) -> None:
    """The strain rate around the wheel at the last snapshot of each run's window, one panel per run."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.colors import LogNorm

    series = list(dict.fromkeys(r["series"] for r in rows))
    cells = sorted({r["cell_mm"] for r in rows}, reverse=True)
    fig, axes = plt.subplots(
        len(series),
        len(cells),
        figsize=(3.6 * len(cells) + 1.0, 1.7 * len(series) + 0.3),
        squeeze=False,
        layout="constrained",
    )
    norm = LogNorm(vmin=0.1, vmax=100.0)
    for ax in axes.flat:
        ax.set_axis_off()
    for r in rows:
        ax = axes[series.index(r["series"]), cells.index(r["cell_mm"])]
        ax.set_axis_on()
        f = r["field"]
        order = np.argsort(f["gdot"])  # fastest on top
        sc = ax.scatter(
            1e3 * f["x"][order],
            1e3 * f["z"][order],
            c=np.clip(f["gdot"][order], 0.1, None),
            s=0.6 * (r["cell_mm"] / 1.25) ** 2,  # about the points' own area
            cmap="viridis",
            norm=norm,
            linewidths=0,
            rasterized=True,
        )
        phi = np.linspace(0.0, 2.0 * np.pi, 200)
        ax.fill(1e3 * RIM_RADIUS * np.cos(phi), 1e3 * RIM_RADIUS * np.sin(phi), color="tab:red", alpha=0.8)
        ax.set_xlim(-150, 250)
        ax.set_ylim(-170, -40)
        ax.set_aspect("equal")
        ax.set_title(f"{r['series']}, {r['cell_mm']:g} mm cells, t = {r['t_last']:.3f} s", fontsize=8)
        ax.set_xlabel("x - x_wheel (mm)", fontsize=8)
        ax.set_ylabel("z - z_wheel (mm)", fontsize=8)
    fig.colorbar(sc, ax=axes.ravel().tolist(), label="gdot_p (1/s)")
    fig.savefig(path, dpi=130)
    plt.close(fig)


if __name__ == "__main__":
    main()
