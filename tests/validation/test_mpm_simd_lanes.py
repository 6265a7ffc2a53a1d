"""The CPU's vectorised G2P (``BenchmarkSwitches.simd_lanes``, the default: 8 points per loop iteration, SIMD arithmetic)
against the one-point-per-iteration kernel (the reference, and a GPU's kernel).

The two compute the same sums in the same order; they may differ in the last bit (the vector code
is compiled separately, with fast-math), so one step agrees to float32 rounding and a run of many
steps drifts apart only as rounding does.
"""

import os
import subprocess
import sys

import numpy as np
import pytest
import taichi as ti

from intrusim.mpm.backend import BenchmarkSwitches, ensure_initialized, unscalarized
from intrusim.mpm.config import MaterialConfig, MuIConfig
from intrusim.mpm.constitutive import DruckerPragerSeparation, material_from_config
from intrusim.mpm.fluidity import SOURCE_CHUNKS, fluidity_relax_kernel, fluidity_sources_kernel
from intrusim.mpm.grid import record_width
from intrusim.mpm.particles import FIELDS, LANES, Particles
from intrusim.mpm.solver import Solver
from intrusim.mpm.transfer import exp_near_zero_lanes, g2p_kernel, p2g_kernel
from intrusim.scenarios import grousered_wheel_scenario
from intrusim.scenarios.mpm_locomotion import mpm_config, quick_settings

# the vectorised kernels are the CPU's (a GPU runs the one-point ones); with the suite on a GPU
# (INTRUSIM_TI_ARCH, benchmarks/gpu_checks.sh) these tests would compile them for the GPU
pytestmark = pytest.mark.skipif(
    os.environ.get("INTRUSIM_TI_ARCH", "cpu") != "cpu", reason="the vectorised G2P and P2G are the CPU's kernels"
)

H, PAD, NX, NZ, DT = 0.01, 2, 24, 20, 2e-4
RHO_C = 1500.0


def _state(n: int, seed: int = 3) -> dict:
    """n points in a 0.2 x 0.16 m box with a mix of stresses: compressed and sheared past yield,
    elastic, in tension, and below the critical density; a grid velocity field with shear."""
    rng = np.random.default_rng(seed)
    x = np.column_stack([rng.uniform(0.0, 0.2, n), rng.uniform(0.0, 0.16, n)]).astype(np.float32)
    p = rng.uniform(500.0, 3000.0, n)
    shear = rng.uniform(0.0, 1.0, n) * p
    sigma = np.zeros((n, 2, 2))
    sigma[:, 0, 0] = -p + 0.3 * shear
    sigma[:, 1, 1] = -p - 0.3 * shear
    sigma[:, 0, 1] = sigma[:, 1, 0] = 0.5 * shear
    sigma[: n // 10] *= -1.0  # tension
    mass = np.full(n, 1600.0 * H * H / 4.0)
    rho = np.where(rng.random(n) < 0.1, 0.9 * RHO_C, rng.uniform(1.0, 1.1, n) * RHO_C)  # 10 % loose
    gx, gz = np.meshgrid(np.arange(NX) * H, np.arange(NZ) * H, indexing="ij")
    gv = np.stack([0.5 * np.sin(20 * gz) + 0.2 * gx, 0.3 * np.cos(15 * gx) - 0.1 * gz], axis=-1)
    gv += 0.05 * rng.standard_normal(gv.shape)
    return {
        "x": x,
        "v": np.zeros((n, 2)),
        "C": np.zeros((n, 2, 2)),
        "mass": mass,
        "vol": mass / rho,
        "sigma": sigma,
        "s_yy": -p,
        "eps_p": rng.uniform(0.0, 0.1, n),
        "gdot_p": np.zeros(n),
        "gv": gv,
    }


def _arrays(state: dict) -> tuple[Particles, ti.Ndarray]:
    """The state's points as the solver holds them (blocks of LANES, see particles) and its grid velocity."""
    gv = ti.Vector.ndarray(2, ti.f32, shape=state["gv"].shape[:-1])
    gv.from_numpy(np.asarray(state["gv"], np.float32))
    return Particles({k: a for k, a in state.items() if k != "gv"}), gv


def _g2p(material, state: dict, lanes: bool) -> dict:
    pts, gv = _arrays(state)
    no_flip = ti.Vector.ndarray(2, ti.f32, shape=(1, 1))  # FLIP's old grid velocity: a placeholder (not touched)
    args = [pts.arrays[k] for k in FIELDS] + [gv, H, PAD, DT, material.params, 1.0 / 300.0, no_flip, 0.0]
    if lanes:
        with unscalarized():
            g2p_kernel(material.taichi_update, len(material.params), lanes=True)(*args)
    else:
        g2p_kernel(material.taichi_update, len(material.params))(*args)
    return _with_pads(pts)


def _with_pads(pts: Particles) -> dict:
    """Every field of the points; the last block's pads must have stayed copies of the last point."""
    out = pts.to_numpy(pads=True)
    for name, a in out.items():
        pads = a[pts.n :]
        np.testing.assert_array_equal(pads, np.repeat(a[pts.n - 1 : pts.n], len(pads), axis=0), err_msg=name)
    return {name: a[: pts.n] for name, a in out.items()}


def _close(got: dict, want: dict) -> None:
    """Equal to float32 rounding: within 2e-5 of each field's largest value (measured: up to 3.6e-6,
    in gdot_p and C, whose formulas subtract nearly equal sums)."""
    for name in want:
        scale = max(np.abs(want[name]).max(), 1e-30)
        np.testing.assert_allclose(got[name], want[name], rtol=0, atol=2e-5 * scale, err_msg=name)


MATERIALS = {
    "paper": MaterialConfig(rho_c=RHO_C, mu_s=0.56),
    "viscous": MaterialConfig(rho_c=RHO_C, mu_s=0.56, viscosity=10.0),
    "mu_i": MaterialConfig(rho_c=RHO_C, mu_s=0.56, mu_i=MuIConfig(grain_diameter=1e-3)),
}


@pytest.mark.parametrize("law", list(MATERIALS))
def test_one_g2p_step_matches_the_one_point_kernel(law):
    ensure_initialized(precision="f32")
    material = material_from_config(MATERIALS[law])
    n = 8 * 125 + 5  # a last block of 5 points: its 3 pads are computed and stay copies of the last point
    state = _state(n)
    a, b = _g2p(material, state, lanes=False), _g2p(material, state, lanes=True)
    # every case of the law occurs: free separation, yield (plastic strain grows), elastic
    dgamma = a["gdot_p"] * DT
    free = np.all(a["sigma"] == 0.0, axis=(1, 2))
    assert free.sum() > n // 20 and (~free & (dgamma > 0)).sum() > n // 20 and (~free & (dgamma == 0)).sum() > n // 20
    _close(b, a)
    assert np.array_equal(free, np.all(b["sigma"] == 0.0, axis=(1, 2)))
    assert np.array_equal(dgamma > 0, b["gdot_p"] > 0)


def test_a_point_count_below_one_block():
    ensure_initialized(precision="f32")
    material = DruckerPragerSeparation.from_config(MATERIALS["paper"])
    state = _state(LANES - 3)
    _close(*(_g2p(material, state, lanes=lanes) for lanes in (True, False)))


def _p2g(state: dict, chunks: int, lanes: bool) -> tuple[np.ndarray, np.ndarray]:
    """The chunked P2G of ``state`` into ``chunks`` grid copies: (copies, each copy's node box)."""
    pts, _ = _arrays(state)
    copies = ti.Vector.ndarray(record_width(True), ti.f32, shape=chunks * NX * NZ)  # the solver's chunked copies
    box = ti.ndarray(ti.i32, shape=(chunks, 4))
    no_flip = ti.Vector.ndarray(2, ti.f32, shape=1)  # FLIP's momentum copies: a placeholder (not touched)
    args = [pts.arrays[k] for k in ("x", "v", "C", "mass", "vol", "sigma")] + [
        pts.n,
        copies,
        box,
        NX,
        NZ,
        H,
        PAD,
        DT,
        1.0,
        no_flip,
    ]
    if lanes:
        with unscalarized():
            p2g_kernel(chunked=True, lanes=True)(*args)
    else:
        p2g_kernel(chunked=True)(*args)
    out = copies.to_numpy().reshape(chunks, NX, NZ, -1)
    assert np.all(out[..., 3:] == 0.0)  # the padding of a 4-wide record stays zero
    return out[..., :3], box.to_numpy()


@pytest.mark.parametrize("chunks", [1, 3, 16])
def test_chunked_p2g_matches_the_one_point_kernel(chunks):
    ensure_initialized(precision="f32")
    state = _state(8 * 125 + 5)
    state["x"] = np.clip(state["x"], 0.02, 0.15)  # inside the grid's stencil range
    state["v"] = np.random.default_rng(5).standard_normal((len(state["x"]), 2))
    state["C"] = np.random.default_rng(6).standard_normal((len(state["x"]), 2, 2))
    (a, box_a), (b, box_b) = _p2g(state, chunks, lanes=False), _p2g(state, chunks, lanes=True)
    assert np.array_equal(box_a, box_b)  # each chunk's node box: lanes past a chunk's end not counted
    assert np.abs(a).max() > 0
    # every point's mass once, the pads' (copies of the last point) not
    np.testing.assert_allclose(a[..., 2].sum(), state["mass"].sum(), rtol=1e-5)
    # each copy's sums, point by point in order (measured on x86-64: identical bit for bit)
    for e, name in enumerate(("momentum x", "momentum z", "mass")):
        np.testing.assert_allclose(b[..., e], a[..., e], rtol=0, atol=2e-6 * np.abs(a[..., e]).max(), err_msg=name)


def _relax(state: dict, excess: np.ndarray, lanes: bool) -> dict:
    """The nonlocal fluidity's relaxation of ``state`` with the nodes' excess g - g_loc."""
    pts, _ = _arrays(state)
    ex = ti.ndarray(ti.f32, shape=excess.shape)
    ex.from_numpy(excess.astype(np.float32))
    prm = (1e6 / 2.6, 0.56, 1.0, 1e-3, 2500.0)  # G, mu_s, b, d, rho_s
    args = [pts.arrays[k] for k in ("x", "sigma", "s_yy", "eps_p", "gdot_p")] + [ex, H, PAD, DT, prm]
    if lanes:
        with unscalarized():
            fluidity_relax_kernel(lanes=True)(*args)
    else:
        fluidity_relax_kernel()(*args)
    out = _with_pads(pts)
    return {k: out[k] for k in ("sigma", "s_yy", "eps_p", "gdot_p")}


def test_nonlocal_relaxation_matches_the_one_point_kernel():
    ensure_initialized(precision="f32")
    state = _state(8 * 125 + 5)
    rng = np.random.default_rng(7)
    excess = rng.uniform(-20.0, 40.0, (NX, NZ))  # 1/s: points that creep, flow and stay
    a, b = _relax(state, excess, lanes=False), _relax(state, excess, lanes=True)
    sig = state["sigma"]
    untouched = -(sig[:, 0, 0] + sig[:, 1, 1] + state["s_yy"]) <= 0  # tension (P <= 0): left as they are
    assert untouched.sum() > 50 and (a["gdot_p"][~untouched] > 0).mean() > 0.5
    for name in a:
        np.testing.assert_array_equal(b[name][untouched], a[name][untouched], err_msg=name)
    _close(b, a)


@ti.kernel
def _exp_lanes(x: ti.types.ndarray(), out: ti.types.ndarray()):
    for blk in range(x.shape[0] // LANES):
        v = ti.Vector([x[blk * LANES + k] for k in ti.static(range(LANES))])
        r = exp_near_zero_lanes(v)
        for k in ti.static(range(LANES)):
            out[blk * LANES + k] = r[k]


def test_the_volume_factor_takes_exp_where_a_lane_needs_it():
    # exp(dt tr L): a polynomial near 0, ti.exp from |x| = 0.01 on, lane by lane; blocks that mix both.
    # Taichi 1.7.4 reads an unscalarised mask's .any() as false whatever it holds (transfer.any_lane):
    # the polynomial alone would be 1.4e-3 off at x = 1
    ensure_initialized(precision="f32")
    x = np.array([0.0, 1e-3, -5e-3, 0.5, 1e-4, -0.3, 1.0, 2e-3] + [1e-4] * 7 + [-1.0], np.float32)
    xs, out = ti.ndarray(ti.f32, len(x)), ti.ndarray(ti.f32, len(x))
    xs.from_numpy(x)
    with unscalarized():
        _exp_lanes(xs, out)
    np.testing.assert_allclose(out.to_numpy(), np.exp(x.astype(np.float64)), rtol=2e-7)


def _sources(state: dict, lanes: bool) -> tuple[np.ndarray, np.ndarray]:
    """The nonlocal fluidity's sources of ``state``, summed over the chunk copies: (src, copy boxes)."""
    pts, _ = _arrays(state)
    chunks = SOURCE_CHUNKS
    parts = ti.Vector.ndarray(record_width(True), ti.f32, shape=chunks * NX * NZ)
    box_parts, box = ti.ndarray(ti.i32, shape=(chunks, 4)), ti.ndarray(ti.i32, shape=8)
    box.from_numpy(np.array([0, NX, 0, NZ, 0, 0, 0, 0], np.int32))
    src = ti.Vector.ndarray(3, ti.f32, shape=(NX, NZ))
    prm = (0.56, 1.0, 1e-3, 2500.0)  # mu_s, b, d, rho_s
    args = [pts.arrays[k] for k in ("x", "mass", "sigma", "s_yy")] + [
        pts.n,
        parts,
        box_parts,
        box,
        src,
        H,
        PAD,
        prm,
        1.0,
    ]
    if lanes:
        with unscalarized():
            fluidity_sources_kernel(True, lanes=True)(*args)
    else:
        fluidity_sources_kernel(True)(*args)
    return src.to_numpy(), box_parts.to_numpy()


def test_nonlocal_sources_match_the_one_point_kernel():
    ensure_initialized(precision="f32")
    state = _state(8 * 125 + 5)  # points in tension (no source), below mu_s (|dmu|, no g_loc) and above it
    state["x"] = np.clip(state["x"], 0.02, 0.15)
    (a, box_a), (b, box_b) = _sources(state, lanes=False), _sources(state, lanes=True)
    assert np.array_equal(box_a, box_b)
    assert np.abs(a[..., 1]).max() > 0 and np.abs(a[..., 0]).max() > 0
    # float32 rounding: g_loc's product of quotients may round otherwise in vector code (measured: up
    # to 4.7e-8, 1.0e-6 of the largest |dmu| g_loc)
    for e, name in enumerate(("|dmu|", "|dmu| g_loc", "mass")):
        np.testing.assert_allclose(b[..., e], a[..., e], rtol=0, atol=2e-5 * np.abs(a[..., e]).max(), err_msg=name)


def test_the_vectorised_p2g_is_only_the_chunked_one():
    for chunked, fixed in ((False, False), (False, True)):  # a GPU's atomic adds: one point per iteration
        with pytest.raises(ValueError, match="chunked"):
            p2g_kernel(chunked, fixed, lanes=True)
        with pytest.raises(ValueError, match="chunked"):
            fluidity_sources_kernel(chunked, fixed, lanes=True)


def test_unscalarized_restores_the_config_on_error():
    ensure_initialized(precision="f32")
    cfg = ti.lang.impl.current_cfg()
    assert cfg.real_matrix_scalarize
    with pytest.raises(RuntimeError):
        with unscalarized():
            assert not cfg.real_matrix_scalarize
            raise RuntimeError("boom")
    assert cfg.real_matrix_scalarize


def _wheel(**switches) -> Solver:
    cfg = mpm_config(grousered_wheel_scenario(), quick_settings("wheel"), 60.0, None)
    cfg.contact = "band"  # the bound of test_wheel_run_follows_the_one_point_run was measured with the band
    return Solver(cfg, switches=BenchmarkSwitches(**switches))


def _run(solver: Solver, steps: int) -> tuple[np.ndarray, np.ndarray]:
    for _ in range(steps):
        solver.step()
    st = solver.intruders[0].state
    return np.array([st.x, st.z, st.vx, st.vz]), solver.particles.to_numpy(["x"])["x"]


_COMPILE_THE_STEP = """
import sys, taichi as ti
from intrusim.mpm.backend import BenchmarkSwitches, ensure_initialized
ensure_initialized("cpu", "f32", 1)
ti.lang.impl.current_cfg().print_kernel_llvm_ir_optimized = True  # each kernel's IR as it compiles, here
from intrusim.mpm.solver import Solver
from intrusim.scenarios import grousered_wheel_scenario
from intrusim.scenarios.mpm_locomotion import mpm_config, quick_settings
cfg = mpm_config(grousered_wheel_scenario(), quick_settings("wheel"), 60.0, None)
cfg.transfer.flip = None if sys.argv[2] == "default" else 0.0
solver = Solver(cfg, switches=BenchmarkSwitches(step_graph=sys.argv[1] == "graph"))
for _ in range(3):
    solver.step()
assert ti.lang.impl.current_cfg().real_matrix_scalarize  # switched back after compiling
"""


@pytest.mark.parametrize("path,transfer", [("graph", "apic"), ("direct", "apic"), ("graph", "default")])
def test_the_step_compiles_the_kernel_once_as_vector_code(path, transfer, tmp_path):
    # a fresh process and kernel cache; Taichi writes the optimised LLVM IR of each kernel it compiles.
    # Unscalarised, every square root of the law (G2P) and every floor of a position (both kernels) is
    # one 8-wide vector op; a kernel compiled with Taichi's default (scalarised, then partly
    # re-vectorised by LLVM) has scalar ones and is slower (G2P ~1.3x). The step must compile each
    # kernel once, unscalarised, and run that one
    script = tmp_path / "step.py"
    script.write_text(_COMPILE_THE_STEP)
    env = {**os.environ, "TI_OFFLINE_CACHE_FILE_PATH": str(tmp_path / "cache")}
    done = subprocess.run(
        [sys.executable, str(script), path, transfer], cwd=tmp_path, env=env, capture_output=True, text=True
    )
    assert done.returncode == 0, done.stderr[-2000:]
    ir = [f.read_text() for f in tmp_path.glob("*.ll")]
    g2p = [text for text in ir if "define void @g2p_density_stress" in text]
    p2g = [text for text in ir if "define void @p2g_scatter" in text]
    assert len(g2p) == 1 and len(p2g) == 1
    assert "@llvm.sqrt.v8f32" in g2p[0] and "@llvm.sqrt.f32(" not in g2p[0]
    assert "@llvm.floor.v8f32" in p2g[0] and "@llvm.floor.f32(" not in p2g[0]
    # the particles in blocks of 8 (particles.py): each component of a block is one vector load or
    # store, G2P reads 9 (x 2, m, V, sigma 3, s_yy, eps_p) and writes 15, P2G reads 13 (x 2, v 2, C 4,
    # m, V, sigma 3); P2G adds into 9 nodes per point as one 4-wide record each (grid.record_width);
    # the default transfer's G2P also reads the points' own velocity (2), and its P2G adds FLIP's
    # momentum into the same records, 8 wide (Grid.flip_in_records)
    flip = transfer == "default"
    assert g2p[0].count("load <8 x float>") == 9 + 2 * flip and g2p[0].count("store <8 x float>") == 15
    assert p2g[0].count("load <8 x float>") == 13 + 9 * LANES * flip
    assert p2g[0].count("load <4 x float>") == 9 * LANES * (not flip)


def test_wheel_run_follows_the_one_point_run():
    # the coarse wheel, 1500 steps (spin-up, sinking, rolling): the two kernels' runs differ as
    # rounding grows. Measured with the particle blocks: 6.9e-10 m in the wheel's height
    # and 6e-8 m in a point's position up to step 1056, where one point's density reaches rho_c one
    # step apart in the two runs (a rounding tie; the law is stress-free below rho_c), then 4.9e-7 m
    # and 2.9e-6 m at step 1500 (7.7e-7 m and 2.3e-6 m at step 1250)
    lanes, scalar = _wheel(), _wheel(simd_lanes=False)
    start = _run(lanes, 0)[0]
    bl, xl = _run(lanes, 1500)
    bs, xs = _run(scalar, 1500)
    assert bl[0] - start[0] > 0.02 and start[1] - bl[1] > 0.01  # it rolled 2 cm and sank 1 cm
    np.testing.assert_allclose(bl[:2], bs[:2], rtol=0, atol=1e-6)  # m
    np.testing.assert_allclose(bl[2:], bs[2:], rtol=0, atol=1e-4)  # m/s
    assert np.max(np.abs(xl - xs)) < 1e-5  # m


_FLOAT64_WHEEL = """
from intrusim.mpm.solver import Solver
from intrusim.scenarios import grousered_wheel_scenario
from intrusim.scenarios.mpm_locomotion import mpm_config, quick_settings
cfg = mpm_config(grousered_wheel_scenario(), quick_settings("wheel"), 60.0, None)
cfg.backend.precision = "f64"
solver = Solver(cfg)
z0 = solver.intruders[0].state.z
for _ in range(50):
    solver.step()
assert solver.particles.x.to_numpy().dtype.name == "float64" and not solver._lanes
print(z0 - solver.intruders[0].state.z)
"""


def test_a_float64_run_steps_on_the_one_point_kernels(tmp_path):
    # in float64 the vectorised P2G crashes the process (Taichi 1.7.4): such a run must take the
    # one-point kernels (it crashed at its first step when it did not); its own process, as Taichi
    # is initialised once per process
    script = tmp_path / "f64.py"
    script.write_text(_FLOAT64_WHEEL)
    done = subprocess.run([sys.executable, str(script)], cwd=tmp_path, capture_output=True, text=True)
    assert done.returncode == 0, done.stderr[-2000:]
    assert float(done.stdout.strip().splitlines()[-1]) > 0.0  # the wheel falls onto the bed
