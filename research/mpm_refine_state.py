"""Go on with a coupled MPM run at finer cells, from the state it reached: start-up or resolution?

A wheel run at 1.25 mm cells settles slower and deeper than at 2.5 mm (research/notes/results_log.md, "The
band-0 wheel after it settles"). Either the finer grains push differently on the wheel at the
same state, or the finer run started differently (the bulge it pushed up while sinking in) and
the memory of the start lasts. This script takes a finished run's last checkpoint, splits every
material point into factor^2 points (mass and volume shared out, velocity from the APIC affine
field v + C dx, stress and plastic strain kept), and goes on at cells `factor` times finer with
everything else unchanged, the wheel in the pose and motion it had. If the wheel then drifts
towards the finer run's state, the force law differs with the cells; if it stays, the start does.

    python research/mpm_refine_state.py runs/conv/grousered_wheel_30rpm_2.5mm_band0_1x0.4m_bed0.15m \
        --t-more 1.0 --threads 2 --out runs/refined      # ~25-30 min on 2 threads

The run folder (OUT/NAME_x2) resumes when the same command is given again, and is read by
`research/run_histories.py` like any other run folder (it holds locomotion.json and timeseries.csv;
its time axis goes on from the source run's).
"""

from __future__ import annotations

import argparse
import json
import shutil
from pathlib import Path

from intrusim.mpm import io as mpm_io
from intrusim.mpm.config import MPMConfig
from intrusim.mpm.particles import split_points
from intrusim.mpm.solver import CHECKPOINT, Solver
from intrusim.scenarios.mpm_locomotion import summarise_run


def refined_config(run: Path, factor: int, t_end: float, threads: int, out: Path) -> MPMConfig:
    payload = json.loads((run / "config.json").read_text())["config"]
    payload["domain"]["cells"] = [factor * c for c in payload["domain"]["cells"]]
    payload["time"]["t_end"] = t_end
    payload["output"]["directory"] = str(out)
    payload["backend"]["cpu_threads"] = threads
    return MPMConfig.model_validate(payload)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("run", type=Path, help="a coupled MPM run folder with checkpoint.npz")
    ap.add_argument("--factor", type=int, default=2, help="cells this many times finer in each direction")
    ap.add_argument("--t-more", type=float, default=1.0, help="s of physical time after the checkpoint")
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--out", type=Path, default=Path("runs/refined"))
    args = ap.parse_args()
    if args.factor < 2 or args.t_more <= 0:
        ap.error("--factor must be >= 2 and --t-more > 0")
    src = args.run / CHECKPOINT
    for need in (src, args.run / "locomotion.json"):
        if not need.exists():
            raise SystemExit(f"{args.run} has no {need.name}: not a finished or checkpointed locomotion run")
    out = args.out / f"{args.run.name}_x{args.factor}"
    own = out / CHECKPOINT
    if own.exists():  # resume: time origin as recorded (the source run may have gone on since)
        t0 = float(json.loads((out / "locomotion.json").read_text())["refined_from"]["t"])
        cfg = refined_config(args.run, args.factor, t0 + args.t_more, args.threads, out)
        arrays, meta = mpm_io.load_checkpoint(own)
        solver = Solver(cfg, particles=arrays)  # the split count, not a fresh bed's
        solver.restore(arrays, meta)
        print(f"resumed {out} at t = {solver.t:.3f} s", flush=True)
    else:
        arrays, meta = mpm_io.load_checkpoint(src)
        t0 = int(meta["step_count"]) * float(meta["dt"])
        cfg = refined_config(args.run, args.factor, t0 + args.t_more, args.threads, out)
        spacing = args.factor * cfg.domain.size[0] / cfg.domain.cells[0] / cfg.domain.particles_per_cell
        solver = Solver(cfg, particles=split_points(arrays, spacing, args.factor))
        solver.start_from(int(round(t0 / solver.dt)), meta["bodies"])
        out.mkdir(parents=True, exist_ok=True)
        info = json.loads((args.run / "locomotion.json").read_text())
        info["settings"]["cells"] = cfg.domain.cells
        info["refined_from"] = {"run": str(args.run), "t": t0, "factor": args.factor}
        (out / "locomotion.json").write_text(json.dumps(info, indent=1))
        print(f"{len(arrays['x'])} points -> {solver.particles.n}, dt {meta['dt']:.3g} -> {solver.dt:.3g} s, "
              f"from t = {t0:.3f} s", flush=True)  # fmt: skip

    def progress(s: Solver) -> None:
        r = s.rows[-1]
        if s.step_count % max(1, int(round(0.05 / s.dt))) < max(1, int(round(0.01 / s.dt))):
            print(
                f"t {r['time']:.2f} s  x {r['x']:.4f}  z {r['z']:.4f}  vx {r['vx']:.4f}  fz {r['fz']:.1f} N", flush=True
            )

    solver.run(progress=progress)
    st = summarise_run(out, t_start=t0 + 0.5 * args.t_more)
    print(json.dumps({"velocity": st.velocity, "sinkage": st.sinkage, "window": st.window}))
    shutil.copy(args.run / "config.json", out / "source_config.json")


if __name__ == "__main__":
    main()
