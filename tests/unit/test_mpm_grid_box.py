"""The grid update visits only the nodes P2G touched (this step or the last): nothing stale survives."""

import numpy as np

from intrusim.mpm.config import BedConfig, DomainConfig, MPMConfig, Rectangle
from intrusim.mpm.solver import Solver


def _stencil_nodes(x: np.ndarray, h: float, pad: int) -> set[tuple[int, int]]:
    base = np.floor(x / h + pad - 0.5).astype(int)
    return {(int(i + a), int(j + b)) for i, j in base for a in range(3) for b in range(3)}


def test_grid_mass_follows_the_points_after_a_jump():
    cfg = MPMConfig(
        domain=DomainConfig(size=(0.2, 0.2), cells=(20, 20)),
        bed=BedConfig(rectangles=[Rectangle(x0=0.02, z0=0.0, x1=0.08, z1=0.05)]),
    )
    s = Solver(cfg)
    s.step()
    d = s.particles.to_numpy()
    d["x"] = d["x"] + np.array([0.09, 0.1], dtype=d["x"].dtype)  # move the block 9 x 10 cells away
    d["v"][:] = 0.0
    d["C"][:] = 0.0
    s.particles.load(d)
    s.step()
    m = s.grid.m.to_numpy()
    nonzero = {tuple(ij) for ij in np.argwhere(m > 0)}
    assert nonzero, "the moved block left no mass on the grid"
    assert nonzero <= _stencil_nodes(d["x"].astype(float), s.h, s.grid.pad)  # old footprint cleared
    np.testing.assert_allclose(m.sum(), d["mass"].sum(), rtol=1e-5)
    v = s.grid.v.to_numpy()
    assert np.all(v[m == 0] == 0.0)


def test_walls_act_in_the_fused_grid_update():
    """Walls act inside the fused update: a block pressed on the floor keeps the floor's v_z >= 0."""
    cfg = MPMConfig(
        domain=DomainConfig(size=(0.2, 0.2), cells=(20, 20)),
        bed=BedConfig(rectangles=[Rectangle(x0=0.0, z0=0.0, x1=0.2, z1=0.1)]),
    )
    s = Solver(cfg)
    d = s.particles.to_numpy()
    d["v"][:, 1] = -0.5  # everything falls onto the floor
    s.particles.load(d)
    s.step()
    v = s.grid.v.to_numpy()
    floor = v[:, : s.grid.pad + 1]  # nodes at or below z = 0
    assert np.all(floor[..., 1] >= -1e-7)
    assert np.all(v[: s.grid.pad + 1, :, 0] >= -1e-7)  # nothing moves into the left wall
    assert np.all(v[-s.grid.pad - 1 :, :, 0] <= 1e-7)  # nor into the right wall


def test_atomic_and_chunked_particle_passes_agree():
    """P2G with atomics into one copy (the GPU path, p2g_chunks = 1) = the chunked CPU path."""
    out = []
    for chunks in (1, 16):
        cfg = MPMConfig(
            domain=DomainConfig(size=(0.2, 0.2), cells=(20, 20)),
            bed=BedConfig(rectangles=[Rectangle(x0=0.0, z0=0.0, x1=0.2, z1=0.1)]),
            backend=dict(p2g_chunks=chunks),
        )
        s = Solver(cfg)
        d = s.particles.to_numpy()
        rng = np.random.default_rng(3)
        d["v"] = rng.normal(0, 0.2, d["v"].shape).astype(d["v"].dtype)
        s.particles.load(d)
        for _ in range(5):
            s.step()
        out.append(s.particles.to_numpy())
    moved = np.abs(out[1]["x"] - d["x"]).max()
    assert moved > 1e-5  # the points did move
    np.testing.assert_allclose(out[0]["x"], out[1]["x"], atol=1e-4 * moved)
    np.testing.assert_allclose(out[0]["v"], out[1]["v"], atol=1e-4)
