"""The MPM wheel's rear free-surface drop dh against the paper's law and against the rim's slip speed.

The paper's structural correction sets dh = r psi(r omega^2 / g) with psi the identity: a function
of omega alone. Our MPM wheels run at one omega with other loads and grouser counts too
(`examples/wheel_variants.py compare`, whose CSVs carry each run's dh), so the drop can be set
against both candidates: x = r omega^2 / g, and the slip speed of the rim v_s = r omega - v.

    python examples/rear_drop_slip.py \
        --sweep docs/figures/mpm_band0_settled/grousered_wheel_mpm_sweep.csv \
        --sweep docs/figures/mpm_small_1p25mm/small_grousered_wheel_mpm_sweep.csv \
        --variants docs/figures/wheel_load.csv --variants docs/figures/wheel_lugs.csv \
        --out docs/figures/rear_drop_slip

The time constant tau of dh = tau v_s (least squares through the origin) is fitted on the first
--sweep only (the large wheel's omega sweep); every other point is a check of the same tau.
Writes OUT.csv (one row per run: omega, v, v_s, x, the measured dh and both laws' dh) and OUT.png
(dh / r against x with the identity; dh against v_s with the fitted line), and prints the
relative misses of both laws. Runs whose drop measurement failed (dh below -5 mm: the loaded rear
contact far above the surface, grains carried up the wheel's rear, as for the heaviest wheel) are
listed and left out; a drop within a few mm of zero (a wheel that does not slip) is kept.
"""

from __future__ import annotations

import argparse
import csv
import math
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from intrusim.params import GRAVITY  # noqa: E402
from intrusim.scenarios import LOCOMOTORS  # noqa: E402

RPM = 2.0 * math.pi / 60.0
FIELDS = ("source", "label", "fit", "omega_rpm", "radius", "velocity", "slip_speed", "x", "dh", "dh_identity", "dh_slip_law")
FAILED_BELOW = -5e-3  # m: a rear drop this far above the surface is a failed measurement
RADIUS = {f().name: f().radius for f in LOCOMOTORS.values()}  # scenario name -> outer radius, m


def _rows(path: Path, kind: str) -> list[dict]:
    with path.open(newline="") as f:
        table = list(csv.DictReader(f))
    out = []
    if kind == "sweep":  # NAME_mpm_sweep.csv of `intrusim mpm collect`
        name = path.name.removesuffix("_mpm_sweep.csv")
        if name not in RADIUS:
            raise SystemExit(f"{path}: no shipped scenario named {name!r} (known: {sorted(RADIUS)})")
        for r in table:
            if r.get("ok", "True") == "True":
                out.append({"source": f"{name}: omega sweep ({path.parent.name})", "label": f"{float(r['omega_rpm']):g} RPM", "radius": RADIUS[name],
                            "omega_rpm": float(r["omega_rpm"]), "velocity": float(r["velocity"]), "dh": float(r["surface_drop"] or "nan")})  # fmt: skip
    else:  # a wheel_variants.py compare CSV: its MPM rows
        for r in table:
            if r["model"] == "MPM" and r.get("surface_drop"):
                out.append({"source": f"grousered_wheel: {path.stem}, {float(r['omega_rpm']):g} RPM",
                            "label": f"{r['lug_count']} grousers, {float(r['mass_z']):g} kg",
                            "radius": RADIUS["grousered_wheel"], "omega_rpm": float(r["omega_rpm"]),
                            "velocity": float(r["velocity"]), "dh": float(r["surface_drop"])})  # fmt: skip
    for r in out:
        w = r["omega_rpm"] * RPM
        r["slip_speed"] = r["radius"] * w - r["velocity"]
        r["x"] = r["radius"] * w * w / GRAVITY
        r["dh_identity"] = r["radius"] * r["x"]
    return out


def analyse(sweeps: list[Path], variants: list[Path]) -> tuple[list[dict], list[dict], float]:
    """Runs kept (each with both laws' dh), runs whose drop measurement failed, and tau (s)
    fitted on the first sweep's runs: dh = tau v_s by least squares through the origin."""
    sets = [(p, "sweep") for p in sweeps] + [(p, "variants") for p in variants]
    rows = [dict(r, fit=k == 0) for k, (path, kind) in enumerate(sets) for r in _rows(path, kind)]
    bad = [r for r in rows if not r["dh"] > FAILED_BELOW]
    rows = [r for r in rows if r["dh"] > FAILED_BELOW]
    fit = [r for r in rows if r["fit"]]  # the first sweep's runs
    vs, dh = np.array([r["slip_speed"] for r in fit]), np.array([r["dh"] for r in fit])
    tau = float(vs @ dh / (vs @ vs))
    for r in rows:
        r["dh_slip_law"] = tau * r["slip_speed"]
    return rows, bad, tau


def _miss(model: float, measured: float) -> str:
    """Relative miss of a law, or its absolute one (mm) where the measured drop is within 1 mm of 0."""
    if abs(measured) < 1e-3:
        return f"{(model - measured) * 1e3:+6.1f} mm"
    return f"{model / measured - 1:+8.0%}"


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--sweep", action="append", default=[], help="an MPM sweep CSV (the first: the fit set)")
    ap.add_argument("--variants", action="append", default=[], help="a wheel_variants.py compare CSV")
    ap.add_argument("--out", required=True, help="output stem (OUT.csv, OUT.png)")
    args = ap.parse_args()
    if not args.sweep:
        raise SystemExit("give at least one --sweep (the first one is the fit set)")
    rows, bad, tau = analyse([Path(p) for p in args.sweep], [Path(p) for p in args.variants])
    for r in bad:
        print(f"left out, drop measurement failed: {r['source']}: {r['label']} (dh {r['dh'] * 1e3:.1f} mm)")
    print(f"tau = {tau * 1e3:.1f} ms, fitted on the {sum(r['fit'] for r in rows)} runs of {args.sweep[0]}")
    print(f"{'run':<58s} {'v_s m/s':>8s} {'x':>6s} {'dh mm':>6s}  identity  slip law")
    for r in rows:
        print(f"{r['source'] + ', ' + r['label']:<58s} {r['slip_speed']:8.3f} {r['x']:6.3f} {r['dh'] * 1e3:6.1f}"
              f"  {_miss(r['dh_identity'], r['dh'])}  {_miss(r['dh_slip_law'], r['dh'])}")  # fmt: skip
    out = Path(args.out)
    out.parent.mkdir(parents=True, exist_ok=True)
    with out.with_suffix(".csv").open("w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(FIELDS), extrasaction="ignore")
        w.writeheader()
        w.writerows(rows)
    fig, (a, b) = plt.subplots(1, 2, figsize=(10, 4))
    for src in dict.fromkeys(r["source"] for r in rows):
        pts = [r for r in rows if r["source"] == src]
        a.plot([r["x"] for r in pts], [r["dh"] / r["radius"] for r in pts], "o", label=src)
        b.plot([r["slip_speed"] for r in pts], [r["dh"] * 1e3 for r in pts], "o", label=src)
    xs = np.linspace(0.0, max(r["x"] for r in rows) * 1.05, 50)
    a.plot(xs, xs, "k--", label="paper: psi(x) = x")
    a.set_xlabel("x = r omega^2 / g")
    a.set_ylabel("dh / r")
    v = np.linspace(0.0, max(r["slip_speed"] for r in rows) * 1.05, 50)
    b.plot(v, tau * v * 1e3, "k-", label=f"dh = {tau * 1e3:.0f} ms x v_s (fit: first sweep)")
    b.set_xlabel("rim slip speed v_s = r omega - v (m/s)")
    b.set_ylabel("dh (mm)")
    for ax in (a, b):
        ax.legend(fontsize=7)
    fig.suptitle("MPM rear free-surface drop: against r omega^2 / g and against the rim's slip speed")
    fig.tight_layout()
    fig.savefig(out.with_suffix(".png"), dpi=120)
    print(out.with_suffix(".csv"), out.with_suffix(".png"))


if __name__ == "__main__":
    main()
