"""Measure the RFT map alpha(beta, gamma) of the MPM medium with plates, and fit Li's form to it.

    python examples/mpm_rft_map.py run --out runs/rftmap/base --workers 2
    python examples/mpm_rft_map.py fit runs/rftmap/base --out docs/figures/rft_map_mpm

``run`` moves one plate per (beta, gamma) (``intrusim.mpm.rft_map``) and appends each result to
OUT/alpha_map.csv as it finishes (each column with its unit: beta_rad, alpha_z_N_m3 ...; a map
written before, without, is read and extended as it is); run it again to do only the missing cases. ``fit`` fits the
Li (2013) Fourier form to the map (``intrusim.analysis.rft_fit``), writes NAME.json (the
coefficients, in N/cm^3, for ``intrusim.laws.rft``), NAME.csv (measured, fitted and generic
alpha per case) and NAME.png.
"""

from __future__ import annotations

import csv
import json
import math
import time
from concurrent.futures import ProcessPoolExecutor, as_completed
from dataclasses import asdict
from multiprocessing import get_context
from pathlib import Path
from typing import Optional

import numpy as np
import typer

from intrusim._checks import InputError
from intrusim.mpm.config import DEFAULT_CONTACT
from intrusim.mpm.rft_map import (
    PlateMapCase,
    alpha_map_column,
    alpha_map_key,
    alpha_map_row,
    case_record,
    map_cases,
    measure_alpha,
    read_alpha_map,
)

app = typer.Typer(add_completion=False, no_args_is_help=True)


@app.callback()
def main() -> None:
    """Plate maps alpha(beta, gamma) of the MPM medium (run) and Li's form fitted to them (fit)."""


KEYS = [
    "beta", "gamma", "depth", "plate_length", "plate_thickness", "speed", "travel", "cell_size",
    "contact", "contact_band_cells", "bed_height", "domain", "grid_offset", "fluidity_diameter", "alpha_x", "alpha_z", "alpha_x_std", "alpha_z_std", "depth_mean", "steps", "wall_s",
]  # fmt: skip
FIELDS = [alpha_map_column(k) for k in KEYS]  # the CSV's columns, each with its unit (beta_rad, alpha_x_N_m3 ...)


def _run_one(kw: dict) -> dict:
    from intrusim.mpm.solver import Solver  # in the worker: one Taichi runtime per process

    case = PlateMapCase(**kw)
    t0 = time.perf_counter()
    solver = Solver(case.config(cpu_threads=1))
    rows = solver.run()
    rec = {k: v for k, v in case_record(case).items() if k in KEYS}
    rec.update(measure_alpha(rows, case), steps=solver.step_count, wall_s=round(time.perf_counter() - t0, 1))
    return rec


def _key(beta: float, gamma: float) -> tuple[float, float]:
    """A case's identity in the CSV (angles as written and read back)."""
    return round(float(beta), 6), round(float(gamma), 6)


def _angle_columns(columns) -> tuple[str, str]:
    """The (beta, gamma) columns of a map's header: beta_rad, gamma_rad or, written before, beta, gamma."""
    by_key = {alpha_map_key(c): c for c in columns}
    if "beta" not in by_key or "gamma" not in by_key:
        raise typer.BadParameter(f"not an alpha_map.csv: no beta and gamma columns in {list(columns)}")
    return by_key["beta"], by_key["gamma"]


def _existing(path: Path) -> tuple[list[str] | None, set[tuple[float, float]]]:
    """The CSV's columns (None: no file yet) and the (beta, gamma) of the cases it holds, in one read."""
    if not path.exists():
        return None, set()
    with path.open() as f:
        reader = csv.DictReader(f)
        if not reader.fieldnames:  # an empty file: written as a new one
            return None, set()
        beta, gamma = _angle_columns(reader.fieldnames)  # beta_rad or, in a map written before, beta
        return list(reader.fieldnames), {_key(r[beta], r[gamma]) for r in reader}


def _degrees(text: str) -> list[float]:
    return [math.radians(float(s)) for s in text.split(",") if s.strip()]


@app.command()
def run(
    out: Path = typer.Option(..., help="folder; OUT/alpha_map.csv grows one row per finished case"),
    betas: str = typer.Option("-60,-30,0,30,60,90", help="plate orientations, degrees"),
    gammas: str = typer.Option("-90,-60,-30,0,30,60,90", help="motion directions, degrees"),
    depth_mm: float = typer.Option(40.0),
    plate_mm: float = typer.Option(25.0),
    thickness_mm: float = typer.Option(5.0, help="plate thickness (keep it 2 cells or more)"),
    cell_mm: float = typer.Option(2.5),
    contact: str = typer.Option(DEFAULT_CONTACT, help="the MPM contact: nodes (its default), band, surface"),
    band: float = typer.Option(0.0, help="contact band, cells (with --contact band)"),
    bed_mm: float = typer.Option(150.0),
    domain_mm: str = typer.Option("300x200", help="WIDTHxHEIGHT"),
    workers: int = typer.Option(2, min=1),
    fluidity_diameter: Optional[float] = typer.Option(
        None, help="nonlocal granular fluidity with grains of this diameter, m, in place of the paper's law"
    ),
) -> None:
    """Run the plate cases not yet in OUT/alpha_map.csv, ``workers`` processes of one thread each."""
    try:
        w_mm, h_mm = (float(v) for v in domain_mm.lower().split("x"))
    except ValueError:
        raise typer.BadParameter(f"--domain-mm must be WIDTHxHEIGHT, got {domain_mm!r}") from None
    common = dict(depth=depth_mm / 1e3, plate_length=plate_mm / 1e3, plate_thickness=thickness_mm / 1e3,
                  cell_size=cell_mm / 1e3, contact=contact, contact_band_cells=band,
                  bed_height=bed_mm / 1e3, domain=(w_mm / 1e3, h_mm / 1e3), fluidity_diameter=fluidity_diameter)  # fmt: skip
    try:
        cases = map_cases(_degrees(betas), _degrees(gammas), **common)  # validates every case first
    except InputError as err:
        typer.echo(f"error: {err}", err=True)
        raise typer.Exit(2) from None
    out.mkdir(parents=True, exist_ok=True)
    path = out / "alpha_map.csv"
    header, done = _existing(path)
    todo = [c for c in cases if _key(c.beta, c.gamma) not in done]
    typer.echo(f"{len(cases)} cases, {len(cases) - len(todo)} done, {len(todo)} to run")
    kws = [asdict(c) for c in todo]
    failed = 0
    new = header is None
    fields = FIELDS if new else header  # keep an existing file's columns
    with path.open("a", newline="") as f, ProcessPoolExecutor(workers, mp_context=get_context("spawn")) as pool:
        w = csv.DictWriter(f, fieldnames=fields, extrasaction="ignore")
        if new:
            w.writeheader()
        futures = {pool.submit(_run_one, kw): kw for kw in kws}
        for i, fut in enumerate(as_completed(futures), 1):
            kw = futures[fut]
            try:
                rec = fut.result()
            except Exception as err:  # noqa: BLE001 - report and go on; the case stays missing
                typer.echo(f"[{i}/{len(kws)}] beta {math.degrees(kw['beta']):.0f} gamma "
                           f"{math.degrees(kw['gamma']):.0f}: FAILED {type(err).__name__}: {err}")  # fmt: skip
                failed += 1
                continue
            w.writerow({**rec, **alpha_map_row(rec)})  # an older map's columns (beta ...) or the new ones
            f.flush()
            typer.echo(f"[{i}/{len(kws)}] beta {math.degrees(rec['beta']):4.0f} gamma {math.degrees(rec['gamma']):4.0f}: "
                       f"alpha_x {rec['alpha_x']:9.0f} alpha_z {rec['alpha_z']:9.0f} N/m^3 ({rec['wall_s']} s)")  # fmt: skip
    if failed:
        typer.echo(f"{failed} case(s) failed and are not in {path}; run again to retry them", err=True)
        raise typer.Exit(1)


def read_map(path: Path) -> dict[str, np.ndarray]:
    """The map's columns by their short keys (beta, gamma rad, alpha_x N/m^3 ...), the units in the
    header or not (a map written before)."""
    if not path.is_file():
        raise typer.BadParameter(f"{path} not found: run the map first")
    try:
        return read_alpha_map(path)
    except InputError as err:
        raise typer.BadParameter(str(err)) from None


@app.command()
def fit(
    runs: Path = typer.Argument(..., help="folder of a map run (holds alpha_map.csv)"),
    out: Path = typer.Option(..., help="NAME: writes NAME.json, NAME.csv, NAME.png"),
) -> None:
    """Fit Li's nine-term form to the measured map; compare with the generic fit scaled by one xi."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from intrusim.analysis.rft_fit import fit_li_form, scale_to, write_coefficients
    from intrusim.laws.rft import LI2013, alpha

    m = read_map(runs / "alpha_map.csv")
    b, g = m["beta"], m["gamma"]
    coef, info = fit_li_form(b, g, m["alpha_x"], m["alpha_z"])
    gx, gz = alpha(b, g)
    meas = np.concatenate([m["alpha_x"], m["alpha_z"]])
    gen = np.concatenate([gx, gz])
    xi_map = float(meas @ gen / (gen @ gen))  # one xi for the generic map, least squares over the points
    fx, fz = alpha(b, g, coef=coef)
    size = float(np.sqrt(np.mean(meas**2)))
    info.update(
        xi_map=xi_map, xi_table=scale_to(coef, LI2013), rms_alpha=size,
        rms_generic_scaled=float(np.sqrt(np.mean((meas - xi_map * gen) ** 2))),
        depth=float(m["depth"][0]), plate_length=float(m["plate_length"][0]), cell_size=float(m["cell_size"][0]),
        contact_band_cells=float(m["contact_band_cells"][0]), source=str(runs),
        wall_s=float(m["wall_s"].sum()) if "wall_s" in m else None,  # the reference set's map keeps steps only
    )  # fmt: skip
    out.parent.mkdir(parents=True, exist_ok=True)
    write_coefficients(out.with_suffix(".json"), coef, info)
    order = np.lexsort((g, b))
    cols = {
        "beta_deg": np.degrees(b), "gamma_deg": np.degrees(g), "alpha_x_mpm": m["alpha_x"], "alpha_z_mpm": m["alpha_z"],
        "alpha_x_fit": fx, "alpha_z_fit": fz, "alpha_x_generic_xi": xi_map * gx, "alpha_z_generic_xi": xi_map * gz,
        "alpha_x_std": m["alpha_x_std"], "alpha_z_std": m["alpha_z_std"],
    }  # fmt: skip
    with out.with_suffix(".csv").open("w", newline="") as f:
        w = csv.writer(f)
        w.writerow(list(cols))
        for i in order:
            w.writerow([f"{cols[k][i]:.6g}" for k in cols])
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.2), sharex=True)
    gg = np.linspace(-0.5 * np.pi, 0.5 * np.pi, 91)
    for j, beta in enumerate(np.unique(np.round(b, 9))):
        c = plt.cm.viridis(j / max(1, len(np.unique(np.round(b, 9))) - 1))
        sel = np.isclose(b, beta)
        fit_x, fit_z = alpha(np.full_like(gg, beta), gg, coef=coef)
        gen_x, gen_z = alpha(np.full_like(gg, beta), gg, xi=xi_map)
        for ax_, y, yf, yg in ((axes[0], m["alpha_z"][sel], fit_z, gen_z), (axes[1], m["alpha_x"][sel], fit_x, gen_x)):
            ax_.plot(np.degrees(g[sel]), y / 1e3, "o", color=c, label=f"beta {np.degrees(beta):.0f}")
            ax_.plot(np.degrees(gg), yf / 1e3, "-", color=c)
            ax_.plot(np.degrees(gg), yg / 1e3, ":", color=c)
    for ax_, name in zip(axes, ("alpha_z", "alpha_x")):
        ax_.set_xlabel("gamma (deg)")
        ax_.set_ylabel(f"{name} (kN/m^3)")
        ax_.axhline(0, color="0.7", lw=0.5)
    axes[0].legend(fontsize=7)
    fig.suptitle(f"MPM plate map (points), Li form fitted (solid), generic x {xi_map:.3f} (dotted); "
                 f"L {info['plate_length'] * 1e3:.0f} mm, depth {info['depth'] * 1e3:.0f} mm", fontsize=9)  # fmt: skip
    fig.tight_layout()
    fig.savefig(out.with_suffix(".png"), dpi=120)
    typer.echo(json.dumps({k: (round(v, 4) if isinstance(v, float) else v) for k, v in info.items()}, indent=1))


@app.command()
def table(
    runs: list[Path] = typer.Argument(..., help="map run folders (each holds alpha_map.csv)"),
    out: Path = typer.Option(..., help="CSV: every case of every folder, one row each, with the folder name"),
) -> None:
    """Gather maps of other plate lengths, depths or cells into one table (alpha in N/m^3)."""
    keys = ["plate_length", "depth", "depth_mean", "cell_size", "beta", "gamma", "alpha_x", "alpha_z",
            "alpha_x_std", "alpha_z_std", "wall_s"]  # fmt: skip
    rows = []
    for run in runs:
        m = read_map(run / "alpha_map.csv")
        for i in range(len(m["beta"])):
            rows.append({"run": run.name, **{k: float(m[k][i]) for k in keys}})
    rows.sort(key=lambda r: (r["beta"], r["gamma"], r["plate_length"], r["depth"], r["cell_size"]))
    out.parent.mkdir(parents=True, exist_ok=True)
    with out.open("w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=["run", *keys])
        w.writeheader()
        w.writerows(rows)
    for r in rows:
        typer.echo(f"{r['run']:>10} beta {math.degrees(r['beta']):4.0f} gamma {math.degrees(r['gamma']):4.0f} "
                   f"L {r['plate_length'] * 1e3:5.1f} mm depth {r['depth_mean'] * 1e3:5.1f} mm cell {r['cell_size'] * 1e3:4.2f} mm: "
                   f"alpha_x {r['alpha_x']:8.0f} alpha_z {r['alpha_z']:8.0f}")  # fmt: skip


if __name__ == "__main__":
    app()
