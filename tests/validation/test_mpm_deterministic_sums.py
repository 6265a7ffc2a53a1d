"""Atomic sums in 64-bit fixed point (``backend.deterministic_sums``): reproducible runs without
private grid copies.

A GPU sums P2G, the body impulses and the fluidity sources with atomic adds into one target. Float
atomic adds round at each addition in whatever order the threads take, so two runs of the same
state drift apart at round-off (measured on an H200: one float32 ulp of position within a few
hundred steps, docs/performance.md), and a restarted run cannot reproduce the uninterrupted one.
Integer adds are exact in any order. The CPU runs the same kernels with ``p2g_chunks = 1`` (one
grid copy, atomic adds on 2 threads), which is how these tests check them without a GPU.
"""

import numpy as np
import pytest
import taichi as ti

from intrusim.mpm.exact_sums import FIXED_POINT_HEADROOM, fixed_point_scale
from intrusim.mpm.plate import PlateDragCase
from intrusim.mpm.solver import Solver
from intrusim.mpm.step_graph import run_direct
from intrusim.scenarios import grousered_wheel_scenario
from intrusim.scenarios.mpm_locomotion import mpm_config, quick_settings


def _wheel(p2g_chunks: int, deterministic: bool = True, steps: int = 1500) -> Solver:
    """The coarse wheel at 60 RPM (2,500 points), ``steps`` steps into its spin-up and sinking."""
    cfg = mpm_config(grousered_wheel_scenario(), quick_settings("wheel"), 60.0, None)
    cfg.contact = "band"  # the bound below was measured with the band contact
    cfg.backend.p2g_chunks = p2g_chunks
    cfg.backend.deterministic_sums = deterministic
    solver = Solver(cfg)
    for _ in range(steps):
        solver.step()
    return solver


def _state(solver: Solver) -> np.ndarray:
    st = solver.intruders[0].state
    p = solver.particles.to_numpy(["x", "v", "sigma"])
    return np.concatenate(
        [
            p["x"].ravel(),
            p["v"].ravel(),
            p["sigma"].ravel(),
            solver.intruders[0].contact.read_impulse(),
            [st.x, st.z, st.vx, st.vz],
        ]
    )


@pytest.fixture(scope="module")
def fixed_runs():
    return _wheel(1), _wheel(1)


def test_atomic_sums_in_fixed_point_repeat_bit_for_bit(fixed_runs):
    a, b = fixed_runs
    assert a.fixed_scale is not None and a.grid.mp_parts.dtype == ti.i64
    assert a.intruders[0].contact.step_sums is not None
    np.testing.assert_array_equal(_state(a), _state(b))
    assert a.intruders[0].state.x > 0.17  # the wheel has rolled: the sums were not trivially empty


def test_fixed_point_sums_agree_with_the_chunked_fixed_order_sums(fixed_runs):
    a = fixed_runs[0]
    chunked = _wheel(16)
    assert chunked.fixed_scale is None
    xa = a.particles.to_numpy(["x"])["x"]
    xc = chunked.particles.to_numpy(["x"])["x"]
    # m, after 1500 steps (measured 4.3e-7, 6e-6 with the vectorised G2P, 2.9e-6 with the particle blocks)
    assert np.max(np.abs(xa - xc)) < 1e-5
    sa, sc = a.intruders[0].state, chunked.intruders[0].state
    # the law is discontinuous at rho_c (stress-free below): with the vectorised G2P a point's density
    # reaches rho_c one step apart in the two runs (step 1056, rounding), 200 Pa in its stress, which moves
    # the wheel by 5.4e-7 m and 1.5e-5 m/s by step 1500 (with the particle blocks 5.1e-7 m and 1.5e-5 m/s;
    # before it, 1e-9 m); the sums themselves: below
    assert abs(sa.z - sc.z) < 1e-6 and abs(sa.vx - sc.vx) < 5e-5


def test_one_p2g_in_fixed_point_is_the_chunked_sum_to_rounding(fixed_runs):
    # the same state (the fixed-point run's after 1500 steps) scattered both ways, once: the node masses
    # and momenta of the one exact sum and of the 16 float copies added up agree to float32 rounding
    state = fixed_runs[0].particles.to_numpy()
    sums = []
    for chunks in (1, 16):
        s = _wheel(chunks, steps=0)
        s.particles.load(state)
        active = tuple(o.removal_time is None for o in s.cfg.obstacles)
        run_direct(s._launches(active)[:1], {})  # P2G alone
        parts = s.grid.mp_parts.to_numpy().astype(np.float64).reshape(s.grid.chunks, *s.grid.shape, -1)[..., :3]
        sums.append(parts.sum(axis=0) * s.grid.inv_scale)
    fixed, chunked = sums
    for k, name in enumerate(("momentum x", "momentum z", "mass")):
        scale = np.abs(fixed[..., k]).max()
        assert scale > 0
        np.testing.assert_allclose(chunked[..., k], fixed[..., k], rtol=0, atol=1e-6 * scale, err_msg=name)


def test_float_atomic_sums_are_still_there_when_asked_for():
    s = _wheel(1, deterministic=False, steps=2)
    assert s.fixed_scale is None and s.intruders[0].contact.step_sums is None
    assert s.grid.mp_parts.dtype == ti.f32


def test_a_restart_with_fixed_point_atomic_sums_reproduces_the_uninterrupted_run(
    tmp_path, run_killed_after_second_checkpoint
):
    def config(name):
        case = PlateDragCase(depth=0.03, speed=0.3, travel=0.012, cells=(40, 20), domain=(0.2, 0.1), bed_height=0.07)
        cfg = case.config(directory=str(tmp_path / name))
        cfg.backend.p2g_chunks = 1  # one grid copy, atomic adds, as on a GPU
        cfg.output.record_every = cfg.time.t_end / 8
        cfg.output.checkpoint_every = cfg.time.t_end / 4
        return cfg

    full = Solver(config("full"))
    assert full.fixed_scale is not None
    full.run()
    ckpt_steps = run_killed_after_second_checkpoint(config("killed"))
    resumed = Solver.resume(tmp_path / "killed")
    assert resumed.step_count == 2 * ckpt_steps
    resumed.run()
    ref, out = full.particle_fields(), resumed.particle_fields()
    for key in ("x", "v", "sigma", "s_yy", "vol", "eps_p"):
        np.testing.assert_array_equal(out[key], ref[key], err_msg=key)
    assert len(resumed.rows) == len(full.rows)
    diagnostics = ("kinetic_energy", "grain_mass")  # float reductions over the points, reported only
    for a, b in zip(resumed.rows, full.rows):  # the body's state and forces too: the impulse sums are exact
        assert {k: v for k, v in a.items() if k not in diagnostics} == {
            k: v for k, v in b.items() if k not in diagnostics
        }
        for k in diagnostics:
            assert a[k] == pytest.approx(b[k], rel=1e-12)


def test_the_fixed_point_scale_is_a_power_of_two_that_leaves_the_headroom():
    for ref in (1e-9, 6.4e-4, 0.016, 1.0, 2500.0):
        scale = fixed_point_scale(ref)
        k = np.log2(scale)
        assert k == np.round(k)
        assert FIXED_POINT_HEADROOM * ref * scale <= 2.0**62 < 2 * FIXED_POINT_HEADROOM * ref * scale
        assert 1.0 / (scale * ref) < 1e-12  # each term exact to better than 1e-12 of the reference
    for bad in (0.0, -1.0, float("nan"), float("inf")):
        with pytest.raises(ValueError, match="positive number"):
            fixed_point_scale(bad)
