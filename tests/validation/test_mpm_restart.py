"""A run killed after a checkpoint resumes from it and reproduces the uninterrupted run.

P2G sums into per-chunk grid copies in a fixed order, so the particle state does not depend on
thread scheduling and is compared exactly. The contact impulse uses float64 atomic adds whose
order may vary with 2+ threads: forces are compared to 1e-9 relative.
"""

import numpy as np

from intrusim.mpm.plate import PlateDragCase
from intrusim.mpm.solver import Solver


def _config(tmp_path, name):
    case = PlateDragCase(depth=0.03, speed=0.3, travel=0.012, cells=(40, 20), domain=(0.2, 0.1),
                         bed_height=0.07)
    cfg = case.config(directory=str(tmp_path / name))
    cfg.output.record_every = cfg.time.t_end / 8
    cfg.output.checkpoint_every = cfg.time.t_end / 4
    return cfg


def test_restart_reproduces_uninterrupted_run(tmp_path):
    full = Solver(_config(tmp_path, "full"))
    full.run()
    ref = full.particle_fields()

    cfg = _config(tmp_path, "killed")
    killed = Solver(cfg)
    # "kill" the run a few steps after the second checkpoint (t_end/2): stop stepping there
    ckpt_steps = int(round(cfg.output.checkpoint_every / killed.dt))
    killed.run(t_end=(2 * ckpt_steps + 7) * killed.dt)
    del killed

    resumed = Solver.resume(tmp_path / "killed")
    assert resumed.step_count == 2 * ckpt_steps
    resumed.run()
    out = resumed.particle_fields()
    for key in ("x", "v", "sigma", "s_yy", "vol", "eps_p"):
        np.testing.assert_array_equal(out[key], ref[key], err_msg=key)
    assert len(resumed.rows) == len(full.rows)
    for a, b in zip(resumed.rows, full.rows):
        for k in a:
            np.testing.assert_allclose(a[k], b[k], rtol=1e-9, atol=1e-12, err_msg=k)
    assert (tmp_path / "killed" / "timeseries.csv").read_text().count("\n") == len(full.rows) + 1
