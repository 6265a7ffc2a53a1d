"""The particle arrays' layout: blocks of LANES points per field (intrusim.mpm.particles)."""

import numpy as np
import pytest
import taichi as ti

from intrusim.mpm.backend import ensure_initialized
from intrusim.mpm.particles import FIELDS, LANES, XX, XZ, ZZ, Particles, from_blocks, get_sym2, get_vec2, to_blocks


def _points(n: int, seed: int = 1) -> dict:
    rng = np.random.default_rng(seed)
    data = {name: rng.standard_normal((n, *shape)) for name, (shape, _) in FIELDS.items()}
    data["sigma"] = data["sigma"] + data["sigma"].transpose(0, 2, 1)  # a stress is symmetric
    return data


@pytest.mark.parametrize("n", [1, LANES - 1, LANES, 3 * LANES + 5])
def test_the_fields_come_back_as_they_went_in(n):
    ensure_initialized(precision="f32")
    data = _points(n)
    pts = Particles(data)
    assert pts.blocks == -(-n // LANES)
    back = pts.to_numpy()
    for name, a in data.items():
        np.testing.assert_array_equal(back[name], a.astype(np.float32), err_msg=name)


def test_the_pads_are_copies_of_the_last_point_and_sigma_is_stored_once():
    ensure_initialized(precision="f32")
    n = 2 * LANES + 3
    data = _points(n)
    pts = Particles(data)
    full = pts.to_numpy(pads=True)
    assert len(full["x"]) == 3 * LANES
    for name, a in full.items():
        assert np.array_equal(a[n:], np.repeat(a[n - 1 : n], LANES - 3, axis=0)), name
    blocks = pts.sigma.to_numpy()  # (blocks, 3, LANES): xx, zz, xz of each block's points
    assert blocks.shape == (3, 3, LANES)
    s = data["sigma"].astype(np.float32)
    np.testing.assert_array_equal(blocks[1, XX], s[LANES : 2 * LANES, 0, 0])
    np.testing.assert_array_equal(blocks[1, ZZ], s[LANES : 2 * LANES, 1, 1])
    np.testing.assert_array_equal(blocks[1, XZ], s[LANES : 2 * LANES, 0, 1])


def test_an_unsymmetric_stress_is_stored_as_its_symmetric_part():
    ensure_initialized(precision="f32")
    data = _points(5)
    data["sigma"][:, 0, 1] += 2.0
    got = Particles(data).to_numpy(["sigma"])["sigma"]
    want = 0.5 * (data["sigma"] + data["sigma"].transpose(0, 2, 1))
    np.testing.assert_allclose(got, want, rtol=1e-6, atol=1e-6)


def test_a_field_of_the_wrong_shape_is_refused():
    ensure_initialized(precision="f32")
    data = _points(10)
    data["C"] = data["C"][:, 0]
    with pytest.raises(ValueError, match="'C'"):
        Particles(data)


def test_blocks_round_trip_on_the_host():
    comps = np.arange(11 * 3, dtype=np.float32).reshape(11, 3)
    blocks = to_blocks(comps)
    assert blocks.shape == (2, 3, LANES)
    np.testing.assert_array_equal(blocks[0, 1], comps[:LANES, 1])
    np.testing.assert_array_equal(blocks[1, 2, 3:], np.full(LANES - 3, comps[-1, 2]))
    np.testing.assert_array_equal(from_blocks(blocks, 11), comps)


@ti.kernel
def _read_point(x: ti.types.ndarray(), sigma: ti.types.ndarray(), p: int, out: ti.types.ndarray()):
    xp, sp = get_vec2(x, p), get_sym2(sigma, p)
    out[0], out[1] = xp[0], xp[1]
    out[2], out[3], out[4], out[5] = sp[0, 0], sp[0, 1], sp[1, 0], sp[1, 1]


def test_a_one_point_kernel_reads_point_p():
    ensure_initialized(precision="f32")
    data = _points(2 * LANES + 3)
    pts = Particles(data)
    out = ti.ndarray(ti.f32, 6)
    for p in (0, 5, LANES, 2 * LANES + 2):
        _read_point(pts.x, pts.sigma, p, out)
        want = np.concatenate([data["x"][p], data["sigma"][p].ravel()]).astype(np.float32)
        np.testing.assert_array_equal(out.to_numpy(), want)
