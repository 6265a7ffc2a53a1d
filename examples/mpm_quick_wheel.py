"""The paper's wheel in the MPM continuum solver, coarse and short (2 cm cells): a trend in seconds.

    python examples/mpm_quick_wheel.py --omega-rpm 30 --out runs/quick_wheel

Prints the steady window's speed, sinkage and slip and writes the run folder (time series, result
JSON). For converged numbers use the paper's settings (``paper_settings``, 5 mm cells; docs/mpm.md).
"""

from __future__ import annotations

import argparse
from pathlib import Path

from intrusim.scenarios import grousered_wheel_scenario
from intrusim.scenarios.mpm_locomotion import quick_settings, run_mpm_steady


def main(argv: list[str] | None = None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--omega-rpm", type=float, default=30.0)
    ap.add_argument("--t-max", type=float, default=1.2, help="simulated time, s")
    ap.add_argument("--threads", type=int, default=1, help="CPU threads")
    ap.add_argument("--out", type=Path, default=None, help="run folder (none: nothing written)")
    args = ap.parse_args(argv)
    settings = quick_settings("wheel").validated_copy(t_max=args.t_max, cpu_threads=args.threads)
    st = run_mpm_steady(grousered_wheel_scenario(), settings, args.omega_rpm, out_dir=args.out)
    print(
        f"omega {args.omega_rpm:g} RPM: v = {st.velocity * 1e3:.1f} mm/s, sinkage = {st.sinkage * 1e3:.1f} mm, "
        f"slip = {st.slip:.2f} (window {st.window[0]:.2f}-{st.window[1]:.2f} s, {st.steps} steps, {st.wall_time:.1f} s)"
    )
    return st.summary()


if __name__ == "__main__":
    main()
