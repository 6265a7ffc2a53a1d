"""Is it the grain size? Two runs of one wheel that differ only in the nonlocal law's grain diameter.

The 1.25 mm small wheel at 60 RPM (0.65 omega_0) slips half as much as the large wheel at the
same omega / omega_0, so the MPM with the nonlocal law is not size-similar. The law carries one
length, the grain diameter d (6 mm: 0.11 r of the small wheel, 0.057 r of the large). Halving d
for the small wheel makes it the large wheel at 2.5 mm scaled by 1/2 in every length of the law
and of the mesh. This script puts the two small-wheel runs (d = 6 and 3 mm, the same window) side
by side with the large wheel's steady state at the same omega / omega_0 (linear in omega between
two of its settled runs), and gives the verdict registered in research/notes/results_log.md (b119ed1):

    python research/grain_size_pair.py \\
        --run research/outputs/small_wheel_60rpm_nonlocal_cells_3p5s.csv "small wheel, 1.25 mm, 60 RPM, 0.45 m box, to 3.5 s" 6e-3 \\
        --run research/outputs/small_wheel_60rpm_nonlocal_d3mm.csv "small wheel, 1.25 mm, 60 RPM, 0.45 m box, 3 mm grains" 3e-3 \\
        --large research/outputs/wheel_30rpm_nonlocal_treadmill_steady.csv "2.5 mm, treadmill in 1 m from 2.75 s" \\
        --large research/outputs/wheel_60rpm_nonlocal_treadmill_steady.csv "2.5 mm, treadmill in 1 m" \\
        --omega 60 --window 1.5 2.0 --out research/outputs/grain_size_pair

``--run`` takes a run_histories.py window CSV, the run's label in it and its grain diameter (m);
``--large`` a run_histories.py ``_steady.csv`` and the row's label (its omega is in the row). Writes OUT.csv
(every 0.25 s window of each run: v, sinkage, slip, sinkage / r), OUT.json (the window means, the
change from the first run to the second, the large wheel's state and the verdict) and OUT.png.
"""

from __future__ import annotations

import argparse
import json
import math
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from helpers.histories import read_steady, read_windows, wheel_state, window_mean  # noqa: E402

from intrusim._checks import InputError  # noqa: E402
from intrusim.mpm.io import write_csv  # noqa: E402
from intrusim.scenarios.locomotor import grousered_wheel_scenario, small_wheel_scenario  # noqa: E402

# registered in b119ed1, over 1.5-2.0 s: the grain length explains the size effect if slip >= 0.11
# and sinkage >= 9.9 mm; it does not if slip <= 0.095 and sinkage <= 9.6 mm; in between, in part
IN_FULL = (0.11, 9.9e-3)
NOT_AT_ALL = (0.095, 9.6e-3)


def large_at(points: list[tuple[float, dict]], omega_rpm: float, radius: float) -> dict:
    """The large wheel's slip and sinkage / r at ``omega_rpm``, linear in omega between two runs."""
    (w0, a), (w1, b) = sorted(points, key=lambda p: p[0])
    f = (omega_rpm - w0) / (w1 - w0)
    return {
        "omega_rpm": omega_rpm,
        "slip": a["slip"] + f * (b["slip"] - a["slip"]),
        "sinkage_over_r": (a["sinkage"] + f * (b["sinkage"] - a["sinkage"])) / radius,
    }


def verdict(state: dict) -> str:
    """The registered reading of the second run's window (slip, sinkage)."""
    if state["slip"] >= IN_FULL[0] and state["sinkage"] >= IN_FULL[1]:
        return "in full"
    if state["slip"] <= NOT_AT_ALL[0] and state["sinkage"] <= NOT_AT_ALL[1]:
        return "not at all"
    return "in part"


def analyse(
    runs: list[tuple[Path, str, float]],
    large_runs: list[tuple[Path, str]],
    omega_rpm: float,
    window: tuple[float, float],
) -> tuple[list[dict], dict]:
    """Every window of both small-wheel runs (CSV, label, d) and the comparison over ``window``
    with the large wheel (steady CSV, label; two runs) at the same omega / omega_0."""
    r_small, r_large = small_wheel_scenario().radius, grousered_wheel_scenario().radius
    omega_large = omega_rpm * math.sqrt(r_small / r_large)  # the same omega / omega_0, omega_0 = sqrt(g / r)
    steady = [read_steady(p, lab) for p, lab in large_runs]
    large = large_at([(st["omega_rpm"], st) for st in steady], omega_large, r_large)
    rows, means = [], []
    for path, label, d in runs:
        windows = read_windows(path, label)
        for w in windows:
            rows.append({"label": label, "grain_diameter": d, **wheel_state(w, omega_rpm, r_small)})
        m = window_mean(windows, *window)
        m.update(label=label, grain_diameter=d)
        means.append({**wheel_state(m, omega_rpm, r_small), "grain_over_r": d / r_small})
    first, second = means
    return rows, {
        "window": list(window),
        "omega_rpm": omega_rpm,
        "radius": r_small,
        "runs": means,
        "change": {
            "slip": second["slip"] - first["slip"],
            "sinkage": second["sinkage"] - first["sinkage"],
            "velocity": second["velocity"] / first["velocity"] - 1.0,
        },
        "large_wheel": {**large, "grain_over_r": first["grain_diameter"] / r_large},
        "registered": {"in_full": IN_FULL, "not_at_all": NOT_AT_ALL},
        "verdict": verdict(second),
    }


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--run", nargs=3, action="append", required=True, metavar=("CSV", "LABEL", "D"))
    ap.add_argument("--large", nargs=2, action="append", required=True, metavar=("STEADY_CSV", "LABEL"))
    ap.add_argument("--omega", type=float, required=True, help="the small wheel's omega, RPM")
    ap.add_argument("--window", nargs=2, type=float, required=True, metavar=("T0", "T1"))
    ap.add_argument("--out", required=True)
    args = ap.parse_args()
    if len(args.run) != 2 or len(args.large) != 2:
        raise SystemExit("give two --run and two --large")

    try:
        rows, result = analyse(
            [(Path(p), lab, float(d)) for p, lab, d in args.run],
            [(Path(p), lab) for p, lab in args.large],
            args.omega,
            tuple(args.window),
        )
    except InputError as e:
        raise SystemExit(str(e)) from None
    runs, large, out = result["runs"], result["large_wheel"], Path(args.out)
    out.parent.mkdir(parents=True, exist_ok=True)
    write_csv(out.with_suffix(".csv"), rows)
    out.with_suffix(".json").write_text(json.dumps(result, indent=2) + "\n")
    plot(rows, runs, large, result["window"], out.with_suffix(".png"))
    for m in runs:
        print(
            f"d {m['grain_diameter'] * 1e3:.0f} mm ({m['grain_over_r']:.3f} r), {args.window[0]}-{args.window[1]} s: "
            f"v {m['velocity']:.4f} m/s, sinkage {m['sinkage'] * 1e3:.2f} mm, slip {m['slip']:.3f}, "
            f"sinkage / r {m['sinkage_over_r']:.3f}, drift {m['drift'] * 100:+.1f} %"
        )
    print(
        f"large wheel at {large['omega_rpm']:.1f} RPM (steady): slip {large['slip']:.3f}, sinkage / r {large['sinkage_over_r']:.3f}"
    )
    print(f"verdict (registered thresholds): the grain length explains the size effect {result['verdict']}")


def plot(rows: list[dict], runs: list[dict], large: dict, window, path: Path) -> None:
    fig, axes = plt.subplots(1, 2, figsize=(10, 4))
    for m, colour in zip(runs, ("C0", "C3")):
        mine = [r for r in rows if r["label"] == m["label"]]
        t = [0.5 * (r["t_start"] + r["t_end"]) for r in mine]
        name = f"small wheel, d = {m['grain_diameter'] * 1e3:.0f} mm ({m['grain_over_r']:.3f} r)"
        axes[0].plot(t, [r["slip"] for r in mine], "o-", color=colour, label=name)
        axes[1].plot(t, [r["sinkage_over_r"] for r in mine], "o-", color=colour, label=name)
    for ax, key in zip(axes, ("slip", "sinkage_over_r")):
        ax.axhline(large[key], color="k", ls="--", label=f"large wheel, steady at {large['omega_rpm']:.1f} RPM")
        ax.axvspan(*window, color="0.9", zorder=0)
        ax.set_xlabel("t (s)")
    axes[0].set_ylabel("slip")
    axes[1].set_ylabel("sinkage / r")
    axes[0].set_ylim(0, None)
    axes[1].legend(fontsize=8)
    fig.suptitle("Small wheel at 0.65 omega_0, 1.25 mm cells: grain diameter halved (shaded: the registered window)")
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


if __name__ == "__main__":
    main()
