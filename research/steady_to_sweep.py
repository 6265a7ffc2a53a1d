"""Turn steady states of finished runs (``run_histories.py --steady-from``) into an MPM sweep CSV.

``intrusim calibrate --mpm`` and ``intrusim reproduce --mpm`` read sweep CSVs (one row per omega:
omega_rpm, ok, velocity, sinkage, slip, drift, settled, surface_drop). The long runs of
research/notes/results_log.md (the nonlocal-law wheels on the treadmill) are summarised per run in
``NAME_steady.csv`` files instead; this picks the rows whose label contains ``--label-contains``
from any number of them and writes one sweep CSV, sorted by omega:

    python research/steady_to_sweep.py research/outputs/wheel_30rpm_nonlocal_treadmill_steady.csv \
        research/outputs/wheel_90rpm_nonlocal_treadmill_steady.csv --label-contains "2.5 mm" \
        --cell-mm 2.5 --out research/outputs/mpm_nonlocal/grousered_wheel_mpm_sweep.csv

A row is marked settled when its velocity drift (change of v across the window, relative) is
below --settled-drift (default 0.05, the sweep's own criterion).
"""

from __future__ import annotations

import argparse
import csv
import math
from pathlib import Path

FIELDS = (
    "omega_rpm",
    "ok",
    "velocity",
    "sinkage",
    "slip",
    "velocity_std",
    "sinkage_std",
    "drift",
    "settled",
    "error",
    "cell_mm",
    "surface_drop",
    "window_start",
    "window_end",
)


def sweep_rows(paths: list[Path], label_contains: str, cell_mm: float, settled_drift: float) -> list[dict]:
    """Sweep-CSV rows (SI, omega in RPM) of the steady rows whose label contains ``label_contains``."""
    rows = []
    for path in paths:
        with path.open(newline="") as f:
            for r in csv.DictReader(f):
                if label_contains not in r["label"]:
                    continue
                drift = float(r["drift"])
                rows.append(
                    {
                        "omega_rpm": round(float(r["omega"]) * 30.0 / math.pi, 9),
                        "ok": True,
                        "velocity": float(r["velocity"]),
                        "sinkage": float(r["sinkage"]),
                        "slip": float(r["slip"]),
                        "velocity_std": "",
                        "sinkage_std": "",
                        "drift": drift,
                        "settled": abs(drift) < settled_drift,
                        "error": "",
                        "cell_mm": cell_mm,
                        "surface_drop": float(r["surface_drop"]),
                        "window_start": float(r["window_start"]),
                        "window_end": float(r["window_end"]),
                    }
                )
    omegas = [r["omega_rpm"] for r in rows]
    if len(set(omegas)) != len(omegas):
        raise SystemExit(f"two rows at one omega ({sorted(omegas)} RPM): narrow --label-contains")
    return sorted(rows, key=lambda r: r["omega_rpm"])


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("steady", nargs="+", type=Path, help="NAME_steady.csv files of run_histories.py")
    ap.add_argument("--label-contains", required=True, help="keep the rows whose label contains this text")
    ap.add_argument("--cell-mm", type=float, required=True, help="the runs' cell size, mm (a column of the sweep CSV)")
    ap.add_argument("--settled-drift", type=float, default=0.05)
    ap.add_argument("--out", type=Path, required=True)
    args = ap.parse_args()
    missing = [str(p) for p in args.steady if not p.is_file()]
    if missing:
        ap.error(f"not found: {', '.join(missing)}")
    rows = sweep_rows(args.steady, args.label_contains, args.cell_mm, args.settled_drift)
    if not rows:
        ap.error(f"no row's label contains {args.label_contains!r}")
    args.out.parent.mkdir(parents=True, exist_ok=True)
    with args.out.open("w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=FIELDS)
        w.writeheader()
        w.writerows(rows)
    print(f"wrote {args.out}: {len(rows)} omegas, {[r['omega_rpm'] for r in rows]} RPM")


if __name__ == "__main__":
    main()
