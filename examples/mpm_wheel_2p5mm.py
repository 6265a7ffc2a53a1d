"""Convergence check of docs/mpm.md: the Table S1 wheel with 2.5 mm cells, 2 s, 2 threads.

    python examples/mpm_wheel_2p5mm.py 30      # ~25 min on 2 cores; writes runs/mpm-2p5/
"""
import json
import sys

from intrusim.scenarios import grousered_wheel_scenario
from intrusim.scenarios.mpm_locomotion import paper_settings, run_mpm_steady, write_result

rpm = float(sys.argv[1]) if len(sys.argv) > 1 else 30.0
settings = paper_settings("wheel").model_copy(update=dict(cells=(400, 400), t_max=2.0, cpu_threads=2))
out = f"runs/mpm-2p5/grousered_wheel_{rpm:g}rpm"
st = run_mpm_steady(grousered_wheel_scenario(), settings, rpm, out,
                    lambda d: print(json.dumps({k: round(v, 4) for k, v in d.items()}), flush=True))
write_result(out, st)
print(st.summary())
