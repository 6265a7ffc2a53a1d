"""The moving window (Solver.shift_window): a treadmill under the bodies for long runs in a short box."""

import numpy as np
import pytest

from intrusim._checks import InputError
from intrusim.mpm.config import (
    BedConfig,
    CoupledMotion,
    DomainConfig,
    FluidityConfig,
    IntruderConfig,
    MaterialConfig,
    MPMConfig,
    ObstacleConfig,
    Rectangle,
)  # fmt: skip
from intrusim.mpm.solver import Solver

H = 0.01  # m, cell size of these scenes
SQUARE = [[-0.02, -0.02], [0.02, -0.02], [0.02, 0.02], [-0.02, 0.02]]


BED = [Rectangle(x0=0.0, z0=0.0, x1=0.3, z1=0.06)]
MOUND = Rectangle(x0=0.0, z0=0.06, x1=0.03, z1=0.08)  # on the left: a shift drops more points than it adds


def _cfg(rectangles=BED, **kw) -> MPMConfig:
    return MPMConfig(
        domain=DomainConfig(size=(0.3, 0.15), cells=(30, 15)),
        bed=BedConfig(rectangles=rectangles),
        intruders=[IntruderConfig(vertices=SQUARE, x=0.12, z=0.085, width=0.1,
                                  motion=CoupledMotion(omega=-1.0, mass_x=1.0, mass_z=1.0))],
        **kw,
    )  # fmt: skip


def _stepped(cfg: MPMConfig, steps: int = 30) -> Solver:
    s = Solver(cfg)
    for _ in range(steps):
        s.step()
    return s


def test_a_shift_moves_the_points_and_bodies_back_drops_the_left_strip_and_adds_fresh_bed():
    s = _stepped(_cfg())
    before = s.particles.to_numpy()
    body_x = s.intruders[0].state.x
    row_x = s.record()["x"]
    s.shift_window(3 * H)
    after = s.particles.to_numpy()
    kept = before["x"][:, 0] >= 3 * H
    n_kept = int(kept.sum())
    assert 0 < n_kept < len(before["x"])
    for name in before:  # the points that stay: moved back 3 cells, state untouched
        expect = before[name][kept].copy()
        if name == "x":
            expect[:, 0] -= 3 * H
        np.testing.assert_allclose(after[name][:n_kept], expect, rtol=0, atol=1e-6)
    fresh = {k: v[n_kept:] for k, v in after.items()}
    bed = Solver(_cfg()).particles.to_numpy()  # the configured bed in its geostatic state
    right = bed["x"][:, 0] > 0.3 - 3 * H
    assert len(fresh["x"]) == int(right.sum()) == 3 * 6 * 4  # 3 x 6 cells of 2 x 2 points
    for name in ("x", "mass", "vol", "sigma", "s_yy"):
        np.testing.assert_allclose(fresh[name], bed[name][right], rtol=1e-6, atol=1e-9)
    for name in ("v", "C", "eps_p", "gdot_p"):  # at rest, never sheared
        assert not np.any(fresh[name])
    assert s.intruders[0].state.x == pytest.approx(body_x - 3 * H)
    assert s.x_offset == pytest.approx(3 * H)
    assert s.record()["x"] == pytest.approx(row_x)  # the time series stays in the bed's frame
    s.step()  # and the step runs on the new points
    assert np.all(np.isfinite(s.particles.to_numpy(["v"])["v"]))


def test_the_fluidity_warm_start_moves_with_the_grains():
    s = _stepped(_cfg(material=MaterialConfig(fluidity=FluidityConfig(grain_diameter=6e-3))), steps=5)
    g = np.random.default_rng(1).random(s.fluidity.shape)
    s.fluidity.load(g)
    s.shift_window(2 * H)
    out = s.fluidity.to_numpy()
    np.testing.assert_allclose(out[:-2], g[2:], rtol=1e-6)
    assert not np.any(out[-2:])


def test_a_checkpoint_after_a_shift_restores_into_a_new_solver_and_goes_on_identically(tmp_path):
    s = _stepped(_cfg(BED + [MOUND]))
    s.shift_window(2 * H)
    s.save_checkpoint(tmp_path / "c.npz")
    other = Solver(_cfg(BED + [MOUND]))
    assert other.particles.n == s.particles.n + 2 * 2 * 4  # the mound's 2 x 2 cells left with the strip
    other.load_checkpoint(tmp_path / "c.npz")
    assert other.x_offset == pytest.approx(2 * H)
    for solver in (s, other):
        for _ in range(20):
            solver.step()
    a, b = s.particles.to_numpy(), other.particles.to_numpy()
    for name in a:
        np.testing.assert_array_equal(a[name], b[name], err_msg=name)
    assert other.record()["x"] == pytest.approx(s.record()["x"], abs=1e-12)


@pytest.mark.parametrize(
    "shift, match",
    [
        (0.0, "whole number of cells"),
        (0.015, "whole number of cells"),
        (-H, "whole number of cells"),
        (0.3, "shorter than the domain"),
    ],
)
def test_bad_shifts_are_refused_before_anything_moves(shift, match):
    s = Solver(_cfg())
    before = s.particles.to_numpy()
    with pytest.raises(InputError, match=match):
        s.shift_window(shift)
    np.testing.assert_array_equal(s.particles.to_numpy()["x"], before["x"])
    assert s.x_offset == 0.0


def test_a_scene_with_static_obstacles_is_refused():
    wall = [[0.25, 0.0], [0.26, 0.0], [0.26, 0.1], [0.25, 0.1]]
    s = Solver(_cfg(obstacles=[ObstacleConfig(vertices=wall)]))
    with pytest.raises(InputError, match="static obstacles"):
        s.shift_window(H)
