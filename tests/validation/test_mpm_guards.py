"""Guards stop the run with a diagnosis and a failure checkpoint (or, if asked, drop an escaped point)."""

import numpy as np
import pytest

from intrusim.mpm.config import BedConfig, DomainConfig, MPMConfig, OutputConfig, Rectangle, TimeConfig
from intrusim.mpm.diagnostics import SimulationError
from intrusim.mpm.solver import Solver


def _solver(tmp_path, p2g_chunks: int = 16, escaped: str = "stop"):
    cfg = MPMConfig(
        domain=DomainConfig(size=(0.1, 0.1), cells=(10, 10)),
        bed=BedConfig(rectangles=[Rectangle(x0=0, z0=0, x1=0.1, z1=0.05)]),
        time=TimeConfig(t_end=0.01),
        output=OutputConfig(directory=str(tmp_path), guard_every_steps=1, escaped=escaped),
        backend=dict(p2g_chunks=p2g_chunks),
    )
    return Solver(cfg)


def test_nan_is_reported_with_place_and_time(tmp_path):
    s = _solver(tmp_path)
    d = s.particles.to_numpy(["v"])
    d["v"][5] = np.nan
    s.particles.load(d)
    with pytest.raises(SimulationError, match=r"NaN.*point.*t=.*step 1"):
        s.run()
    assert (tmp_path / "checkpoint_failure.npz").exists()


@pytest.mark.parametrize("p2g_chunks", [16, 1])  # chunked float sums; one copy, fixed-point atomic sums (a GPU's)
@pytest.mark.parametrize("field", ["v", "C", "sigma"])
def test_a_nan_is_reported_at_the_point_that_carries_it(tmp_path, field, p2g_chunks):
    # integer sums carry no NaN: with fixed-point P2G the point itself is marked, so the guard names
    # it rather than the escape of its neighbours that garbage sums would cause
    s = _solver(tmp_path, p2g_chunks)
    assert (s.fixed_scale is not None) == (p2g_chunks == 1)
    d = s.particles.to_numpy([field])
    d[field][5] = np.nan
    s.particles.load(d)
    # float sums spread the NaN over the grid to the neighbours (any of them is named); integer sums
    # cannot, and the point itself is the one named
    where = r"1 points, e\.g\. point 5 " if p2g_chunks == 1 else r"\d+ points, e\.g\. point \d+ "
    with pytest.raises(SimulationError, match=r"NaN/inf in particle state: " + where + r".*step 1"):
        s.run()


def test_cfl_breach_is_reported(tmp_path):
    s = _solver(tmp_path)
    d = s.particles.to_numpy(["v"])
    d["v"][:, 1] = 0.9 * s.h / s.dt  # far above max_cell_fraction * h / dt
    s.particles.load(d)
    with pytest.raises(SimulationError, match="CFL breach|escape"):
        s.run()


def test_escape_is_reported(tmp_path):
    s = _solver(tmp_path)
    d = s.particles.to_numpy(["x"])
    d["x"][3] = (0.05, 0.5)  # above the open top
    s.particles.load(d)
    with pytest.raises(SimulationError, match="escape.*point 3"):
        s.run()


def test_an_escaped_point_can_be_dropped_instead(tmp_path, capsys):
    """output.escaped = "drop": the point leaves the run (its mass counted in ``dropped``), the rest goes on,
    and a checkpoint keeps the count."""
    s = _solver(tmp_path, escaped="drop")
    d = s.particles.to_numpy(["x", "mass"])
    n0, m3 = s.particles.n, float(d["mass"][3])
    d["x"][3] = (0.05, 0.5)  # above the open top
    s.particles.load({"x": d["x"]})
    s.run()
    assert s.particles.n == n0 - 1
    assert s.dropped == {"points": 1, "mass": pytest.approx(m3)}
    assert "1 escaped point(s) dropped" in capsys.readouterr().err
    s.save_checkpoint(tmp_path / "c.npz")
    again = _solver(tmp_path / "again", escaped="drop")
    again.load_checkpoint(tmp_path / "c.npz")
    assert again.dropped == s.dropped and again.particles.n == n0 - 1


def test_a_run_stopped_by_an_escape_goes_on_from_its_folder_with_drop(tmp_path):
    """The folder of a "stop" run is taken by a "drop" run (the history up to its checkpoint dropped no
    point), and not the other way round."""
    from intrusim._checks import InputError
    from intrusim.mpm.io import refuse_other_run

    stop = _solver(tmp_path)
    stop.run()  # writes config.json
    assert refuse_other_run(tmp_path, _solver(tmp_path, escaped="drop").cfg) is False  # same run, not longer
    drop_dir = tmp_path / "drop"
    _solver(drop_dir, escaped="drop").run()
    with pytest.raises(InputError, match="differs in output.escaped"):
        refuse_other_run(drop_dir, _solver(drop_dir).cfg)
