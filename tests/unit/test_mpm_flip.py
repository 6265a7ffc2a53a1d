"""TransferConfig.flip: FLIP's velocity update (v_p + sum w (v_i - v_old_i)) blended with APIC's."""

import numpy as np
import pytest
from pydantic import ValidationError

from intrusim.mpm.config import BackendConfig, BedConfig, DomainConfig, MaterialConfig, MPMConfig, Rectangle, TransferConfig
from intrusim.mpm.constitutive import material_from_config
from intrusim.mpm.solver import Solver
from intrusim.mpm.transfer import g2p_kernel, p2g_kernel


def _loose_patch(flip: float, gravity: float = 0.0, chunks: int = 16) -> Solver:
    """A patch below rho_c (stress-free) away from the walls, with a random velocity field (m/s)."""
    cfg = MPMConfig(domain=DomainConfig(size=(0.2, 0.2), cells=(20, 20)),
                    bed=BedConfig(rectangles=[Rectangle(x0=0.04, z0=0.04, x1=0.16, z1=0.12)], density_ratio=0.8),
                    gravity=(0.0, gravity), transfer=TransferConfig(flip=flip),
                    backend=BackendConfig(p2g_chunks=chunks))  # fmt: skip
    s = Solver(cfg)
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


def test_flip_runs_the_one_point_kernels_and_the_fixed_point_sums_agree():
    chunked, fixed = _loose_patch(1.0, -9.8), _loose_patch(1.0, -9.8, chunks=1)
    assert not chunked._lanes and chunked.grid.flip and fixed.grid.fixed_scale is not None
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


def test_the_vectorised_kernels_refuse_flip():
    with pytest.raises(ValueError, match="APIC only"):
        p2g_kernel(True, lanes=True, flip=True)
    material = material_from_config(MaterialConfig())
    with pytest.raises(ValueError, match="APIC only"):
        g2p_kernel(material.taichi_update, len(material.params), lanes=True, flip=True)
