"""How does the MPM's steady slip follow the grain length d / r? The half-size twins at several d.

The half-size twin of the 5 mm large wheel at 30 RPM (small wheel, 2.5 mm cells, half box, 42.43 RPM:
the same omega / omega_0) was run with the nonlocal law's grain diameter d = 3, 6 and 12 mm
(d / r 0.057, 0.113, 0.226) and carried to the reference's 8.5 s (the twin's 6.01 s). This script
reads each run's window means over one window of the twin's time, tabulates slip and sinkage / r
against d / r, the change per doubling of d, and plots them with the reference (the large wheel,
6 mm grains, d / r 0.057) for scale (docs/results.md, sessions 41-42):

    python examples/grain_length_twins.py \\
        --run docs/figures/small_wheel_42rpm_twin_6s.csv "small wheel, 2.5 mm, 3 mm grains, half box" 3e-3 \\
        --run docs/figures/small_wheel_42rpm_twin_d6_6s.csv "small wheel, 2.5 mm, 6 mm grains, half box" 6e-3 \\
        --run docs/figures/small_wheel_42rpm_twin_d12_6s.csv "small wheel, 2.5 mm, 12 mm grains, half box" 12e-3 \\
        --reference docs/figures/wheel_30rpm_nonlocal_treadmill.csv "5 mm, treadmill in 1 m" 6e-3 \\
        --window 6.0 8.5 --out docs/figures/grain_length_twins

``--run`` takes a run_histories.py window CSV of the small wheel at 42.4264 RPM, the run's label and
its grain diameter (m); ``--reference`` the same for the large wheel at 30 RPM. ``--window`` is in
the reference's time (the twins' is sqrt(r_small / r_large) of it). Writes OUT.csv (one row per run),
OUT.json (the rows and the change per doubling of d between neighbours) and OUT.png.
"""

from __future__ import annotations

import argparse
import json
import math
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from intrusim._checks import InputError, positive  # noqa: E402
from intrusim.analysis.histories import read_windows, wheel_state, window_mean  # noqa: E402
from intrusim.mpm.io import write_csv  # noqa: E402
from intrusim.scenarios.locomotor import grousered_wheel_scenario, small_wheel_scenario  # noqa: E402

TWIN_RPM, REFERENCE_RPM = 42.4264, 30.0  # the same omega / omega_0 (30 sqrt(2) RPM for half the radius)


def state(path: Path, label: str, d: float, rpm: float, radius: float, window: tuple[float, float]) -> dict:
    """One run's window means over ``window`` (its own time, s): slip and sinkage / r at d / r."""
    m = wheel_state(window_mean(read_windows(path, label), *window), rpm, radius)
    return {"label": label, "d": positive("grain diameter", d), "d_over_r": d / radius, "radius": radius, **m}


def analyse(runs: list[tuple[Path, str, float]], reference: tuple[Path, str, float] | None,
            window: tuple[float, float]) -> dict:
    """The twins' states over ``window`` (the reference's time), sorted by d, and the change of slip
    and sinkage / r per doubling of d between neighbours (d(value) / d(log2 d))."""
    if window[1] <= window[0]:
        raise InputError(f"the window must end after it starts, got {window[0]}-{window[1]} s")
    if len({d for _, _, d in runs}) != len(runs) or len(runs) < 2:
        raise InputError("give two or more runs, each with its own grain diameter")
    big, small = grousered_wheel_scenario(), small_wheel_scenario()
    ratio = math.sqrt(small.radius / big.radius)  # twin time / reference time
    twin_window = (window[0] * ratio, window[1] * ratio)
    rows = sorted((state(p, lab, d, TWIN_RPM, small.radius, twin_window) for p, lab, d in runs), key=lambda r: r["d"])
    steps = [{"from_d": a["d"], "to_d": b["d"],
              **{f"{k}_per_doubling": (b[k] - a[k]) / math.log2(b["d"] / a["d"]) for k in ("slip", "sinkage_over_r")}}
             for a, b in zip(rows, rows[1:])]  # fmt: skip
    out = {"window": list(window), "twin_window": list(twin_window), "runs": rows, "steps": steps}
    if reference is not None:
        out["reference"] = state(*reference, REFERENCE_RPM, big.radius, window)
    return out


def plot(result: dict, path: Path) -> None:
    fig, axes = plt.subplots(1, 2, figsize=(10, 4))
    rows, ref = result["runs"], result.get("reference")
    for ax, key, name in zip(axes, ("slip", "sinkage_over_r"), ("slip", "sinkage / r")):
        ax.plot([r["d_over_r"] for r in rows], [r[key] for r in rows], "s-", color="C3", label="half-size twins (small wheel)")
        if ref is not None:
            ax.plot([ref["d_over_r"]], [ref[key]], "o", color="k", label="large wheel, 6 mm grains (the reference)")
        ax.set_xscale("log", base=2)
        ax.set(xlabel="grain length d / r", ylabel=name)
    handles, names = axes[0].get_legend_handles_labels()
    fig.legend(handles, names, fontsize=8, loc="lower center", ncol=2)
    w = result["window"]
    fig.suptitle(f"MPM steady state against the grain length, same omega / omega_0 (reference's {w[0]:g}-{w[1]:g} s)")
    fig.tight_layout(rect=(0.0, 0.07, 1.0, 1.0))
    fig.savefig(path, dpi=120)
    plt.close(fig)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--run", nargs=3, action="append", required=True, metavar=("CSV", "LABEL", "D"))
    ap.add_argument("--reference", nargs=3, metavar=("CSV", "LABEL", "D"))
    ap.add_argument("--window", nargs=2, type=float, required=True, metavar=("T0", "T1"), help="the reference's time, s")
    ap.add_argument("--out", required=True)
    args = ap.parse_args()
    runs = [(Path(p), lab, float(d)) for p, lab, d in args.run]
    reference = None if args.reference is None else (Path(args.reference[0]), args.reference[1], float(args.reference[2]))
    try:
        result = analyse(runs, reference, tuple(args.window))
    except InputError as e:
        raise SystemExit(str(e)) from None
    out = Path(args.out)
    out.parent.mkdir(parents=True, exist_ok=True)
    write_csv(out.with_suffix(".csv"), result["runs"])
    out.with_suffix(".json").write_text(json.dumps(result, indent=2) + "\n")
    plot(result, out.with_suffix(".png"))
    for r in result["runs"] + ([result["reference"]] if "reference" in result else []):
        print(f"{r['label']}: d / r {r['d_over_r']:.3f}, slip {r['slip']:.3f}, sinkage / r {r['sinkage_over_r']:.3f}, "
              f"{r['windows']} windows, drift {r['drift'] * 100:+.1f} %")  # fmt: skip
    for s in result["steps"]:
        print(f"d {s['from_d'] * 1e3:g} -> {s['to_d'] * 1e3:g} mm: slip {s['slip_per_doubling']:+.3f}, "
              f"sinkage / r {s['sinkage_over_r_per_doubling']:+.3f} per doubling of d")


if __name__ == "__main__":
    main()
