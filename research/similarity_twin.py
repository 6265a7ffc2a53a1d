"""Is the MPM size-similar when all its lengths scale together? A run against its half-size twin.

The twin is the Fig S1 small wheel (every length of the wheel halved, inertias and push x 1/8)
with every length of the MPM halved too: cell size, grain diameter, box, bed and treadmill, at
the same omega / omega_0 (omega_0 = sqrt(g / r)). Under Froude scaling time goes as sqrt(r / g),
speed as sqrt(g r) and sinkage as r, so slip and sinkage / r must agree window by window once the
twin's windows are the reference's scaled by sqrt(r_twin / r_reference) (0.3536 s for 0.5 s). This
script pairs the windows, compares them and gives the verdict registered in research/notes/results_log.md:

    python research/similarity_twin.py \\
        --reference research/outputs/wheel_30rpm_nonlocal_treadmill.csv "5 mm, treadmill in 1 m" 30 \\
        --twin research/outputs/small_wheel_42rpm_twin.csv "small wheel, 2.5 mm, 3 mm grains, half box" 42.4264 \\
        --window 3.5 4.5 --out research/outputs/similarity_twin

``--reference`` takes a run_histories.py window CSV of the Table S1 wheel, the run's label in it
and its omega (RPM); ``--twin`` the same for the small wheel (its CSV made with ``--every`` the
reference's window times sqrt(r_small / r_large)). ``--window`` is in the reference's time. Writes
OUT.csv (each pair of windows: both runs' slip and sinkage / r), OUT.json (the window means, the
differences and the verdict) and OUT.png (slip and sinkage / r against t / sqrt(r / g)).
``--similar`` and ``--not-similar`` take another registration's bands (slip, sinkage / r), as
the reading of the twins over the reference's 6.0-8.5 s: ``--similar 0.008 0.004
--not-similar 0.015 0.008``.
"""

from __future__ import annotations

import argparse
import json
import math
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from helpers.histories import read_windows, slip, wheel_state, window_mean  # noqa: E402

from intrusim._checks import InputError  # noqa: E402
from intrusim.mpm.io import write_csv  # noqa: E402
from intrusim.scenarios.locomotor import grousered_wheel_scenario, small_wheel_scenario  # noqa: E402

# registered over the reference's 3.5-4.5 s: similar if |d slip| <= 0.03 and
# |d sinkage / r| <= 0.015; not similar if either is off by more than 0.06 or 0.03; else in part
SIMILAR = (0.03, 0.015)
NOT_SIMILAR = (0.06, 0.03)


def check_bands(similar: tuple[float, float], not_similar: tuple[float, float]) -> None:
    """Refuse bands (slip, sinkage / r) that are not positive or not nested."""
    if not (0 < similar[0] <= not_similar[0] and 0 < similar[1] <= not_similar[1]):
        raise InputError(f"the bands must be positive and the similar ones within the not-similar ones, got "
                         f"similar {similar}, not similar {not_similar}")  # fmt: skip


def verdict(
    d_slip: float,
    d_sinkage_over_r: float,
    similar: tuple[float, float] = SIMILAR,
    not_similar: tuple[float, float] = NOT_SIMILAR,
) -> str:
    """The registered reading of the twin's difference from the reference (slip, sinkage / r):
    "similar" inside both ``similar`` bands, "not similar" past either ``not_similar`` band."""
    check_bands(similar, not_similar)
    if abs(d_slip) <= similar[0] and abs(d_sinkage_over_r) <= similar[1]:
        return "similar"
    if abs(d_slip) > not_similar[0] or abs(d_sinkage_over_r) > not_similar[1]:
        return "not similar"
    return "in part"


def pair_windows(reference: list[dict], twin: list[dict], time_ratio: float) -> list[tuple[dict, dict]]:
    """The reference's windows with the twin's of the same index, checked to be the reference's
    scaled by ``time_ratio`` (twin time / reference time) within 1 % of a window."""
    pairs = list(zip(reference, twin))
    for a, b in pairs:
        length = a["t_end"] - a["t_start"]
        if (
            abs(b["t_start"] / time_ratio - a["t_start"]) > 0.01 * length
            or abs(b["t_end"] / time_ratio - a["t_end"]) > 0.01 * length
        ):
            raise SystemExit(f"the twin's window {b['t_start']:g}-{b['t_end']:g} s is not the reference's "
                             f"{a['t_start']:g}-{a['t_end']:g} s scaled by {time_ratio:.6f}: make the twin's CSV with "
                             f"run_histories.py --every {length * time_ratio:.8f}")  # fmt: skip
    return pairs


def analyse(
    reference: tuple[Path, str, float],
    twin: tuple[Path, str, float],
    window: tuple[float, float],
    similar: tuple[float, float] = SIMILAR,
    not_similar: tuple[float, float] = NOT_SIMILAR,
) -> tuple[list[dict], dict]:
    """Every pair of windows and the comparison over ``window`` (the reference's time, s), read
    with the registered bands (slip, sinkage / r; default: an earlier study's)."""
    check_bands(similar, not_similar)  # before any file is read
    big, small = grousered_wheel_scenario(), small_wheel_scenario()
    r_ref, r_twin, g = big.radius, small.radius, big.gravity
    (p_ref, lab_ref, w_ref), (p_twin, lab_twin, w_twin) = reference, twin
    time_ratio = math.sqrt(r_twin / r_ref)
    if abs(w_twin * time_ratio / w_ref - 1.0) > 1e-4:
        raise SystemExit(f"the twin's {w_twin:g} RPM is not the reference's {w_ref:g} RPM at the same omega / omega_0 "
                         f"({w_ref / time_ratio:.4f} RPM)")  # fmt: skip
    pairs = pair_windows(read_windows(p_ref, lab_ref), read_windows(p_twin, lab_twin), time_ratio)
    t_ref = math.sqrt(r_ref / g)  # the time scale sqrt(r / g) of tau
    rows = [{"t_start": a["t_start"], "t_end": a["t_end"], "tau_start": a["t_start"] / t_ref, "tau_end": a["t_end"] / t_ref,
             "slip_reference": slip(a["velocity"], w_ref, r_ref), "slip_twin": slip(b["velocity"], w_twin, r_twin),
             "sinkage_over_r_reference": a["sinkage"] / r_ref, "sinkage_over_r_twin": b["sinkage"] / r_twin}
            for a, b in pairs]  # fmt: skip
    inside = [(a, b) for a, b in pairs if a["t_start"] >= window[0] - 1e-6 and a["t_end"] <= window[1] + 1e-6]
    if not inside:
        raise SystemExit(
            f"no pair of windows inside {window[0]}-{window[1]} s (the pairs end at {pairs[-1][0]['t_end']} s)"
        )
    means = {}
    for name, runs, w, r in (
        ("reference", [a for a, _ in inside], w_ref, r_ref),
        ("twin", [b for _, b in inside], w_twin, r_twin),
    ):
        m = wheel_state(window_mean(runs, runs[0]["t_start"], runs[-1]["t_end"]), w, r)
        means[name] = {**m, "omega_rpm": w, "radius": r, "window": [runs[0]["t_start"], runs[-1]["t_end"]]}
    ref, tw = means["reference"], means["twin"]
    diff = {"slip": tw["slip"] - ref["slip"], "sinkage_over_r": tw["sinkage_over_r"] - ref["sinkage_over_r"]}
    return rows, {
        "window": list(window),
        "time_ratio": time_ratio,
        "time_scale": t_ref,
        **means,
        "difference": diff,
        "registered": {"similar": list(similar), "not_similar": list(not_similar)},
        "verdict": verdict(diff["slip"], diff["sinkage_over_r"], similar, not_similar),
    }


def plot(rows: list[dict], result: dict, labels: tuple[str, str], path: Path) -> None:
    fig, axes = plt.subplots(1, 2, figsize=(10, 4))
    tau = [0.5 * (r["tau_start"] + r["tau_end"]) for r in rows]
    for ax, key, name in zip(axes, ("slip", "sinkage_over_r"), ("slip", "sinkage / r")):
        ax.plot(tau, [r[f"{key}_reference"] for r in rows], "o-", color="k", label=labels[0])
        ax.plot(tau, [r[f"{key}_twin"] for r in rows], "s--", color="C3", label=labels[1])
        ax.axvspan(*(t / result["time_scale"] for t in result["window"]), color="0.9", zorder=0)
        ax.set(xlabel="t / sqrt(r / g)", ylabel=name)
    handles, names = axes[0].get_legend_handles_labels()
    fig.legend(handles, names, fontsize=8, loc="lower center", ncol=2)  # below the axes: the labels are long
    fig.suptitle(f"Half-size twin at the same omega / omega_0: {result['verdict']} (shaded: the registered window)")
    fig.tight_layout(rect=(0.0, 0.07, 1.0, 1.0))
    fig.savefig(path, dpi=120)
    plt.close(fig)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--reference", nargs=3, required=True, metavar=("CSV", "LABEL", "RPM"))
    ap.add_argument("--twin", nargs=3, required=True, metavar=("CSV", "LABEL", "RPM"))
    ap.add_argument(
        "--window", nargs=2, type=float, required=True, metavar=("T0", "T1"), help="the reference's time, s"
    )
    ap.add_argument(
        "--similar",
        nargs=2,
        type=float,
        default=SIMILAR,
        metavar=("SLIP", "SINKAGE_OVER_R"),
        help="the registered bands within which the twin reads similar (default: the 0.03 0.015)",
    )
    ap.add_argument(
        "--not-similar",
        nargs=2,
        type=float,
        default=NOT_SIMILAR,
        metavar=("SLIP", "SINKAGE_OVER_R"),
        help="the registered bands past either of which it reads not similar (default: 0.06 0.03)",
    )
    ap.add_argument("--out", required=True)
    args = ap.parse_args()
    ref, twin = ((Path(p), lab, float(w)) for p, lab, w in (args.reference, args.twin))
    try:
        rows, result = analyse(ref, twin, tuple(args.window), tuple(args.similar), tuple(args.not_similar))
    except InputError as e:
        raise SystemExit(str(e)) from None
    out = Path(args.out)
    out.parent.mkdir(parents=True, exist_ok=True)
    write_csv(out.with_suffix(".csv"), rows)
    out.with_suffix(".json").write_text(json.dumps(result, indent=2) + "\n")
    plot(rows, result, (f"Table S1 wheel: {ref[1]}", f"half-size twin: {twin[1]}"), out.with_suffix(".png"))
    for name in ("reference", "twin"):
        m = result[name]
        print(f"{name} over {m['window'][0]:g}-{m['window'][1]:g} s: v {m['velocity']:.4f} m/s, sinkage {m['sinkage'] * 1e3:.2f} mm, "
              f"slip {m['slip']:.3f}, sinkage / r {m['sinkage_over_r']:.3f}, drift {m['drift'] * 100:+.1f} %")  # fmt: skip
    d = result["difference"]
    print(
        f"twin - reference: slip {d['slip']:+.3f}, sinkage / r {d['sinkage_over_r']:+.3f}: {result['verdict']} (registered thresholds)"
    )


if __name__ == "__main__":
    main()
