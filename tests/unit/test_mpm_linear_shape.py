"""TransferConfig.shape = "linear": the cell's bilinear shape functions in P2G and G2P (mpm-2d's)."""

import numpy as np
import pytest
from pydantic import ValidationError

from intrusim.mpm.config import (
    BackendConfig,
    BedConfig,
    DomainConfig,
    MaterialConfig,
    MPMConfig,
    Rectangle,
    TimeConfig,
    TransferConfig,
)
from intrusim.mpm.constitutive import material_from_config
from intrusim.mpm.solver import Solver
from intrusim.mpm.transfer import g2p_kernel, p2g_kernel


def _patch(density_ratio: float, shape: str = "linear", flip: float = 1.0, chunks: int = 16) -> Solver:
    """A patch away from the walls, no gravity (density_ratio < 1: loose and stress-free)."""
    cfg = MPMConfig(domain=DomainConfig(size=(0.2, 0.2), cells=(20, 20)),
                    bed=BedConfig(rectangles=[Rectangle(x0=0.04, z0=0.04, x1=0.16, z1=0.12)],
                                  density_ratio=density_ratio),
                    gravity=(0.0, 0.0), transfer=TransferConfig(flip=flip, shape=shape),
                    backend=BackendConfig(p2g_chunks=chunks))  # fmt: skip
    return Solver(cfg)


def test_linear_g2p_gives_an_affine_fields_gradient_exactly_inside_the_patch():
    """v = A x + b on the points: each inner node gets A x_i + b (the points sit symmetrically about it),
    and sum v_i (grad w)^T over a cell's 4 nodes is A for every point in it."""
    s = _patch(0.8)
    a = np.array([[0.3, -0.2], [0.5, 0.1]])  # 1/s
    x = s.particles.to_numpy(["x"])["x"].astype(np.float64)
    s.particles.load({"v": x @ a.T + np.array([0.01, -0.02])})
    s.step()
    d = s.particles.to_numpy(["x", "C"])
    h = s.h
    inner = np.all((d["x"] > [0.04 + 1.5 * h, 0.04 + 1.5 * h]) & (d["x"] < [0.16 - 1.5 * h, 0.12 - 1.5 * h]), axis=1)
    assert inner.sum() > 50
    assert np.allclose(d["C"][inner], a, rtol=0, atol=1e-5)


def test_linear_flip_conserves_the_momentum_of_a_stressed_patch():
    """A dense free patch with a random velocity field: the stress forces sum to zero over the nodes
    (sum grad w = 0), so FLIP leaves the points' total momentum as it was."""
    s = _patch(1.0)
    rng = np.random.default_rng(5)
    s.particles.load({"v": rng.normal(0.0, 0.05, (s.particles.n, 2))})
    d0 = s.particles.to_numpy(["v", "mass"])
    p0 = (d0["mass"][:, None] * d0["v"]).sum(axis=0)
    for _ in range(30):
        s.step()
    d = s.particles.to_numpy(["v", "mass", "sigma"])
    assert np.abs(d["sigma"]).max() > 10.0  # Pa: the field did load the patch
    p1 = (d["mass"][:, None] * d["v"]).sum(axis=0)
    scale = (d0["mass"] * np.linalg.norm(d0["v"], axis=1)).sum()
    assert np.allclose(p1, p0, rtol=0, atol=1e-5 * scale)


def test_linear_and_quadratic_differ_and_the_fixed_point_sums_agree():
    """The option acts (its one step is not the quadratic one), and the atomic fixed-point P2G
    (a GPU's) gives the chunked CPU sums."""
    runs = {}
    for key, (shape, chunks) in dict(lin=("linear", 16), fixed=("linear", 1), quad=("quadratic", 16)).items():
        s = _patch(1.0, shape=shape, chunks=chunks)
        s.particles.load({"v": np.random.default_rng(2).normal(0.0, 0.05, (s.particles.n, 2))})
        for _ in range(20):
            s.step()
        runs[key] = s.particles.to_numpy(["v"])["v"]
    scale = np.abs(runs["lin"]).max()
    assert np.allclose(runs["lin"], runs["fixed"], rtol=0, atol=1e-5 * scale)
    assert np.abs(runs["lin"] - runs["quad"]).max() > 1e-3 * scale


def test_a_linear_bed_at_rest_holds_the_hydrostatic_stress():
    rho, g, depth = 900.0, 9.8, 0.10
    cfg = MPMConfig(domain=DomainConfig(size=(0.2, 0.15), cells=(40, 30)),
                    material=MaterialConfig(rho_c=rho, mu_s=0.56, youngs_modulus=1e6),
                    bed=BedConfig(rectangles=[Rectangle(x0=0, z0=0, x1=0.2, z1=depth)]),
                    time=TimeConfig(t_end=0.3), transfer=TransferConfig(flip=1.0, shape="linear"))  # fmt: skip
    s = Solver(cfg)
    mass0 = s.particle_fields()["mass"].sum()
    s.run()
    d = s.particle_fields()
    x, z = d["x"][:, 0], d["x"][:, 1]
    inner = (x > 0.05) & (x < 0.15)
    errors = []
    for top in np.arange(2 * s.h, depth - 2 * s.h, s.h):
        band = inner & (z < depth - top) & (z >= depth - top - s.h)
        errors.append(abs((-d["sigma"][band, 1, 1]).sum() / (rho * g * (depth - z[band])).sum() - 1.0))
    assert max(errors) < 0.05, errors
    assert d["mass"].sum() == pytest.approx(mass0, rel=1e-12)
    assert np.linalg.norm(d["v"], axis=1).max() < 0.05  # m/s; FLIP keeps the settling waves (APIC < 0.01)


def test_linear_runs_the_one_point_kernels_and_the_vectorised_ones_refuse_it():
    assert not _patch(0.8)._lanes
    with pytest.raises(ValueError, match="quadratic only"):
        p2g_kernel(True, lanes=True, linear=True)
    material = material_from_config(MaterialConfig())
    with pytest.raises(ValueError, match="quadratic only"):
        g2p_kernel(material.taichi_update, len(material.params), lanes=True, linear=True)


def test_an_unknown_shape_is_refused():
    with pytest.raises(ValidationError, match="shape"):
        TransferConfig(shape="cubic")
