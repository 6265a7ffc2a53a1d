"""How does the MPM's steady slip follow the grain length d / r? The half-size twins at several d.

The half-size twin of the 5 mm large wheel at 30 RPM (small wheel, 2.5 mm cells, half box, 42.43 RPM:
the same omega / omega_0) was run with the nonlocal law's grain diameter d = 3, 6 and 12 mm
(d / r 0.057, 0.113, 0.226) and carried to the reference's 8.5 s (the twin's 6.01 s). This script
reads each run's window means over one window of the twin's time, tabulates slip and sinkage / r
against d / r, the change per doubling of d, and plots them with the reference (the large wheel,
6 mm grains, d / r 0.057) for scale (research/notes/results_log.md):

    python research/grain_length_twins.py \\
        --run research/outputs/small_wheel_42rpm_twin_6s.csv "small wheel, 2.5 mm, 3 mm grains, half box" 3e-3 \\
        --run research/outputs/small_wheel_42rpm_twin_d6_6s.csv "small wheel, 2.5 mm, 6 mm grains, half box" 6e-3 \\
        --run research/outputs/small_wheel_42rpm_twin_d12_6s.csv "small wheel, 2.5 mm, 12 mm grains, half box" 12e-3 \\
        --reference research/outputs/wheel_30rpm_nonlocal_treadmill.csv "5 mm, treadmill in 1 m" 6e-3 \\
        --window 6.0 8.5 --out research/outputs/grain_length_twins

``--run`` takes a run_histories.py window CSV of the small wheel at 42.4264 RPM, the run's label and
its grain diameter (m); ``--reference`` the same for the large wheel at 30 RPM. ``--window`` is in
the reference's time (the twins' is sqrt(r_small / r_large) of it). Writes OUT.csv (one row per run),
OUT.json (the rows and the change per doubling of d between neighbours) and OUT.png.

The same question on the resolved grid: ``--fine CSV LABEL D`` (repeatable) adds large
wheels at 30 RPM on 2.5 mm cells (h / r 0.024 against the twins' 0.047), read over ``--fine-window``
(their own time), and ``--small-pair CSV LABEL D RPM T0 T1`` (twice) the small wheel on 1.25 mm
cells (h / r 0.024 too) at two omegas, each over its own window, interpolated linearly in omega to
42.43 RPM: by Froude scaling with d / r and h / r kept, the large wheel's twin at d / r of its grains::

    python research/grain_length_twins.py ... (the twins, as above) \
        --fine research/outputs/wheel_30rpm_nonlocal_treadmill.csv "2.5 mm, treadmill in 1 m from 2.75 s" 6e-3 \
        --fine research/outputs/wheel_30rpm_nonlocal_d12.csv "2.5 mm, 12 mm grains, treadmill in 1 m" 12e-3 \
        --fine-window 4.5 6.0 \
        --small-pair research/outputs/small_wheel_30rpm_nonlocal_cells_3p5s.csv \
            "small wheel, 1.25 mm, 0.45 m box, to 3.5 s" 6e-3 30 3.0 3.5 \
        --small-pair research/outputs/small_wheel_60rpm_nonlocal_cells_3s.csv \
            "small wheel, 1.25 mm, 60 RPM, 0.45 m box, to 3.0 s" 6e-3 60 2.5 3.0 \
        --out research/outputs/grain_length_grids
"""

from __future__ import annotations

import argparse
import json
import math
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from helpers.histories import read_windows, wheel_state, window_mean  # noqa: E402

from intrusim._checks import InputError, positive  # noqa: E402
from intrusim.mpm.io import write_csv  # noqa: E402
from intrusim.scenarios.locomotor import grousered_wheel_scenario, small_wheel_scenario  # noqa: E402

TWIN_RPM, REFERENCE_RPM = 42.4264, 30.0  # the same omega / omega_0 (30 sqrt(2) RPM for half the radius)


def _check_twin_rpm(big_radius: float, small_radius: float) -> None:
    """The runs were made at TWIN_RPM; it must be REFERENCE_RPM at the same omega / omega_0 = omega sqrt(r / g)."""
    same = REFERENCE_RPM * math.sqrt(big_radius / small_radius)
    if abs(TWIN_RPM / same - 1.0) > 1e-5:
        raise InputError(
            f"the twins' {TWIN_RPM} RPM is not the reference's omega / omega_0 for these wheels ({same:.4f} RPM)"
        )


def per_doubling(rows: list[dict]) -> list[dict]:
    """The change of slip and sinkage / r per doubling of d between neighbours (d(value) / d(log2 d))."""
    return [{"from_d": a["d"], "to_d": b["d"],
             **{f"{k}_per_doubling": (b[k] - a[k]) / math.log2(b["d"] / a["d"]) for k in ("slip", "sinkage_over_r")}}
            for a, b in zip(rows, rows[1:])]  # fmt: skip


def state(path: Path, label: str, d: float, rpm: float, radius: float, window: tuple[float, float]) -> dict:
    """One run's window means over ``window`` (its own time, s): slip and sinkage / r at d / r."""
    m = wheel_state(window_mean(read_windows(path, label), *window), rpm, radius)
    return {"label": label, "d": positive("grain diameter", d), "d_over_r": d / radius, "radius": radius, **m}


def interpolated(pair: list[tuple[Path, str, float, float, tuple[float, float]]], rpm: float, radius: float) -> dict:
    """The small wheel's slip and sinkage / r at ``rpm``, linear in omega between two runs (CSV, label, d,
    their RPM, their own window) of the same grains."""
    if len(pair) != 2 or pair[0][2] != pair[1][2] or pair[0][3] == pair[1][3]:
        raise InputError("give two small-wheel runs with the same grain diameter at two omegas")
    (a, b) = (state(p, lab, d, w_rpm, radius, window) | {"rpm": w_rpm} for p, lab, d, w_rpm, window in pair)
    f = (rpm - a["rpm"]) / (b["rpm"] - a["rpm"])
    return {"label": f"{a['label']} / {b['label']}, at {rpm:g} RPM", "d": a["d"], "d_over_r": a["d_over_r"], "rpm": rpm,
            "from": [a, b], **{k: a[k] + f * (b[k] - a[k]) for k in ("slip", "sinkage_over_r")}}  # fmt: skip


def _ordered(window: tuple[float, float]) -> tuple[float, float]:
    if window[1] <= window[0]:
        raise InputError(f"the window must end after it starts, got {window[0]}-{window[1]} s")
    return window


def analyse(
    runs: list[tuple[Path, str, float]],
    reference: tuple[Path, str, float] | None,
    window: tuple[float, float],
    fine: list[tuple[Path, str, float]] | None = None,
    fine_window: tuple[float, float] | None = None,
    small_pair: list[tuple[Path, str, float, float, tuple[float, float]]] | None = None,
) -> dict:
    """The twins' states over ``window`` (the reference's time), sorted by d, and the change of slip
    and sinkage / r per doubling of d between neighbours (d(value) / d(log2 d)); with ``fine`` the
    large wheels on the finer grid over ``fine_window`` (sorted by d, with their steps), with
    ``small_pair`` the small wheel on that grid interpolated to the twins' omega."""
    _ordered(window)
    if len({d for _, _, d in runs}) != len(runs) or len(runs) < 2:
        raise InputError("give two or more runs, each with its own grain diameter")
    big, small = grousered_wheel_scenario(), small_wheel_scenario()
    _check_twin_rpm(big.radius, small.radius)
    ratio = math.sqrt(small.radius / big.radius)  # twin time / reference time
    twin_window = (window[0] * ratio, window[1] * ratio)
    rows = sorted((state(p, lab, d, TWIN_RPM, small.radius, twin_window) for p, lab, d in runs), key=lambda r: r["d"])
    out = {"window": list(window), "twin_window": list(twin_window), "runs": rows, "steps": per_doubling(rows)}
    if reference is not None:
        out["reference"] = state(*reference, REFERENCE_RPM, big.radius, window)
    if fine:
        if fine_window is None:
            raise InputError("the fine-grid runs need their window (fine_window)")
        if len({d for _, _, d in fine}) != len(fine):
            raise InputError("give each fine-grid run its own grain diameter")
        out["fine_window"] = list(_ordered(fine_window))
        out["fine"] = sorted((state(p, lab, d, REFERENCE_RPM, big.radius, fine_window) for p, lab, d in fine),
                             key=lambda r: r["d"])  # fmt: skip
        out["fine_steps"] = per_doubling(out["fine"])
    if small_pair is not None:
        out["small_interpolated"] = interpolated([(p, lab, d, rpm, _ordered(w)) for p, lab, d, rpm, w in small_pair],
                                                 TWIN_RPM, small.radius)  # fmt: skip
    return out


def plot(result: dict, path: Path) -> None:
    fig, axes = plt.subplots(1, 2, figsize=(10, 4))
    rows, ref = result["runs"], result.get("reference")
    for ax, key, name in zip(axes, ("slip", "sinkage_over_r"), ("slip", "sinkage / r")):
        ax.plot([r["d_over_r"] for r in rows], [r[key] for r in rows], "s-", color="C3",
                label="half-size twins (small wheel, 2.5 mm cells)")  # fmt: skip
        if ref is not None:
            ax.plot(
                [ref["d_over_r"]],
                [ref[key]],
                "o",
                color="k",
                label="large wheel, 5 mm cells, 6 mm grains (the reference)",
            )
        if "fine" in result:
            fine = result["fine"]
            ax.plot([r["d_over_r"] for r in fine], [r[key] for r in fine], "o-", color="C0",
                    label="large wheel, 2.5 mm cells (h / r as the small wheel at 1.25 mm)")  # fmt: skip
        if "small_interpolated" in result:
            si = result["small_interpolated"]
            ax.plot([si["d_over_r"]], [si[key]], "D", mfc="none", color="C0", ms=8,
                    label=f"small wheel, 1.25 mm cells, interpolated to {si['rpm']:g} RPM")  # fmt: skip
        ax.set_xscale("log", base=2)
        ax.set(xlabel="grain length d / r", ylabel=name)
    handles, names = axes[0].get_legend_handles_labels()
    fig.legend(handles, names, fontsize=8, loc="lower center", ncol=2)
    w = result["window"]
    fine = (
        f"; 2.5 mm large wheels over {result['fine_window'][0]:g}-{result['fine_window'][1]:g} s"
        if "fine" in result
        else ""
    )
    fig.suptitle(f"MPM steady state against the grain length, same omega / omega_0 (reference's {w[0]:g}-{w[1]:g} s{fine})",
                 fontsize=10)  # fmt: skip
    fig.tight_layout(rect=(0.0, 0.07 if len(names) < 3 else 0.13, 1.0, 1.0))
    fig.savefig(path, dpi=120)
    plt.close(fig)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--run", nargs=3, action="append", required=True, metavar=("CSV", "LABEL", "D"))
    ap.add_argument("--reference", nargs=3, metavar=("CSV", "LABEL", "D"))
    ap.add_argument(
        "--window", nargs=2, type=float, required=True, metavar=("T0", "T1"), help="the reference's time, s"
    )
    ap.add_argument(
        "--fine",
        nargs=3,
        action="append",
        metavar=("CSV", "LABEL", "D"),
        help="a large wheel at 30 RPM on the finer grid (repeatable)",
    )
    ap.add_argument("--fine-window", nargs=2, type=float, metavar=("T0", "T1"), help="the fine runs' own time, s")
    ap.add_argument(
        "--small-pair",
        nargs=6,
        action="append",
        metavar=("CSV", "LABEL", "D", "RPM", "T0", "T1"),
        help="a small-wheel run on the finer grid (give two omegas)",
    )
    ap.add_argument("--out", required=True)
    args = ap.parse_args()
    runs = [(Path(p), lab, float(d)) for p, lab, d in args.run]
    reference = (
        None if args.reference is None else (Path(args.reference[0]), args.reference[1], float(args.reference[2]))
    )
    fine = None if args.fine is None else [(Path(p), lab, float(d)) for p, lab, d in args.fine]
    pair = (
        None
        if args.small_pair is None
        else [
            (Path(p), lab, float(d), float(rpm), (float(t0), float(t1))) for p, lab, d, rpm, t0, t1 in args.small_pair
        ]
    )
    try:
        result = analyse(runs, reference, tuple(args.window), fine, None if args.fine_window is None
                         else tuple(args.fine_window), pair)  # fmt: skip
    except InputError as e:
        raise SystemExit(str(e)) from None
    out = Path(args.out)
    out.parent.mkdir(parents=True, exist_ok=True)
    write_csv(out.with_suffix(".csv"), result["runs"])
    out.with_suffix(".json").write_text(json.dumps(result, indent=2) + "\n")
    plot(result, out.with_suffix(".png"))
    for r in result["runs"] + [result["reference"]] * ("reference" in result) + result.get("fine", []):
        print(f"{r['label']}: d / r {r['d_over_r']:.3f}, slip {r['slip']:.3f}, sinkage / r {r['sinkage_over_r']:.3f}, "
              f"{r['windows']} windows, drift {r['drift'] * 100:+.1f} %")  # fmt: skip
    if "small_interpolated" in result:
        si = result["small_interpolated"]
        print(
            f"{si['label']}: d / r {si['d_over_r']:.3f}, slip {si['slip']:.3f}, sinkage / r {si['sinkage_over_r']:.3f}"
        )
    for series, s in [("twins", s) for s in result["steps"]] + [("fine grid", s) for s in result.get("fine_steps", [])]:
        print(
            f"{series}, d {s['from_d'] * 1e3:g} -> {s['to_d'] * 1e3:g} mm: slip {s['slip_per_doubling']:+.3f}, "
            f"sinkage / r {s['sinkage_over_r_per_doubling']:+.3f} per doubling of d"
        )


if __name__ == "__main__":
    main()
