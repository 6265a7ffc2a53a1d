"""Velocity and sinkage against time of finished MPM locomotion runs, side by side.

For a question like "does the small wheel dig in at finer cells too?" (research/notes/results_log.md, Fig S1):
each run folder's time series is averaged over consecutive windows of --every seconds and
written to OUT.csv (one row per run and window: mean v, mean sinkage of the true outline) and
plotted in OUT.png (v and sinkage against time, one line per run).

    python research/run_histories.py \
        runs/small-fine/small_grousered_wheel_90rpm_2.5mm_band0_0.6x0.5m \
        runs/small-fine/small_grousered_wheel_90rpm_1.25mm_band0_0.6x0.5m \
        --label "2.5 mm" --label "1.25 mm" --out research/outputs/small_wheel_cells
"""

from __future__ import annotations

import argparse
import csv
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from intrusim.analysis.steady import whole_windows, window_means  # noqa: E402
from intrusim.scenarios.mpm_locomotion import summarise_run  # noqa: E402


def windows(run_dir: Path, every: float, whole_only: bool = False, until: float | None = None) -> list[dict]:
    """Mean v (m/s) and sinkage (m) over consecutive windows [t, t + every) of one run; the last
    one may be partial (it ends after the run's last record) unless ``whole_only``; with ``until``,
    only the windows that end by then."""
    series = summarise_run(run_dir, t_start=0.0).series
    rows = window_means(series["time"], {"velocity": series["vx"], "sinkage": series["sinkage"]}, every,
                        whole_only=whole_only)  # fmt: skip
    rows = rows if until is None else [r for r in rows if r["t_end"] <= until + 1e-9]
    if not whole_only and rows and rows[-1]["t_end"] > whole_windows(series["time"], every) * every + 1e-9:
        print(f"{run_dir.name}: the last window, {rows[-1]['t_start']:g}-{rows[-1]['t_end']:g} s, is partial (the run "
              f"ends at {series['time'][-1]:g} s); --whole-only leaves it out", file=sys.stderr)  # fmt: skip
    return rows


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("runs", nargs="+", type=Path, help="finished run folders (timeseries.csv, config.json)")
    ap.add_argument("--label", action="append", default=None, help="a legend label per run, in order")
    ap.add_argument("--every", type=float, default=0.125, help="window length, s")
    ap.add_argument(
        "--steady-from",
        type=float,
        action="append",
        default=None,
        metavar="T",
        help="per run, in order: also write OUT_steady.csv with the run's steady state from T s on "
        "(v, sinkage, slip, rear surface drop; summarise_run)",
    )
    ap.add_argument(
        "--whole-only",
        action="store_true",
        help="only windows the run covers whole (default: the last one may be partial, with a warning)",
    )
    ap.add_argument("--until", type=float, default=None, metavar="T", help="only the windows that end by T s")
    ap.add_argument("--title", default="")
    ap.add_argument("--out", required=True, help="output stem: OUT.csv and OUT.png")
    args = ap.parse_args()
    labels = args.label or [r.name for r in args.runs]
    if len(labels) != len(args.runs):
        ap.error(f"{len(labels)} labels for {len(args.runs)} runs")
    if args.every <= 0:
        ap.error("--every must be positive")
    if args.steady_from is not None and len(args.steady_from) != len(args.runs):
        ap.error(f"{len(args.steady_from)} --steady-from values for {len(args.runs)} runs")
    out = Path(args.out)
    out.parent.mkdir(parents=True, exist_ok=True)
    fig, (ax_v, ax_s) = plt.subplots(1, 2, figsize=(10, 4))
    with out.with_suffix(".csv").open("w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=["run", "label", "t_start", "t_end", "velocity", "sinkage"])
        w.writeheader()
        for run, label in zip(args.runs, labels):
            rows = windows(run, args.every, args.whole_only, args.until)
            for r in rows:
                w.writerow({"run": run.name, "label": label, **r})
            mid = [0.5 * (r["t_start"] + r["t_end"]) for r in rows]
            ax_v.plot(mid, [r["velocity"] for r in rows], "o-", ms=3, label=label)
            ax_s.plot(mid, [1e3 * r["sinkage"] for r in rows], "o-", ms=3, label=label)
    ax_v.set(xlabel="t (s)", ylabel=f"v (m/s), mean over {args.every:g} s")
    ax_s.set(xlabel="t (s)", ylabel="sinkage (mm)")
    ax_v.legend()
    fig.suptitle(args.title)
    fig.tight_layout()
    fig.savefig(out.with_suffix(".png"), dpi=120)
    print(f"wrote {out.with_suffix('.csv')} and {out.with_suffix('.png')}")
    if args.steady_from is not None:
        path = out.with_name(out.name + "_steady.csv")
        write_steady(path, args.runs, labels, args.steady_from)
        print(f"wrote {path}")


def write_steady(path: Path, runs: list[Path], labels: list[str], starts: list[float]) -> None:
    """One row per run: its steady state over [start, end] (m/s, m; rear drop from progress.json)."""
    keys = (
        "window_start",
        "window_end",
        "omega",
        "velocity",
        "sinkage",
        "slip",
        "surface_drop",
        "surface_drop_std",
        "drift",
    )
    with path.open("w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=["run", "label", *keys])
        w.writeheader()
        for run, label, t0 in zip(runs, labels, starts):
            summary = summarise_run(run, t_start=t0).summary()
            w.writerow({"run": run.name, "label": label, **{k: summary[k] for k in keys}})


if __name__ == "__main__":
    main()
