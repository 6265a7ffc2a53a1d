"""New wheels for DRFT to predict: the Table S1 wheel with another number of grousers, load or push.

The bulldozing coefficient k_b was fitted on the 20-grouser wheel of 6.3 kg with the MPM runs' 4 N
forward push (research/notes/results_log.md, "A body-level resistance: DRFT + bulldozing"). Here DRFT predicts,
before any MPM run of them, wheels of the same hub and grouser size with N grousers (same
inertias), another vertical mass m_z (weight m_z g; the horizontal inertia and the push kept), or
another constant forward push (N; < 0 a drawbar load), at one omega; the MPM runs
(`research/mpm_contact_band.py wheel 30 ... --lug-count N`, `--mass-z KG` or `--push N`) are then
set against the prediction.

    python research/wheel_variants.py predict --calibration research/outputs/calibration_wheel_band0_settled_bulldozing.json \
        --out research/outputs/wheel_lugs_prediction.csv
    python research/wheel_variants.py compare runs/lugs/* --window 2.0 3.0 \
        --prediction research/outputs/wheel_lugs_prediction.csv --out research/outputs/wheel_lugs \
        --history research/outputs/wheel_30rpm_start_band0.csv:grousered_wheel_30rpm_2.5mm_band0_1x0.4m_bed0.15m:20
    python research/wheel_variants.py predict --calibration research/outputs/calibration_wheel_band0_settled_bulldozing.json \
        --lug-counts 20 --mass-z 3.15 6.3 9.45 --out research/outputs/wheel_load_prediction.csv
    python research/wheel_variants.py predict --calibration research/outputs/calibration_wheel_band0_settled_bulldozing.json \
        --lug-counts 20 --push -4 0 4 8 12 --out research/outputs/wheel_push_prediction.csv

`predict` writes, for each variant (N, m_z, push) and model (the paper's DRFT; the paper's DRFT +
bulldozing with the calibration's k_b), the steady v and sinkage. `compare` averages each MPM run
over the window (`summarise_run`; --history: the 0.25 s windows a run_histories CSV kept of a run
whose folder is gone, here the 20-grouser wheel in the same box), writes NAME.csv (MPM and
prediction per variant; for the MPM runs also the rear surface drop dh over the window, the mean
and the median of the run's own measurements, one per 0.05 s: a snapshot that catches grains
carried up the wheel's rear gives a large negative drop, which moves the mean) and NAME.png (against the one variant axis along which the runs differ).
"""

from __future__ import annotations

import argparse
import csv
import json
import math
import statistics
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from pydantic import ValidationError  # noqa: E402

from intrusim.analysis.calibration import RPM, with_mpm_push, with_parameters  # noqa: E402
from intrusim.analysis.steady import run_steady, window_drift  # noqa: E402
from intrusim.params import GRAVITY  # noqa: E402
from intrusim.scenarios import grousered_wheel_scenario  # noqa: E402
from intrusim.scenarios.locomotor import with_lug_count, with_mass_z  # noqa: E402

FIELDS = ("lug_count", "mass_z", "push", "omega_rpm", "model", "velocity", "sinkage", "slip")
TABLE_S1_MASS_Z = grousered_wheel_scenario().mass_z  # kg, the wheel k_b was fitted on
MPM_PUSH = with_mpm_push(grousered_wheel_scenario()).external_fx  # N, the MPM runs' forward push (4 N)
AXES = {  # variant axis: (label of a plot's x axis, its value in the plot, the figure title's words)
    "lug_count": ("grousers", lambda r: r["lug_count"], "N grousers"),
    "mass_z": ("weight m_z g (N)", lambda r: r["mass_z"] * GRAVITY, "another load"),
    "push": ("forward push (N)", lambda r: r["push"], "another forward push"),
}


def wheel(lug_count: int, k_b: float, mass_z: float = TABLE_S1_MASS_Z, push: float = MPM_PUSH):
    """The paper's DRFT wheel (rear half, lambda 1, the identity psi) with ``lug_count`` grousers,
    vertical mass ``mass_z`` (kg), a constant forward push (N; the MPM runs' 4 N by default) and k_b."""
    s = with_mass_z(with_lug_count(grousered_wheel_scenario(), lug_count), mass_z)
    return with_parameters(s.model_copy(update=dict(external_fx=float(push))), {"bulldozing": k_b})


def predict(args: argparse.Namespace) -> None:
    k_b = float(json.loads(Path(args.calibration).read_text())["calibration"]["values"]["bulldozing"])
    models = (("DRFT (paper)", 0.0), (f"DRFT + bulldozing (k_b {k_b:.3g})", k_b))
    try:  # every variant validated (lugs fit, mass_z > 0) before the first run
        grid = [(n, mz, f) for n in args.lug_counts for mz in args.mass_z for f in args.push]
        variants = {(n, mz, f, k): wheel(n, k, mz, f) for n, mz, f in grid for _, k in models}
    except ValidationError as e:
        raise SystemExit(f"bad variant: {e}") from None
    rows = []
    for n, mz, f in grid:
        for label, k in models:
            st = run_steady(variants[n, mz, f, k], "drft", args.rpm)
            rows.append({"lug_count": n, "mass_z": mz, "push": f, "omega_rpm": args.rpm, "model": label,
                         "velocity": st.velocity, "sinkage": st.sinkage, "slip": st.slip})  # fmt: skip
            print(
                f"{_variant(n, mz, f)}, {label:<28s} v {st.velocity:.4f} m/s, sinkage {st.sinkage * 1e3:.1f} mm, slip {st.slip:.3f}"
            )
    _write(Path(args.out), rows)


def compare(args: argparse.Namespace) -> None:
    from intrusim.scenarios.locomotor import LocomotorScenario
    from intrusim.scenarios.mpm_locomotion import MPMSettings, forward_force, read_progress, summarise_run

    with Path(args.prediction).open(newline="") as f:
        pred = [dict(r, lug_count=int(r["lug_count"]), mass_z=float(r.get("mass_z") or TABLE_S1_MASS_Z),
                     push=float(r.get("push") or MPM_PUSH), velocity=float(r["velocity"]), sinkage=float(r["sinkage"]))
                for r in csv.DictReader(f)]  # fmt: skip
    rows = []
    for run in map(Path, args.runs):
        info_path = run / "locomotion.json"
        if not info_path.exists():
            continue
        info = json.loads(info_path.read_text())
        n, mz = int(info["scenario"]["lug_count"]), float(info["scenario"]["mass_z"])
        push = forward_force(
            LocomotorScenario.model_validate(info["scenario"]), MPMSettings.model_validate(info["settings"])
        )
        st = summarise_run(run, t_start=args.window[0], t_end=args.window[1])
        drops = [
            d for t, d in read_progress(run)[0] if args.window[0] < t <= args.window[1] + 1e-9 and math.isfinite(d)
        ]
        rows.append({"lug_count": n, "mass_z": mz, "push": push, "omega_rpm": round(st.omega / RPM, 3), "model": "MPM",
                     "velocity": st.velocity, "sinkage": st.sinkage, "slip": st.slip, "drift": st.drift,
                     "surface_drop": st.surface_drop, "surface_drop_median": statistics.median(drops) if drops else "",
                     "run": str(run)})  # fmt: skip
    for item in args.history:  # a run whose folder is gone: its windows in a run_histories CSV
        path, run_name, n = item.rsplit(":", 2)
        with Path(path).open(newline="") as f:
            win = [r for r in csv.DictReader(f) if r["run"] == run_name
                   and float(r["t_start"]) >= args.window[0] - 1e-9 and float(r["t_end"]) <= args.window[1] + 1e-9]  # fmt: skip
        if not win:
            raise SystemExit(f"{path}: no window of {run_name} within {args.window}")
        v, sk = [float(r["velocity"]) for r in win], [float(r["sinkage"]) for r in win]  # equal windows
        rows.append({"lug_count": int(n), "mass_z": TABLE_S1_MASS_Z, "push": MPM_PUSH, "omega_rpm": rows[0]["omega_rpm"] if rows else args.rpm, "model": "MPM",
                     "velocity": sum(v) / len(v), "sinkage": sum(sk) / len(sk), "slip": "",
                     "drift": window_drift(v, sk, grousered_wheel_scenario().radius), "run": f"{path}:{run_name}"})  # fmt: skip
    if not rows:
        raise SystemExit("no MPM run folder (with locomotion.json) among the arguments")
    out = Path(args.out)
    _write(
        out.with_suffix(".csv"),
        rows + [dict(r, drift="", run="") for r in pred],
        FIELDS + ("drift", "surface_drop", "surface_drop_median", "run"),
    )
    for r in sorted(rows, key=_key):
        print(
            f"{_variant(r['lug_count'], r['mass_z'], r['push'])}, MPM: v {r['velocity']:.4f} m/s, sinkage {r['sinkage'] * 1e3:.1f} mm (drift {r['drift']:.3f})"
        )
        for p in (p for p in pred if _key(p) == _key(r)):
            print(f"      {p['model']:<28s} v {p['velocity']:.4f} ({p['velocity'] / r['velocity'] - 1:+.1%}), "
                  f"sinkage {p['sinkage'] * 1e3:.1f} mm ({p['sinkage'] / r['sinkage'] - 1:+.1%})")  # fmt: skip
    # the plot's x axis: the one variant axis along which the MPM runs differ (grousers if none);
    # the predictions shown: those at the runs' values of the other axes
    keys = list(AXES)
    varying = [i for i in range(len(keys)) if len({_key(r)[i] for r in rows}) > 1] or [0]
    if len(varying) > 1:
        raise SystemExit(f"the runs differ in {[keys[i] for i in varying]}: compare runs that differ in one of them")
    axis = varying[0]
    fixed = {i: {_key(r)[i] for r in rows} for i in range(len(keys)) if i != axis}
    pred = [p for p in pred if all(_key(p)[i] in vals for i, vals in fixed.items())]
    xlabel, x_of, what = AXES[keys[axis]]
    fig, axes = plt.subplots(1, 2, figsize=(9, 3.6))
    models = list(dict.fromkeys(p["model"] for p in pred))
    for ax, key, unit, scale in ((axes[0], "velocity", "v (m/s)", 1.0), (axes[1], "sinkage", "sinkage (mm)", 1e3)):
        for m in models:
            pts = sorted((x_of(p), p[key] * scale) for p in pred if p["model"] == m)
            ax.plot(*zip(*pts), "o-", label=m)
        mpm = sorted((x_of(r), r[key] * scale) for r in rows)
        ax.plot(*zip(*mpm), "ks", ms=8, label=f"MPM ({args.window[0]:g}-{args.window[1]:g} s)")
        ax.set_xlabel(xlabel)
        ax.set_ylabel(unit)
    axes[0].legend(fontsize=8)
    fig.suptitle(
        f"Table S1 wheel with {what}, {rows[0]['omega_rpm']:g} RPM:\n"
        "DRFT predictions (k_b fitted on N = 20, 6.3 kg, 4 N) and MPM",
        fontsize=10,
    )
    fig.tight_layout()
    fig.savefig(out.with_suffix(".png"), dpi=120)
    print(out.with_suffix(".csv"), out.with_suffix(".png"))


def _key(r: dict) -> tuple[int, float, float]:
    """A variant's place along AXES: (grousers, m_z in kg, push in N), rounded for matching."""
    return int(r["lug_count"]), round(float(r["mass_z"]), 6), round(float(r["push"]), 6)


def _variant(n: int, mass_z: float, push: float) -> str:
    return f"{n:3d} grousers, {mass_z:g} kg, {push:g} N push"


def _write(path: Path, rows: list[dict], fields: tuple[str, ...] = FIELDS) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    with path.open("w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(fields), extrasaction="ignore")
        w.writeheader()
        w.writerows(rows)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = ap.add_subparsers(dest="cmd", required=True)
    p = sub.add_parser("predict")
    p.add_argument("--calibration", required=True, help="an `intrusim calibrate` JSON with a fitted bulldozing k_b")
    p.add_argument("--lug-counts", type=int, nargs="+", default=[10, 15, 20, 30])
    p.add_argument(
        "--mass-z",
        type=float,
        nargs="+",
        default=[TABLE_S1_MASS_Z],
        metavar="KG",
        help="vertical masses m_z, kg (default: the Table S1 wheel's)",
    )
    p.add_argument(
        "--push",
        type=float,
        nargs="+",
        default=[MPM_PUSH],
        metavar="N",
        help="constant forward pushes, N (default: the MPM runs' 4 N; < 0 pulls back, a drawbar load)",
    )
    p.add_argument("--rpm", type=float, default=30.0)
    p.add_argument("--out", required=True)
    c = sub.add_parser("compare")
    c.add_argument("runs", nargs="+")
    c.add_argument("--window", type=float, nargs=2, default=(2.0, 3.0), metavar=("T0", "T1"))
    c.add_argument("--prediction", required=True)
    c.add_argument(
        "--history",
        action="append",
        default=[],
        metavar="CSV:RUN:N",
        help="an MPM run of N grousers (6.3 kg) whose folder is gone, from the windows of a run_histories CSV (repeatable)",
    )
    c.add_argument("--rpm", type=float, default=30.0, help="omega of --history runs when no run folder is given")
    c.add_argument("--out", required=True)
    args = ap.parse_args()
    predict(args) if args.cmd == "predict" else compare(args)


if __name__ == "__main__":
    main()
