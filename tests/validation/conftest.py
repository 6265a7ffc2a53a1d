"""Fixtures shared by the validation tests."""

import pytest

from intrusim.mpm.solver import Solver


@pytest.fixture
def run_killed_after_second_checkpoint():
    """A function that runs an MPMConfig and "kills" it between its second checkpoint (t_end/2) and
    its third: an exception out of the progress call at the next record stops it there, as a killed
    process would (a run that ends normally also checkpoints its end state). It returns the steps per
    checkpoint; the config must record at least twice per checkpoint interval."""

    def run(cfg) -> int:
        solver = Solver(cfg)
        ckpt_steps = int(round(cfg.output.checkpoint_every / solver.dt))

        def kill(s):
            if s.step_count > 2 * ckpt_steps:
                raise KeyboardInterrupt

        with pytest.raises(KeyboardInterrupt):
            solver.run(progress=kill)
        assert 2 * ckpt_steps < solver.step_count < 3 * ckpt_steps
        return ckpt_steps

    return run
