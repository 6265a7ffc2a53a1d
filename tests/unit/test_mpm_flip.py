"""TransferConfig.flip: FLIP's velocity update (v_p + sum w (v_i - v_old_i)) blended with APIC's."""

import numpy as np
import pytest
from pydantic import ValidationError

from intrusim.mpm.backend import BenchmarkSwitches
from intrusim.mpm.config import BackendConfig, BedConfig, DomainConfig, MPMConfig, Rectangle, TransferConfig
from intrusim.mpm.solver import Solver
from intrusim.mpm.transfer import p2g_kernel


def _loose_patch(flip: float | None, gravity: float = 0.0, chunks: int = 16, lanes: bool = True) -> Solver:
    """A patch below rho_c (stress-free) away from the walls, with a random velocity field (m/s)."""
    cfg = MPMConfig(domain=DomainConfig(size=(0.2, 0.2), cells=(20, 20)),
                    bed=BedConfig(rectangles=[Rectangle(x0=0.04, z0=0.04, x1=0.16, z1=0.12)], density_ratio=0.8),
                    gravity=(0.0, gravity), transfer=TransferConfig(flip=flip),
                    backend=BackendConfig(p2g_chunks=chunks))  # fmt: skip
    s = Solver(cfg, switches=BenchmarkSwitches(simd_lanes=lanes))
    v0 = np.random.default_rng(3).normal(0.0, 0.01, (s.particles.n, 2))
    s.particles.load({"v": v0})
    return s


def _v_after_one_step(s: Solver) -> np.ndarray:
    s.step()
    return s.particles.to_numpy(["v"])["v"]


def test_flip_keeps_a_free_points_velocity_where_apic_replaces_it():
    """No force acts: FLIP's increment is zero, so each point keeps its own velocity; APIC gives it
    the grid's, which smooths a field that varies from point to point."""
    v0 = _loose_patch(1.0).particles.to_numpy(["v"])["v"]
    v_flip = _v_after_one_step(_loose_patch(1.0))
    v_apic = _v_after_one_step(_loose_patch(0.0))
    assert np.max(np.abs(v_flip - v0)) < 1e-6 * np.max(np.abs(v0))
    assert np.max(np.abs(v_apic - v0)) > 0.3 * np.std(v0)


def test_flip_adds_gravity_and_the_blend_is_linear_in_the_share():
    dt = _loose_patch(1.0, -9.8).dt
    v0 = _loose_patch(1.0, -9.8).particles.to_numpy(["v"])["v"]
    v1 = _v_after_one_step(_loose_patch(1.0, -9.8))
    assert np.allclose(v1, v0 + dt * np.array([0.0, -9.8]), rtol=0, atol=1e-6 * np.max(np.abs(v0)))
    v_half = _v_after_one_step(_loose_patch(0.5, -9.8))
    v_apic = _v_after_one_step(_loose_patch(0.0, -9.8))
    assert np.allclose(v_half, 0.5 * (v1 + v_apic), rtol=0, atol=1e-6 * np.max(np.abs(v0)))


def test_flip_runs_the_vectorised_kernels_and_the_fixed_point_sums_agree():
    chunked, fixed = _loose_patch(1.0, -9.8), _loose_patch(1.0, -9.8, chunks=1)
    assert chunked._lanes and chunked.grid.flip and fixed.grid.fixed_scale is not None
    for _ in range(20):
        chunked.step()
        fixed.step()
    a, b = chunked.particles.to_numpy(["x", "v"]), fixed.particles.to_numpy(["x", "v"])
    assert np.all(np.isfinite(a["v"]))
    assert np.allclose(a["v"], b["v"], rtol=0, atol=1e-5 * np.max(np.abs(a["v"])))
    assert np.allclose(a["x"], b["x"], rtol=0, atol=1e-7)


@pytest.mark.parametrize("flip", [-0.1, 1.5])
def test_a_flip_share_outside_0_1_is_refused(flip):
    with pytest.raises(ValidationError, match="flip"):
        TransferConfig(flip=flip)


@pytest.mark.parametrize("flip", [1.0, 0.5, None])
def test_the_vectorised_flip_gives_the_one_point_kernels_numbers(flip):
    """The vectorised P2G and G2P with FLIP's second momentum sum and gather (the default path) give
    the one-point kernels' velocities and positions after 20 steps of a falling patch."""
    lanes, point = _loose_patch(flip, -9.8), _loose_patch(flip, -9.8, lanes=False)
    assert lanes._lanes and not point._lanes and lanes.grid.flip
    for _ in range(20):
        lanes.step()
        point.step()
    a, b = lanes.particles.to_numpy(["x", "v"]), point.particles.to_numpy(["x", "v"])
    assert np.allclose(a["v"], b["v"], rtol=0, atol=1e-5 * np.max(np.abs(a["v"])))
    assert np.allclose(a["x"], b["x"], rtol=0, atol=1e-7)


def test_the_default_share_falls_with_dt_at_a_fixed_damping_rate():
    """flip = None: the share is exp(-dt / tau), tau = pic_time h sqrt(rho_c / E), so the PIC part's
    relaxation over a second does not depend on dt (two half steps give the share of one step)."""
    s = _loose_patch(None)
    mat = s.cfg.material
    tau = s.cfg.transfer.pic_time * s.h * np.sqrt(mat.rho_c / mat.youngs_modulus)
    assert s.flip == pytest.approx(np.exp(-s.dt / tau), rel=1e-12)
    half = Solver(s.cfg.model_copy(update={"time": s.cfg.time.model_copy(update={"dt": s.dt / 2})}))
    assert half.flip**2 == pytest.approx(s.flip, rel=1e-12)
    assert 0.9 < s.flip < 1.0


def test_a_vectorised_p2g_is_the_chunked_one():
    with pytest.raises(ValueError, match="chunked"):
        p2g_kernel(False, lanes=True, flip=True)
