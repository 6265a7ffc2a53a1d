"""A DRFT omega sweep of the paper's four-flap runner (Fig 7B-C), with its plot.

    python examples/drft_sweep.py --omega-rpm 10,50,100,200,300 --out runs/runner_sweep

Each omega runs the driven body to its steady state (``intrusim.analysis.steady``) under RFT and
DRFT (lambda 4, the paper's runner value); OUT/sweep.csv and OUT/sweep.png are written.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from intrusim.analysis.sweep import sweep_omega  # noqa: E402
from intrusim.scenarios import four_flap_runner_scenario  # noqa: E402


def main(argv: list[str] | None = None) -> Path:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--omega-rpm", default="10,50,100,200,300", help="comma-separated RPM")
    ap.add_argument("--out", type=Path, default=Path("runs/runner_sweep"))
    ap.add_argument("--parallel", action="store_true", help="run the points on a local Dask cluster")
    args = ap.parse_args(argv)
    omegas = [float(w) for w in args.omega_rpm.split(",")]
    runner = four_flap_runner_scenario()
    args.out.mkdir(parents=True, exist_ok=True)
    fig, ax = plt.subplots(figsize=(5, 3.5), constrained_layout=True)
    for kind in ("rft", "drft"):
        res = sweep_omega(runner, kind, omegas, parallel=args.parallel, progress=False)
        print(kind, res.table(), sep="\n")
        res.to_csv(args.out / f"sweep_{kind}.csv")
        ax.plot(res.omega_rpm, res.column("velocity"), "o-", label=kind.upper())
    ax.set(xlabel="omega (RPM)", ylabel="forward speed (m/s)", title="four-flap runner")
    ax.legend()
    png = args.out / "sweep.png"
    fig.savefig(png, dpi=120)
    return png


if __name__ == "__main__":
    print(main())
