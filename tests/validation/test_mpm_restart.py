"""A run killed after a checkpoint resumes from it and reproduces the uninterrupted run.

P2G sums into per-chunk grid copies in a fixed order, so the particle state does not depend on
thread scheduling and is compared exactly. The contact impulse uses float64 atomic adds whose
order may vary with 2+ threads: forces are compared to 1e-9 relative.
"""

import numpy as np
import pytest

from intrusim.mpm.plate import PlateDragCase
from intrusim.mpm.solver import Solver


def _config(tmp_path, name):
    case = PlateDragCase(
        depth=0.03, speed=0.3, travel=0.012, cells=(40, 20), domain=(0.2, 0.1), bed_height=0.07, contact="band"
    )  # the force from the nodes ahead: the band contact
    cfg = case.config(directory=str(tmp_path / name))
    cfg.output.record_every = cfg.time.t_end / 8
    cfg.output.checkpoint_every = cfg.time.t_end / 4
    return cfg


def test_restart_reproduces_uninterrupted_run(tmp_path, run_killed_after_second_checkpoint):
    full = Solver(_config(tmp_path, "full"))
    full.run()
    ref = full.particle_fields()

    ckpt_steps = run_killed_after_second_checkpoint(_config(tmp_path, "killed"))

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


def test_drag_force_on_a_plate_comes_from_the_nodes_ahead_of_it(tmp_path):
    # the grid contact books each node's impulse ahead of / behind the body's reference point: a
    # plate dragged through the bed is resisted on its front face, its trailing face separates
    run = Solver(_config(tmp_path, "split"))
    run.run()
    rows = run.rows[1:]
    fx, ahead = np.array([r["fx"] for r in rows]), np.array([r["fx_ahead"] for r in rows])
    assert np.all(fx < -10.0) and np.all(ahead / fx > 0.95)
    total, ahead = run.intruders[0].contact.read_impulse(), run.intruders[0].contact.read_impulse_ahead()
    assert total[0] < 0.0 and abs(total[0] - ahead[0]) < 0.05 * abs(total[0])


def test_checkpoint_from_before_the_front_rear_split_resumes(tmp_path, run_killed_after_second_checkpoint):
    # a checkpoint that holds the total impulse only, no part from ahead and no ahead mark: the
    # resumed run gives the same totals as the uninterrupted one, and from the first row after it the same split
    from intrusim.mpm import io as mpm_io

    full = Solver(_config(tmp_path, "full"))
    full.run()
    run_killed_after_second_checkpoint(_config(tmp_path, "old"))
    path = tmp_path / "old" / "checkpoint.npz"
    arrays, meta = mpm_io.load_checkpoint(path)
    del meta["impulse_ahead"], meta["impulse_mark_ahead"]
    for row in meta["rows"]:
        for key in ("fx_ahead", "fz_ahead", "moment_ahead"):
            row.pop(key)
    mpm_io.save_checkpoint(path, arrays, meta)

    resumed = Solver.resume(tmp_path / "old")
    resumed.run()
    n_old = len(meta["rows"])
    assert len(resumed.rows) == len(full.rows)
    for a, b in zip(resumed.rows, full.rows):
        for k in ("fx", "fz", "moment"):
            np.testing.assert_allclose(a[k], b[k], rtol=1e-9, atol=1e-12, err_msg=k)
    for a, b in zip(resumed.rows[n_old:], full.rows[n_old:]):
        for k in ("fx_ahead", "fz_ahead", "moment_ahead"):
            np.testing.assert_allclose(a[k], b[k], rtol=1e-9, atol=1e-12, err_msg=k)
    header, first = (tmp_path / "old" / "timeseries.csv").read_text().splitlines()[:2]
    assert header.split(",").count("fx_ahead_N") == 1 and first.split(",")[header.split(",").index("fx_ahead_N")] == ""


def test_a_state_carried_on_by_another_solver_keeps_its_clock_and_bodies(tmp_path):
    # Solver.restore (a checkpoint already read) equals load_checkpoint; Solver.start_from sets the
    # clock, the bodies and the start of the force averages for a state carried over from another run
    from intrusim.mpm import io as mpm_io

    cfg = _config(tmp_path, "src")
    src = Solver(cfg)
    src.run(t_end=0.5 * cfg.time.t_end)
    src.checkpoint_run_folder()
    arrays, meta = mpm_io.load_checkpoint(tmp_path / "src" / "checkpoint.npz")
    a, b = Solver(_config(tmp_path, "a")), Solver(_config(tmp_path, "b"))
    a.load_checkpoint(tmp_path / "src" / "checkpoint.npz")
    b.restore(arrays, meta)
    for key in ("x", "v", "sigma"):
        np.testing.assert_array_equal(a.particle_fields()[key], b.particle_fields()[key])
    assert a.step_count == b.step_count == src.step_count and a.rows == b.rows

    c = Solver(_config(tmp_path, "c"), particles=arrays)
    c.start_from(src.step_count, meta["bodies"])
    assert c.step_count == src.step_count and c.t == src.t
    assert c.intruders[0].state.as_dict() == src.intruders[0].state.as_dict()
    c.run(t_end=c.t + 3 * c.dt)
    assert c.step_count == src.step_count + 3
    with pytest.raises(ValueError, match="body states"):
        c.start_from(0, [])


def test_a_run_keeps_its_end_state_and_an_extension_goes_on_from_it(tmp_path):
    """A run that ends between two scheduled checkpoints checkpoints its end state; a longer run
    resumed from its folder starts there and matches one run to the longer time."""
    cfg = _config(tmp_path, "short")
    short = Solver(cfg)
    ckpt_steps = int(round(cfg.output.checkpoint_every / short.dt))
    n_short = 2 * ckpt_steps + 7  # not on the checkpoint schedule
    short.run(t_end=n_short * short.dt)
    resumed = Solver.resume(tmp_path / "short")
    assert resumed.step_count == n_short
    resumed.run()

    full = Solver(_config(tmp_path, "full"))
    full.run()
    got, want = resumed.particle_fields(), full.particle_fields()
    for key in ("x", "v", "sigma", "s_yy", "vol", "eps_p"):
        np.testing.assert_array_equal(got[key], want[key], err_msg=key)
