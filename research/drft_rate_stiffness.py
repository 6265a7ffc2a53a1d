"""Can a rate-dependent stiffness close xi-DRFT's miss on the slow nonlocal-law wheel?

xi-DRFT (DRFT with the RFT stiffness scaled by xi = 1.94, fitted on the 30 and 90 RPM MPM wheels)
misses the slow wheels: at 10 RPM v +18.9 %, sinkage -27 %. Held at one free state, the MPM
wheel's lift grows with omega where DRFT's does not (research/notes/results_log.md, the held pairs). Let that
growth be a stiffness that rises with the rate, xi(omega) = xi_ref (omega / omega_ref)^c: at a
fixed state a power law in the rates scales every RFT stress by (omega_B / omega_A)^c, so each
held pair measures

    c = [ln(Fz_B / Fz_A)_MPM - ln(Fz_B / Fz_A)_DRFT] / ln(omega_B / omega_A)

(DRFT's own change, from its inertial term, taken out). This script reads c from the held pairs,
refits xi_ref on the fit runs with c fixed, predicts the check runs, and finds at each check omega
the xi that would give the MPM's sinkage, with the speed and slip DRFT then has:

    python research/drft_rate_stiffness.py research/outputs/drft_at_switch_{10,15,20,60}rpm.csv \
        --calibration research/outputs/calibration_wheel_nonlocal_xi.json \
        --fit research/outputs/mpm_nonlocal/grousered_wheel_mpm_sweep.csv \
        --check research/outputs/mpm_nonlocal_blind_all/grousered_wheel_mpm_sweep.csv \
        --out research/outputs/drft_rate_stiffness                                   # ~1 min

Writes OUT_held.csv (c of each pair), OUT.csv (each model at each omega against the MPM),
OUT.json (the fits) and OUT.png (the sinkage and speed errors against omega; the xi each check
would need against the held pairs' power laws). A stiffness moves DRFT's sinkage, but hardly
its slip, so what it cannot close shows in the speed.

One more variant asks the same of the structural correction: xi-DRFT with each run's own measured
rear drop (the sweep CSVs' surface_drop, as dh = r psi with psi constant) in place of the paper's
dh = r (r omega^2 / g), xi refitted on the fit runs.
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
from scipy.optimize import brentq, minimize_scalar  # noqa: E402

from intrusim.analysis.calibration import drft_steady_states, load_reference, with_mpm_push, with_parameters  # noqa: E402
from intrusim.scenarios.base import ForceModelConfig  # noqa: E402
from intrusim.scenarios.locomotor import grousered_wheel_scenario  # noqa: E402

DRFT_LABEL = "xi-DRFT"  # the held-pair CSVs' DRFT rows start with this (drft_at_mpm_state.py --calibration)
XI_SEARCH = (0.05, 5.0)  # the bounds of xi in calibration.PARAMETERS
FIELDS = ("model", "c", "xi_ref", "omega_rpm", "xi", "velocity", "sinkage", "slip",
          "mpm_velocity", "mpm_sinkage", "mpm_slip", "dv", "ds", "role")  # fmt: skip


def held_pair(path: Path) -> dict:
    """The rate exponent c of one held pair (a drft_at_mpm_state.py CSV of two held runs)."""
    with path.open(newline="") as f:
        rows = list(csv.DictReader(f))
    mpm = sorted((float(r["omega_rpm"]), float(r["fz"])) for r in rows if r["model"] == "MPM")
    drft = sorted((float(r["omega_rpm"]), float(r["fz"])) for r in rows if r["model"].startswith(DRFT_LABEL))
    if len(mpm) != 2 or len(drft) != 2 or mpm[0][0] == mpm[1][0]:
        raise SystemExit(
            f"{path}: need two MPM rows at two omegas and two {DRFT_LABEL} rows, got {len(mpm)} and {len(drft)}"
        )
    (wa, fa), (wb, fb) = mpm
    (_, da), (_, db) = drft
    ln_w = math.log(wb / wa)
    c_mpm, c_drft = math.log(fb / fa) / ln_w, math.log(db / da) / ln_w
    return {"pair": path.stem, "omega_a": wa, "omega_b": wb, "mpm_fz_a": fa, "mpm_fz_b": fb,
            "drft_fz_a": da, "drft_fz_b": db, "c_mpm": c_mpm, "c_drft": c_drft, "c": c_mpm - c_drft}  # fmt: skip


class Drft:
    """xi-DRFT steady states of the Table S1 wheel with the MPM runs' forward push, cached by (omega, xi)."""

    def __init__(self, force_model: dict) -> None:
        wheel = with_mpm_push(grousered_wheel_scenario())
        self.base = wheel.model_copy(update=dict(force_model=ForceModelConfig.model_validate(force_model)))
        self.cache: dict[tuple[float, float, float | None], tuple[float, float, float]] = {}

    def state(self, omega_rpm: float, xi: float, drop: float | None = None) -> tuple[float, float, float]:
        """(v m/s, sinkage m, slip) at this omega with this xi; NaN if DRFT fails there. ``drop``: a
        rear drop dh (m) in place of the calibration's free-surface law (psi = dh / r, constant)."""
        key = (float(omega_rpm), float(xi), drop)
        if key not in self.cache:
            law = {} if drop is None else {"psi": 0.0, "psi_offset": float(drop) / self.base.radius}
            rec = drft_steady_states(with_parameters(self.base, {"xi": xi, **law}), [omega_rpm]).records[0]
            self.cache[key] = (rec["velocity"], rec["sinkage"], rec["slip"]) if rec["ok"] else (math.nan,) * 3
        return self.cache[key]


def xi_at(xi_ref: float, c: float, omega_rpm: float, omega_ref: float) -> float:
    """xi(omega) = xi_ref (omega / omega_ref)^c."""
    return xi_ref * (omega_rpm / omega_ref) ** c


def fit_xi_ref(model: Drft, c: float, fit: list[dict], omega_ref: float, own_drop: bool = False) -> float:
    """xi_ref minimising the summed squared relative errors of v and sinkage on the fit runs
    (``own_drop``: each run with its measured rear drop)."""

    def cost(log_xi: float) -> float:
        total = 0.0
        for r in fit:
            drop = r["surface_drop"] if own_drop else None
            v, s, _ = model.state(r["omega_rpm"], xi_at(math.exp(log_xi), c, r["omega_rpm"], omega_ref), drop)
            total += ((v - r["velocity"]) / r["velocity"]) ** 2 + ((s - r["sinkage"]) / r["sinkage"]) ** 2
        return total if math.isfinite(total) else 1e6

    res = minimize_scalar(cost, bounds=tuple(math.log(b) for b in XI_SEARCH), method="bounded", options={"xatol": 1e-4})
    return float(math.exp(res.x))


def xi_for_sinkage(model: Drft, omega_rpm: float, sinkage: float) -> float:
    """The xi at which DRFT sinks as deep as ``sinkage`` at this omega (NaN if no xi in the bounds does)."""

    def gap(log_xi: float) -> float:
        return model.state(omega_rpm, math.exp(log_xi))[1] - sinkage

    lo, hi = (math.log(b) for b in XI_SEARCH)
    if not gap(lo) * gap(hi) < 0.0:
        return math.nan
    return float(math.exp(brentq(gap, lo, hi, xtol=1e-4)))


def mpm_rows(path: Path, role: str) -> list[dict]:
    ref = load_reference(path)
    return [{"omega_rpm": r["omega_rpm"], "velocity": r["velocity"], "sinkage": r["sinkage"], "slip": r["slip"],
             "surface_drop": r["surface_drop"], "role": role} for r in ref.records]  # fmt: skip


def _row(model: str, c: float, xi_ref: float, xi: float, state: tuple[float, float, float], mpm: dict) -> dict:
    """One model's steady state at one MPM run's omega, with its errors against that run."""
    v, s, slip = state
    return {"model": model, "c": c, "xi_ref": xi_ref, "omega_rpm": mpm["omega_rpm"], "xi": xi, "velocity": v,
            "sinkage": s, "slip": slip, "mpm_velocity": mpm["velocity"], "mpm_sinkage": mpm["sinkage"],
            "mpm_slip": mpm["slip"], "dv": v / mpm["velocity"] - 1.0, "ds": s / mpm["sinkage"] - 1.0, "role": mpm["role"]}  # fmt: skip


def analyse(held: list[Path], calibration: Path, fit_csv: Path, check_csv: Path, omega_ref: float = 30.0) -> dict:
    """Everything the script writes, as plain data."""
    pairs = [held_pair(p) for p in held]
    cs = np.array([p["c"] for p in pairs])
    fm = json.loads(calibration.read_text())["calibration"]["force_model"]
    model = Drft(fm)
    fit, check = mpm_rows(fit_csv, "fit"), mpm_rows(check_csv, "check")
    variants = {"xi-DRFT (c = 0)": 0.0, "c min": float(cs.min()), "c mean": float(cs.mean()), "c max": float(cs.max())}
    rows, fits = [], {}
    for name, c in variants.items():
        xi_ref = fit_xi_ref(model, c, fit, omega_ref)
        fits[name] = {"c": c, "xi_ref": xi_ref}
        for r in fit + check:
            xi = xi_at(xi_ref, c, r["omega_rpm"], omega_ref)
            rows.append(_row(name, c, xi_ref, xi, model.state(r["omega_rpm"], xi), r))
    xi_drop = fit_xi_ref(model, 0.0, fit, omega_ref, own_drop=True)
    fits["the MPM's own drop"] = {"c": 0.0, "xi_ref": xi_drop}
    for r in fit + check:
        rows.append(
            _row(
                "the MPM's own drop", 0.0, xi_drop, xi_drop, model.state(r["omega_rpm"], xi_drop, r["surface_drop"]), r
            )
        )
    xi0 = fits["xi-DRFT (c = 0)"]["xi_ref"]
    for r in check:
        xi = xi_for_sinkage(model, r["omega_rpm"], r["sinkage"])
        state = model.state(r["omega_rpm"], xi) if math.isfinite(xi) else (math.nan,) * 3
        rows.append(_row("xi for the MPM sinkage", math.nan, xi0, xi, state, r))
    return {"pairs": pairs, "fits": fits, "rows": rows, "omega_ref": omega_ref}


def plot(result: dict, path: Path) -> None:
    rows, fits = result["rows"], result["fits"]
    fig, axes = plt.subplots(1, 3, figsize=(14, 4.2))
    for name in list(fits) + ["xi for the MPM sinkage"]:
        sel = sorted((r for r in rows if r["model"] == name), key=lambda r: r["omega_rpm"])
        w = [r["omega_rpm"] for r in sel]
        style = dict(marker="s", ls=":", color="k") if name.startswith("xi for") else dict(marker="o")
        if name == "the MPM's own drop":
            style = dict(marker="^", ls="--", color="0.5")
        label = name if name.startswith(("xi", "the")) else f"{name} ({fits[name]['c']:.3f})"
        axes[0].plot(w, [100 * r["ds"] for r in sel], label=label, **style)
        axes[1].plot(w, [100 * r["dv"] for r in sel], label=label, **style)
    for ax, what in zip(axes[:2], ("sinkage", "v")):
        ax.axhspan(-15, 15, color="0.9", zorder=0)
        ax.set_xscale("log")
        ax.set_xlabel("omega (RPM)")
        ax.set_ylabel(f"DRFT {what} - MPM (%)")
    axes[0].legend(fontsize=7, title="rate exponent c", title_fontsize=7)
    xi0 = fits["xi-DRFT (c = 0)"]["xi_ref"]
    need = sorted((r for r in rows if r["model"] == "xi for the MPM sinkage"), key=lambda r: r["omega_rpm"])
    axes[2].plot(
        [r["omega_rpm"] for r in need], [r["xi"] / xi0 for r in need], "ks:", label="xi giving the MPM sinkage / 1.94"
    )
    w = np.geomspace(8, 100, 50)
    for p in result["pairs"]:
        axes[2].plot(
            w,
            (w / result["omega_ref"]) ** p["c"],
            lw=1,
            label=f"{p['pair'].removeprefix('drft_at_switch_')} state, {p['omega_a']:g} -> {p['omega_b']:g} RPM: c {p['c']:.3f}",
        )
    axes[2].set_xscale("log")
    axes[2].set_xlabel("omega (RPM)")
    axes[2].set_ylabel("xi / xi fitted at 30-90 RPM")
    axes[2].legend(fontsize=7)
    fig.suptitle(
        "A stiffness that grows with the rate (xi ~ omega^c, c from the held pairs) against the nonlocal-law MPM wheel"
    )
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("held", nargs="+", type=Path, help="drft_at_mpm_state.py CSVs of held pairs (two omegas each)")
    ap.add_argument("--calibration", type=Path, required=True, help="the xi-DRFT calibration JSON (intrusim calibrate)")
    ap.add_argument("--fit", type=Path, required=True, help="MPM sweep CSV that xi_ref is fitted on")
    ap.add_argument("--check", type=Path, required=True, help="MPM sweep CSV of the runs to predict")
    ap.add_argument("--omega-ref", type=float, default=30.0, help="omega_ref of xi(omega), RPM (default 30)")
    ap.add_argument("--out", type=Path, required=True, help="output stem")
    args = ap.parse_args()
    for p in [*args.held, args.calibration, args.fit, args.check]:
        if not p.is_file():
            ap.error(f"no such file: {p}")
    if not args.omega_ref > 0:
        ap.error("--omega-ref must be > 0")
    result = analyse(args.held, args.calibration, args.fit, args.check, args.omega_ref)
    args.out.parent.mkdir(parents=True, exist_ok=True)
    with args.out.with_name(args.out.name + "_held.csv").open("w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(result["pairs"][0]))
        w.writeheader()
        w.writerows(result["pairs"])
    with args.out.with_suffix(".csv").open("w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=FIELDS)
        w.writeheader()
        w.writerows(result["rows"])
    args.out.with_suffix(".json").write_text(
        json.dumps({"omega_ref_rpm": args.omega_ref, "fits": result["fits"]}, indent=1)
    )
    plot(result, args.out.with_suffix(".png"))
    for p in result["pairs"]:
        print(f"{p['pair']}: {p['omega_a']:g} -> {p['omega_b']:g} RPM, MPM Fz {p['mpm_fz_a']:.2f} -> {p['mpm_fz_b']:.2f} N, "
              f"c = {p['c_mpm']:+.4f} (MPM) - {p['c_drft']:+.4f} (DRFT) = {p['c']:+.4f}")  # fmt: skip
    for name, f in result["fits"].items():
        print(f"{name}: c {f['c']:.4f}, xi_ref {f['xi_ref']:.4f}")
        for r in (r for r in result["rows"] if r["model"] == name):
            print(f"   {r['omega_rpm']:5g} RPM ({r['role']}): xi {r['xi']:.3f}  v {r['velocity']:.4f} ({100 * r['dv']:+.1f} %)  "
                  f"sinkage {1e3 * r['sinkage']:.2f} mm ({100 * r['ds']:+.1f} %)  slip {r['slip']:.3f} (MPM {r['mpm_slip']:.3f})")  # fmt: skip
    print("xi giving the MPM sinkage:")
    for r in (r for r in result["rows"] if r["model"] == "xi for the MPM sinkage"):
        print(f"   {r['omega_rpm']:5g} RPM: xi {r['xi']:.3f} ({r['xi'] / result['fits']['xi-DRFT (c = 0)']['xi_ref']:.3f} of the fit)  "
              f"v {100 * r['dv']:+.1f} %  slip {r['slip']:.3f} (MPM {r['mpm_slip']:.3f})")  # fmt: skip
    print(f"wrote {args.out}.csv, _held.csv, .json, .png")


if __name__ == "__main__":
    main()
