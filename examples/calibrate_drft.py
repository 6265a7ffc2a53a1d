"""Fit DRFT's xi and psi to MPM steady states of the paper's wheel (the committed 2.5 mm runs).

    python examples/calibrate_drft.py
    python examples/calibrate_drft.py --mpm runs/mpm/grousered_wheel_mpm_sweep.csv   # your own runs

The reference is an MPM sweep CSV (``intrusim mpm sweep`` writes one); DRFT gets the MPM runs'
forward push and its xi (RFT scale) and psi (free-surface law slope) are fitted by bounded least
squares. The same is ``intrusim calibrate wheel --mpm CSV``.
"""

from __future__ import annotations

import argparse
from pathlib import Path

from intrusim.analysis.calibration import calibrate, load_reference, with_mpm_push
from intrusim.scenarios import grousered_wheel_scenario

ROOT = Path(__file__).resolve().parents[1]
MPM_RUNS = ROOT / "docs" / "figures" / "mpm_band0_settled" / "grousered_wheel_mpm_sweep.csv"


def main(argv: list[str] | None = None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--mpm", type=Path, default=MPM_RUNS, help="MPM sweep CSV of the Table S1 wheel")
    ap.add_argument("--params", default="xi,psi", help="parameters to fit: xi, psi, psi_offset, lam, bulldozing")
    ap.add_argument("--max-nfev", type=int, default=60, help="most parameter sets tried")
    args = ap.parse_args(argv)
    reference = load_reference(args.mpm, "grousered_wheel", settled_only=True)
    result = calibrate(
        with_mpm_push(grousered_wheel_scenario()), reference, args.params.split(","), max_nfev=args.max_nfev
    )
    print("fitted:", {k: round(v, 4) for k, v in result.values.items()})
    print(f"largest |relative error| over {len(reference.omega_rpm)} omegas: {result.max_abs_rel_error:.1%}")
    return result.summary()


if __name__ == "__main__":
    main()
