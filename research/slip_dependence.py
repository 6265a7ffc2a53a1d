"""What sets the MPM wheel's rear drop and sinkage: omega (the paper's law) or the slip?

The paper's structural correction sets the rear free-surface drop dh = r psi(r omega^2 / g) with
psi the identity: a function of omega alone. Our MPM wheels also ran at one omega with other
loads, grouser counts and forward pushes (`research/wheel_variants.py compare`, whose CSVs carry
each run's dh), so dh can be set against both x = r omega^2 / g and the rim's slip speed
v_s = r omega - v, and the sinkage against the slip s = v_s / (r omega).

    python research/slip_dependence.py \
        --sweep docs/figures/mpm_band0_settled/grousered_wheel_mpm_sweep.csv \
        --sweep research/outputs/figures/mpm_small_1p25mm/small_grousered_wheel_mpm_sweep.csv \
        --variants research/outputs/wheel_load.csv --variants research/outputs/wheel_lugs.csv \
        --variants research/outputs/wheel_push.csv --out research/outputs/slip_dependence

The time constant tau of the slip law dh = tau v_s (least squares through the origin) is fitted
on the first --sweep only (the large wheel's omega sweep); every other run is a check of it.
Writes OUT.csv (one row per run), OUT.json (tau and the quadratic sinkage / r = c0 + c1 s + c2 s^2
fitted on every run) and OUT.png (dh / r against x with the identity; dh against v_s
with the slip law; sinkage against slip), and prints both laws' misses. A run whose drop
measurement failed (dh below -5 mm: the loaded rear contact far above the surface, grains carried
up the wheel's rear, as for a wheel that digs in) is left out of the drop panels and of the fit;
a drop within a few mm of zero (a wheel that does not slip) is kept, and a run without a drop (a
--history row of wheel_variants.py) shows in the sinkage panel only. The drops are the means of
each run's measurements over its window (the sweeps' statistic); the variants' CSVs also hold
the medians.
"""

from __future__ import annotations

import argparse
import csv
import json
import math
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from intrusim.analysis.sweep import SweepResult  # noqa: E402
from intrusim.params import GRAVITY, RPM  # noqa: E402
from intrusim.scenarios import LOCOMOTORS  # noqa: E402

FIELDS = ("source", "label", "fit", "omega_rpm", "radius", "velocity", "sinkage", "slip", "slip_speed", "x",
          "dh", "dh_median", "drop_ok", "dh_identity", "dh_slip_law")  # fmt: skip
FAILED_BELOW = -5e-3  # m: a rear drop this far above the surface is a failed measurement
RADIUS = {f().name: f().radius for f in LOCOMOTORS.values()}  # scenario name -> outer radius, m


def _float(text: str | None) -> float:
    return float(text) if text not in (None, "") else math.nan


def _rows(path: Path, kind: str) -> list[dict]:
    """The MPM runs of a sweep CSV (`intrusim mpm collect`) or of a wheel_variants.py compare CSV."""
    out = []
    if kind == "sweep":
        name = path.name.removesuffix("_mpm_sweep.csv")
        if name not in RADIUS:
            raise SystemExit(f"{path}: no shipped scenario named {name!r} (known: {sorted(RADIUS)})")
        for r in SweepResult.from_csv(path).records:  # empty cells read as NaN
            if r["ok"]:
                out.append({"source": f"{name}: omega sweep ({path.parent.name})", "label": f"{r['omega_rpm']:g} RPM",
                            "radius": RADIUS[name], "omega_rpm": r["omega_rpm"], "velocity": r["velocity"],
                            "sinkage": r["sinkage"], "dh": r["surface_drop"], "dh_median": math.nan})  # fmt: skip
    else:
        with path.open(newline="") as f:
            table = list(csv.DictReader(f))
        for r in table:
            if r["model"] == "MPM":  # a run whose folder is gone (--history) has no drop: NaN
                push = f", {float(r['push']):g} N" if r.get("push") else ""
                out.append({"source": f"grousered_wheel: {path.stem}, {float(r['omega_rpm']):g} RPM",
                            "label": f"{r['lug_count']} grousers, {float(r['mass_z']):g} kg{push}",
                            "radius": RADIUS["grousered_wheel"], "omega_rpm": float(r["omega_rpm"]),
                            "velocity": float(r["velocity"]), "sinkage": float(r["sinkage"]),
                            "dh": _float(r.get("surface_drop")), "dh_median": _float(r.get("surface_drop_median"))})  # fmt: skip
    for r in out:
        w = r["omega_rpm"] * RPM
        r["slip_speed"] = r["radius"] * w - r["velocity"]
        r["slip"] = r["slip_speed"] / (r["radius"] * w)
        r["x"] = r["radius"] * w * w / GRAVITY
        r["dh_identity"] = r["radius"] * r["x"]
        r["drop_ok"] = bool(r["dh"] > FAILED_BELOW)
    return out


def analyse(sweeps: list[Path], variants: list[Path]) -> tuple[list[dict], float]:
    """Every run (``drop_ok`` False where the drop measurement failed) with both laws' dh, and
    tau (s) of dh = tau v_s fitted on the first sweep's runs by least squares through the origin."""
    sets = [(p, "sweep") for p in sweeps] + [(p, "variants") for p in variants]
    rows = [dict(r, fit=k == 0) for k, (path, kind) in enumerate(sets) for r in _rows(path, kind)]
    rows = list(
        {(r["source"].split(":")[0], r["label"], r["sinkage"]): r for r in rows}.values()
    )  # a run in two CSVs once
    fit = [r for r in rows if r["fit"] and r["drop_ok"]]
    vs, dh = np.array([r["slip_speed"] for r in fit]), np.array([r["dh"] for r in fit])
    tau = float(vs @ dh / (vs @ vs))
    for r in rows:
        r["dh_slip_law"] = tau * r["slip_speed"]
    return rows, tau


def slip_sinkage(rows: list[dict]) -> np.ndarray:
    """Coefficients (c2, c1, c0) of sinkage / r = c0 + c1 s + c2 s^2 fitted on every run."""
    return np.polyfit([r["slip"] for r in rows], [r["sinkage"] / r["radius"] for r in rows], 2)


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
    rows, tau = analyse([Path(p) for p in args.sweep], [Path(p) for p in args.variants])
    print(
        f"tau = {tau * 1e3:.1f} ms, fitted on the {sum(r['fit'] and r['drop_ok'] for r in rows)} runs of {args.sweep[0]}"
    )
    print(f"{'run':<62s} {'slip':>5s} {'sink mm':>7s} {'v_s m/s':>7s} {'dh mm':>6s} {'median':>6s}  identity  slip law")
    for r in rows:
        drop = (f"{r['dh'] * 1e3:6.1f} {r['dh_median'] * 1e3:6.1f}  {_miss(r['dh_identity'], r['dh'])}  "
                f"{_miss(r['dh_slip_law'], r['dh'])}") if r["drop_ok"] else (
                f"{r['dh'] * 1e3:6.1f}  (measurement failed)" if math.isfinite(r["dh"]) else "     -  (not measured)")  # fmt: skip
        print(
            f"{r['source'] + ', ' + r['label']:<62s} {r['slip']:5.2f} {r['sinkage'] * 1e3:7.1f} {r['slip_speed']:7.3f} {drop}"
        )
    quad = slip_sinkage(rows)
    miss = [np.polyval(quad, r["slip"]) * r["radius"] / r["sinkage"] - 1 for r in rows]
    print(f"sinkage / r = {quad[2]:.4f} + {quad[1]:.4f} s + {quad[0]:.4f} s^2 on {len(rows)} runs: "
          f"misses {min(miss):+.1%} to {max(miss):+.1%}")  # fmt: skip
    out = Path(args.out)
    out.parent.mkdir(parents=True, exist_ok=True)
    out.with_suffix(".json").write_text(
        json.dumps(
            {"slip_law_tau_s": tau, "slip_sinkage_c0_c1_c2": [quad[2], quad[1], quad[0]], "runs": len(rows)}, indent=1
        )
    )
    with out.with_suffix(".csv").open("w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(FIELDS), extrasaction="ignore")
        w.writeheader()
        w.writerows(rows)
    fig, (a, b, c) = plt.subplots(1, 3, figsize=(15, 4.2))
    for k, src in enumerate(dict.fromkeys(r["source"] for r in rows)):
        pts = [r for r in rows if r["source"] == src]
        ok = [r for r in pts if r["drop_ok"]]
        style = dict(marker="os^Dv<>"[k % 7], ls="none", color=f"C{k}", label=src)
        a.plot([r["x"] for r in ok], [r["dh"] / r["radius"] for r in ok], **style)
        b.plot([r["slip_speed"] for r in ok], [r["dh"] * 1e3 for r in ok], **style)
        c.plot([r["slip"] for r in pts], [r["sinkage"] / r["radius"] for r in pts], **style)
    xs = np.linspace(0.0, max(r["x"] for r in rows if r["drop_ok"]) * 1.05, 50)
    a.plot(xs, xs, "k--", label="paper: psi(x) = x")
    a.set(xlabel="x = r omega^2 / g", ylabel="dh / r", title="rear drop against omega")
    v = np.linspace(0.0, max(r["slip_speed"] for r in rows if r["drop_ok"]) * 1.05, 50)
    b.plot(v, tau * v * 1e3, "k-", label=f"dh = {tau * 1e3:.0f} ms x v_s (fit: first sweep)")
    b.set(xlabel="rim slip speed v_s = r omega - v (m/s)", ylabel="dh (mm)", title="rear drop against slip speed")
    ss = np.linspace(min(r["slip"] for r in rows), max(r["slip"] for r in rows), 50)
    c.plot(ss, np.polyval(quad, ss), "k-", label="quadratic fit, all runs")
    c.set(xlabel="slip s = 1 - v / (r omega)", ylabel="sinkage / r", title="sinkage against slip")
    for ax in (a, b, c):
        ax.legend(fontsize=6)
    fig.suptitle(
        "MPM wheels, band 0: what the rear drop and the sinkage follow (drop panels: runs whose drop measurement worked)"
    )
    fig.tight_layout()
    fig.savefig(out.with_suffix(".png"), dpi=120)
    print(out.with_suffix(".csv"), out.with_suffix(".png"))


if __name__ == "__main__":
    main()
