"""Convergence check of docs/mpm.md: the Table S1 wheel (or the half-size wheel of Fig S1) with
2.5 mm cells, 2 s of physical time.

    python examples/mpm_wheel_2p5mm.py 30                     # ~20-25 min on 2 cores; runs/mpm-2p5/
    python examples/mpm_wheel_2p5mm.py 90 --small --threads 1 # the small wheel, one thread
"""
import argparse
import json

from intrusim.scenarios import grousered_wheel_scenario, small_wheel_scenario
from intrusim.scenarios.mpm_locomotion import paper_settings, run_mpm_steady, write_result

ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
ap.add_argument("rpm", type=float, nargs="?", default=30.0)
ap.add_argument("--small", action="store_true", help="the half-size wheel of Fig S1")
ap.add_argument("--threads", type=int, default=2, help="Taichi CPU threads")
ap.add_argument("--t-max", type=float, default=2.0, help="physical time to run (s)")
args = ap.parse_args()
scenario = small_wheel_scenario() if args.small else grousered_wheel_scenario()
settings = paper_settings("wheel").model_copy(update=dict(cells=(400, 400), t_max=args.t_max, cpu_threads=args.threads))
name = "small_grousered_wheel" if args.small else "grousered_wheel"
out = f"runs/mpm-2p5/{name}_{args.rpm:g}rpm"
st = run_mpm_steady(scenario, settings, args.rpm, out,
                    lambda d: print(json.dumps({k: round(v, 4) for k, v in d.items()}), flush=True))
write_result(out, st)
print(st.summary())
