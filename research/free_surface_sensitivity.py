"""How much the measured rear free-surface drop dh (paper Fig 5C) depends on how it is measured.

The paper's psi = identity (dh = r (r omega^2 / g)) is not reproduced by our MPM (psi ~ 0.4-0.5 x,
research/notes/results_log.md). The paper does not give the pressure threshold or the contact band of its
measurement, so this script re-measures dh on the particle snapshots of finished wheel runs
(``fields_*.npz`` in the run folders) with other choices, and fits psi(x) = c x for each:

* the paper's definition (the highest rear contact particle still under pressure, below the
  undisturbed surface: ``rear_contact_drop``) with pressure thresholds of 0.05-2 rho_c g h and
  contact bands of 0.5-2 cells (the runs use 0.5 rho_c g h and one cell);
* the paper's words read literally: the lowest rear contact particle whose pressure is below the
  threshold (which also picks the loosened wake under the wheel);
* the paper's definition, counting only contact particles below the undisturbed surface (the
  small wheel at 60-90 RPM carries grains up its rear, loaded by their own weight);
* the wake: how far the top of the grains in a strip one to three cells behind the wheel's
  bounding circle lies below the undisturbed surface (what "the drop of the rear free surface"
  would mean without reference to contact pressure).

    python research/free_surface_sensitivity.py runs/band --out research/outputs/free_surface_sensitivity

writes OUT.csv (one row per run and choice: mean dh over the snapshots) and OUT.png (dh / r
against r omega^2 / g for each choice, with the identity). Run folders are found under the given
folders by their locomotion.json (wheels only; both sizes collapse on one psi if the law holds).
"""

from __future__ import annotations

import argparse
import csv
import json
from pathlib import Path

import numpy as np

from intrusim.analysis.free_surface import rear_contact_drop, wake_drop
from intrusim.geometry import posed_polygon
from intrusim.scenarios import grousered_wheel_scenario, small_wheel_scenario

TOL_FACTORS = (0.05, 0.1, 0.25, 0.5, 1.0, 2.0)  # pressure threshold / (rho_c g h)
BAND_CELLS = (0.5, 1.0, 2.0)  # contact band, cells


def snapshot_drops(path: Path, bed_depth: float, rho_c: float, gravity: float, h: float) -> dict[str, float]:
    """dh (m) of one snapshot for every (threshold, band) choice and the wake."""
    d = np.load(path)
    x, z, th = (float(v) for v in d["body"][:3])
    poly = posed_polygon(d["outline"], x, z, th)
    out = {}
    for tol in TOL_FACTORS:
        for band in BAND_CELLS:
            out[f"contact_tol{tol:g}_band{band:g}"] = rear_contact_drop(
                d["x"],
                d["pressure"],
                poly,
                (x, z),
                1.0,
                bed_depth,
                band=band * h,
                pressure_tol=tol * rho_c * gravity * h,
            )
    pos, p = d["x"], d["pressure"]
    tol, band = 0.5 * rho_c * gravity * h, h
    out["lowest_free_tol0.5_band1"] = rear_contact_drop(
        pos, p, poly, (x, z), 1.0, bed_depth, band=band, pressure_tol=tol, rule="lowest_free"
    )
    out["loaded_below_surface_tol0.5_band1"] = rear_contact_drop(
        pos, p, poly, (x, z), 1.0, bed_depth, band=band, pressure_tol=tol, below_surface_only=True
    )
    reach = float(np.max(np.hypot(poly[:, 0] - x, poly[:, 1] - z)))
    out["wake"] = wake_drop(pos, x - reach, 1.0, bed_depth, (h, 3 * h))
    return out


def measure(roots: list[str]) -> list[dict]:
    """One row per (wheel run, choice): omega, radius, mean dh over the run's snapshots."""
    rows = []
    for meta_path in sorted(p for root in roots for p in Path(root).rglob("locomotion.json")):
        meta = json.loads(meta_path.read_text())
        if meta.get("body") != "wheel":
            continue
        snaps = sorted(meta_path.parent.glob("fields_*.npz"))
        if not snaps:
            continue
        s = meta["settings"]
        scenario = (
            small_wheel_scenario() if meta["scenario"]["name"].startswith("small") else grousered_wheel_scenario()
        )
        h = s["domain"][0] / s["cells"][0]
        per = [snapshot_drops(p, s["bed_depth"], s["rho_c"], scenario.gravity, h) for p in snaps]
        for choice in per[0]:
            dh = np.array([q[choice] for q in per])
            rows.append(
                {
                    "run": meta_path.parent.name,
                    "wheel": scenario.name,
                    "omega_rpm": meta["omega_rpm"],
                    "radius": scenario.radius,
                    "cell": h,
                    "band": s["contact_band_cells"],
                    "choice": choice,
                    "dh": float(np.nanmean(dh)) if np.isfinite(dh).any() else float("nan"),
                    "snapshots": len(dh),
                }
            )
            print(f"{rows[-1]['run']:45s} {choice:28s} dh = {rows[-1]['dh'] * 1e3:6.1f} mm", flush=True)
    if not rows:
        raise SystemExit(f"no wheel run folders with fields_*.npz snapshots under {roots}")
    return rows


def slopes(rows: list[dict], gravity: float = 9.8, wheel: str | None = None) -> dict[str, float]:
    """psi(x) = c x fitted (least squares of dh / r on x = r omega^2 / g) per choice, over all runs
    or those of one ``wheel``."""
    out = {}
    for choice in dict.fromkeys(r["choice"] for r in rows):
        sel = [r for r in rows if r["choice"] == choice and np.isfinite(r["dh"]) and wheel in (None, r["wheel"])]
        # each run has its own radius, so the fit is on (x, dh / r): c = sum(x y) / sum(x^2)
        x = np.array([r["radius"] * (r["omega_rpm"] * np.pi / 30) ** 2 / gravity for r in sel])
        y = np.array([r["dh"] / r["radius"] for r in sel])
        out[choice] = float(x @ y / (x @ x)) if len(sel) >= 2 else float("nan")
    return out


def plot(rows: list[dict], fits: dict[str, dict[str, float]], path: Path, gravity: float = 9.8) -> None:
    """dh / r against r omega^2 / g per choice, one line per wheel; ``fits[wheel][choice]`` = psi slope."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(8, 5.5))
    shown = [
        "contact_tol0.05_band1",
        "contact_tol0.5_band1",
        "contact_tol2_band1",
        "contact_tol0.5_band0.5",
        "contact_tol0.5_band2",
        "lowest_free_tol0.5_band1",
        "loaded_below_surface_tol0.5_band1",
        "wake",
    ]
    wheels = sorted({r["wheel"] for r in rows})
    for k, choice in enumerate(shown):
        colour = plt.cm.tab10(k)
        for j, wheel in enumerate(wheels):  # one line per wheel: each wheel's points in omega order
            sel = sorted(
                (r for r in rows if r["choice"] == choice and r["wheel"] == wheel), key=lambda r: r["omega_rpm"]
            )
            x = [r["radius"] * (r["omega_rpm"] * np.pi / 30) ** 2 / gravity for r in sel]
            y = [r["dh"] / r["radius"] for r in sel]
            slopes_txt = " / ".join(f"{fits[w][choice]:.2f}" for w in wheels)
            label = f"{choice.replace('contact_', 'paper rule, ')}: c = {slopes_txt}" if j == 0 else None
            ax.plot(x, y, ["o-", "s--"][j % 2], ms=4, color=colour, label=label)
    xs = np.linspace(0, max(r["radius"] * (r["omega_rpm"] * np.pi / 30) ** 2 / gravity for r in rows), 10)
    ax.plot(xs, xs, "k:", label="paper: psi = x")
    ax.set_xlabel("r omega^2 / g")
    ax.set_ylabel("dh / r")
    ax.set_title(
        "Rear surface drop, measured other ways (tol x rho_c g h, band in cells)\n"
        + "; ".join(f"{['o', 's'][j % 2]}: {w}" for j, w in enumerate(wheels))
        + "; c = psi slope per wheel, in that order",
        fontsize=9,
    )
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("roots", nargs="+", help="folders holding wheel run folders")
    ap.add_argument("--out", default="free_surface_sensitivity", help="output stem (.csv, .png)")
    args = ap.parse_args()
    rows = measure(args.roots)
    fits = slopes(rows)
    wheels = sorted({r["wheel"] for r in rows})
    per_wheel = {w: slopes(rows, wheel=w) for w in wheels}
    out = Path(args.out)
    out.parent.mkdir(parents=True, exist_ok=True)
    with open(out.with_suffix(".csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]) + ["psi_slope_all_runs", "psi_slope_this_wheel"])
        w.writeheader()
        for r in rows:
            w.writerow(
                {
                    **r,
                    "psi_slope_all_runs": fits[r["choice"]],
                    "psi_slope_this_wheel": per_wheel[r["wheel"]][r["choice"]],
                }
            )
    plot(rows, per_wheel, out.with_suffix(".png"))
    print("\npsi(x) = c x (paper: c = 1); the runs' own choice is contact_tol0.5_band1:")
    print(f"  {'choice':34s} {'all runs':>9s} " + " ".join(f"{w:>22s}" for w in wheels))
    for choice, c in sorted(fits.items(), key=lambda kv: kv[1]):
        print(f"  {choice:34s} {c:9.3f} " + " ".join(f"{per_wheel[w][choice]:22.3f}" for w in wheels))
    print(f"wrote {out.with_suffix('.csv')} and {out.with_suffix('.png')}")


if __name__ == "__main__":
    main()
