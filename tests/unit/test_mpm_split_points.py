"""Splitting material points for finer cells (intrusim.mpm.particles.split_points)."""

import numpy as np
import pytest

from intrusim.mpm.particles import FIELDS, split_points


def _points(n=7, seed=3):
    rng = np.random.default_rng(seed)
    return {name: rng.normal(size=(n, *shape)) + (2.0 if name in ("mass", "vol") else 0.0)
            for name, (shape, _) in FIELDS.items()}  # fmt: skip


@pytest.mark.parametrize("factor", [2, 3])
def test_split_keeps_mass_volume_momentum_and_centre_of_mass(factor):
    p = _points()
    q = split_points(p, spacing=0.01, factor=factor)
    k = factor**2
    assert len(q["x"]) == k * len(p["x"])
    assert q["mass"].sum() == pytest.approx(p["mass"].sum(), rel=1e-12)
    assert q["vol"].sum() == pytest.approx(p["vol"].sum(), rel=1e-12)
    mom_p = (p["mass"][:, None] * p["v"]).sum(axis=0)
    mom_q = (q["mass"][:, None] * q["v"]).sum(axis=0)
    assert np.allclose(mom_q, mom_p, rtol=1e-12, atol=1e-12)
    com_p = (p["mass"][:, None] * p["x"]).sum(axis=0) / p["mass"].sum()
    com_q = (q["mass"][:, None] * q["x"]).sum(axis=0) / q["mass"].sum()
    assert np.allclose(com_q, com_p, atol=1e-12)


def test_children_sit_on_the_sub_lattice_with_the_apic_velocity_and_the_parent_state():
    p = _points(n=1)
    q = split_points(p, spacing=0.01, factor=2)
    d = q["x"] - p["x"][0]
    assert np.allclose(np.sort(np.abs(d).ravel()), 0.0025)  # +-spacing / 4 in x and z
    assert len({tuple(np.round(r, 6)) for r in d}) == 4
    assert np.allclose(q["v"], p["v"][0] + d @ p["C"][0].T)  # v + C d
    for name in ("C", "sigma", "s_yy", "eps_p", "gdot_p"):
        assert np.allclose(q[name], p[name][0])
    assert np.allclose(q["mass"], p["mass"][0] / 4)


def test_bad_split_arguments_are_refused():
    with pytest.raises(ValueError, match="factor"):
        split_points(_points(), 0.01, 0)
    with pytest.raises(ValueError, match="spacing"):
        split_points(_points(), 0.0, 2)
