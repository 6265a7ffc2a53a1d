"""DRFT's force on the wheel along the MPM wheel's own steady motion: where the two disagree.

The steady states of DRFT and MPM differ (research/notes/results_log.md, Fig 5A-B); this asks why, one
force component at a time. Over the last --last seconds of each finished MPM run, every
sample of the MPM trajectory (x, z, theta, vx, vz, omega) is given to the DRFT force models
of the run's scenario (the free surface at the bed's undisturbed height), and the mean DRFT
force and moment are set against the mean force and moment the MPM grains put on the wheel.
At the MPM's steady state the grains' force balances the load: fx = -(forward push), fz = the
weight, so DRFT's excess over the MPM's fx is the net thrust that would drive the DRFT wheel
faster than the MPM one, and its fz excess the lift that would hold it higher.

Models: the paper's DRFT (rear-half split), the effective split, quasistatic RFT, each
calibrated force model given with --calibration NAME=JSON (an `intrusim calibrate` output), and
the paper's DRFT with other grouser-shadowing factors (--lug-scale S: grousers S x their true
height; the paper's 1/3).
Writes OUT.csv (one row per run and model) and OUT.png (fx, fz and moment against omega); with
--parts also OUT_parts.csv and OUT_parts.png: the paper's DRFT force by part (rim, grouser sides,
grouser tips) ahead of and behind the wheel centre, and the MPM's own ahead / behind split where
its time series has it (fx_ahead, fz_ahead: runs made or extended since that column exists).

    python research/drft_at_mpm_state.py runs/settled/* runs/digging/90 --last 1.0 --parts \
        --calibration "4p fit (settled)=research/outputs/calibration_wheel_band0_settled_4p.json" \
        --out research/outputs/drft_at_mpm_state
    python research/drft_at_mpm_state.py runs/split/* --last 0.5 --parts --out research/outputs/drft_at_mpm_state_split
"""

from __future__ import annotations

import argparse
import csv
import json
from pathlib import Path

import matplotlib
import numpy as np

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from intrusim.analysis.compare import forces_by_part, mean_wrench_along  # noqa: E402
from intrusim.kinematics import BodyState  # noqa: E402
from intrusim.mpm.io import read_timeseries  # noqa: E402
from intrusim.scenarios.base import ForceModelConfig  # noqa: E402
from intrusim.scenarios.locomotor import LocomotorScenario  # noqa: E402
from intrusim.scenarios.mpm_locomotion import summarise_run  # noqa: E402

FIELDS = ("fx", "fz", "moment")


def models(scenario: LocomotorScenario, calibrations: dict[str, dict], lug_scales: list[float]) -> dict[str, object]:
    """The force models compared, by label."""
    fm = scenario.force_model

    def with_fm(**update: object) -> LocomotorScenario:
        return scenario.model_copy(update={"force_model": fm.model_copy(update=update)})

    out = {
        "RFT": scenario.build_model("rft"),
        "DRFT (paper)": with_fm(structural="wheel-rear-half").build_model("drft"),
        "DRFT, effective split": with_fm(structural="wheel-rear-half-effective").build_model("drft"),
    }
    for label, values in calibrations.items():
        out[label] = scenario.model_copy(update={"force_model": ForceModelConfig(**values)}).build_model("drft")
    for h in lug_scales:  # the paper's DRFT with another grouser-shadowing factor (paper: 1/3)
        out[f"DRFT (paper), grousers x{h:g}"] = with_fm(structural="wheel-rear-half").model_copy(
            update={"lug_height_scale": h}).build_model("drft")  # fmt: skip
    return out


def part_forces(model: object, s: dict[str, np.ndarray], surface: float) -> dict[str, np.ndarray]:
    """Mean (fx, fz) of each part of the wheel, ahead of and behind its centre (NumPy path)."""
    els = model.elements  # type: ignore[attr-defined]
    acc: dict[str, list] = {}
    for x, z, th, vx, vz, om in zip(s["x"], s["z"], s["theta"], s["vx"], s["vz"], s["omega"]):
        pos, t = model.element_tractions(BodyState(x, z - surface, th, vx, vz, om))  # type: ignore[attr-defined]
        f = t * els.area[:, None]
        for key, part in forces_by_part(els.tag, pos[:, 0] > x, f, halves=("front", "rear")).items():
            acc.setdefault(key, []).append(part)
    return {k: np.mean(v, axis=0) for k, v in acc.items()}


def mpm_ahead(run: Path, t0: float, t1: float) -> np.ndarray | None:
    """Mean (fx, fz) of the MPM grains on the wheel from the grid nodes ahead of its centre over
    [t0, t1] (time-series columns fx_ahead, fz_ahead), or None where the run has not recorded them."""
    ts = read_timeseries(run / "timeseries.csv")  # units in the header or not (older runs)
    sel = (ts["time"] >= t0 - 1e-9) & (ts["time"] <= t1 + 1e-9)
    if not sel.any() or "fx_ahead" not in ts or np.isnan(ts["fx_ahead"][sel]).any():
        return None
    return np.array([ts["fx_ahead"][sel].mean(), ts["fz_ahead"][sel].mean()])


def plot_halves(parts: list[dict], path: Path) -> None:
    """Bars of fx and fz ahead of / behind the wheel centre: DRFT (paper) and, where recorded, MPM."""
    halves = [r for r in parts if r["part"].startswith("all parts")]
    keys = list(dict.fromkeys((r["omega_rpm"], r["model"]) for r in halves))
    fig, axes = plt.subplots(1, 2, figsize=(10, 3.6))
    for ax, field in zip(axes, ("fx", "fz")):
        for i, (w, model) in enumerate(keys):
            for j, half in enumerate(("front", "rear")):
                v = [
                    r[field] for r in halves if (r["omega_rpm"], r["model"]) == (w, model) and r["part"].endswith(half)
                ][0]
                color = (
                    ("k" if model == "MPM" else "C1") if half == "front" else ("0.6" if model == "MPM" else "#f5c38f")
                )
                ax.bar(i + 0.4 * j - 0.2, v, width=0.38, color=color, label=f"{model}, {'ahead of' if half == 'front' else 'behind'} the centre" if i < 2 else None)  # fmt: skip
        ax.set_xticks(range(len(keys)), [f"{w:g} RPM\n{m}" for w, m in keys], fontsize=7)
        ax.set_ylabel(f"mean {field} on the wheel (N)")
        ax.axhline(0.0, color="0.5", lw=0.8)
    fig.legend(*axes[0].get_legend_handles_labels(), loc="lower center", ncol=4, fontsize=7)
    fig.suptitle("Force ahead of and behind the wheel centre, along the MPM's motion")
    fig.tight_layout(rect=(0, 0.07, 1, 1))
    fig.savefig(path, dpi=120)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("runs", nargs="+", type=Path, help="finished MPM wheel run folders")
    ap.add_argument("--last", type=float, default=1.0, help="averaging window: each run's last LAST seconds")
    ap.add_argument("--calibration", action="append", default=[], metavar="LABEL=JSON",
                    help="a calibrated DRFT (intrusim calibrate JSON) to compare as well; repeatable")  # fmt: skip
    ap.add_argument("--lug-scale", type=float, action="append", default=[], metavar="S",
                    help="also the paper's DRFT with the grousers' effective height S x the true one (paper 1/3); repeatable")  # fmt: skip
    ap.add_argument("--parts", action="store_true",
                    help="also split the paper's DRFT force by part (rim, grouser sides, tips) and half, and the "
                         "MPM's by half where its time series has fx_ahead: OUT_parts.csv")  # fmt: skip
    ap.add_argument("--out", type=Path, required=True, help="output stem (writes OUT.csv and OUT.png)")
    args = ap.parse_args()
    if args.last <= 0:
        ap.error(f"--last must be > 0, got {args.last}")
    if any(not 0.0 < h <= 10.0 for h in args.lug_scale):
        ap.error(f"--lug-scale must be in (0, 10], got {args.lug_scale}")
    calibrations = {}
    for item in args.calibration:
        label, sep, path = item.partition("=")
        if not sep:
            ap.error(f"--calibration must be LABEL=JSON, got {item!r}")
        calibrations[label] = json.loads(Path(path).read_text())["calibration"]["force_model"]

    rows, parts = [], []
    for run in args.runs:
        meta = json.loads((run / "locomotion.json").read_text())
        scenario = LocomotorScenario.model_validate(meta["scenario"])
        s = summarise_run(run, t_start=0.0).series  # the whole series (the window is cut below)
        win = s["time"] >= float(np.max(s["time"])) - args.last
        s = {k: np.asarray(v)[win] for k, v in s.items()}
        base = {"run": run.name, "omega_rpm": float(meta["omega_rpm"]), "t0": float(s["time"][0]),
                "t1": float(s["time"][-1]), "samples": int(win.sum()), "velocity": float(np.mean(s["vx"])),
                "sinkage": float(np.mean(s["sinkage"]))}  # fmt: skip
        mpm = np.array([np.mean(s[f]) for f in FIELDS])
        rows.append({**base, "model": "MPM", **dict(zip(FIELDS, mpm))})
        built = models(scenario, calibrations, args.lug_scale)
        for label, model in built.items():
            rows.append(
                {
                    **base,
                    "model": label,
                    **dict(zip(FIELDS, mean_wrench_along(model, s, meta["settings"]["bed_depth"]))),
                }
            )
        if args.parts:
            split = part_forces(built["DRFT (paper)"], s, meta["settings"]["bed_depth"])
            for half in ("front", "rear"):
                split[f"all parts, {half}"] = sum(v for k, v in split.items() if k.endswith(half))
            entries = [("DRFT (paper)", name, f) for name, f in split.items()]
            ahead = mpm_ahead(run, float(s["time"][0]), float(s["time"][-1]))
            if ahead is not None:  # the MPM's own split (grid nodes ahead of / behind the centre)
                entries += [("MPM", "all parts, front", ahead), ("MPM", "all parts, rear", mpm[:2] - ahead)]
            for model_name, name, (fx, fz) in entries:
                parts.append(
                    {
                        "run": run.name,
                        "omega_rpm": base["omega_rpm"],
                        "model": model_name,
                        "part": name,
                        "fx": fx,
                        "fz": fz,
                    }
                )
        print(
            f"{run.name}: {meta['omega_rpm']:g} RPM, {win.sum()} samples over {s['time'][0]:.2f}-{s['time'][-1]:.2f} s"
        )
        for r in (r for r in rows if r["run"] == run.name):
            print(f"  {r['model']:<28s} fx {r['fx']:8.2f} N  fz {r['fz']:8.2f} N  moment {r['moment']:7.3f} N m")
        for r in (r for r in parts if r["run"] == run.name):
            print(f"    {r['model']}, {r['part']:<20s} fx {r['fx']:8.2f} N  fz {r['fz']:8.2f} N")

    args.out.parent.mkdir(parents=True, exist_ok=True)
    with args.out.with_suffix(".csv").open("w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    if parts:
        with args.out.with_name(args.out.name + "_parts.csv").open("w", newline="") as f:
            w = csv.DictWriter(f, fieldnames=list(parts[0]))
            w.writeheader()
            w.writerows(parts)
        plot_halves(parts, args.out.with_name(args.out.name + "_parts.png"))
    labels = list(dict.fromkeys(r["model"] for r in rows))
    fig, axes = plt.subplots(1, 3, figsize=(13, 3.8))
    for ax, field, unit in zip(axes, FIELDS, ("N", "N", "N m")):
        for label in labels:
            pts = sorted((r["omega_rpm"], r[field]) for r in rows if r["model"] == label)
            style = dict(color="k", ls="--", marker="o", mfc="w") if label == "MPM" else dict(marker=".")
            ax.plot(*zip(*pts), label=label, **style)
        ax.set_xlabel("omega (RPM)")
        ax.set_ylabel(f"mean {field} on the wheel ({unit})")
        ax.axhline(0.0, color="0.8", lw=0.8)
    axes[0].legend(fontsize=7)
    fig.suptitle(f"Force on the wheel along the MPM's own motion (each run's last {args.last:g} s)")
    fig.tight_layout()
    fig.savefig(args.out.with_suffix(".png"), dpi=120)
    print(f"wrote {args.out.with_suffix('.csv')} and .png")


if __name__ == "__main__":
    main()
