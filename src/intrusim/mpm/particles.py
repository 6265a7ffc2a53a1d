"""Material points: their state in Taichi ndarrays, in blocks of LANES points (2D plane strain, per unit width).

Each field is an ndarray of shape (blocks, components) whose element is a vector of LANES floats:
``a[b, c]`` holds component c of the points b * LANES ... b * LANES + LANES - 1 (an array of
structures of arrays). The CPU's vectorised kernels (``BenchmarkSwitches.simd_lanes``, the default) read and write a
block's component as one vector load or store. With one array element per point (the former layout)
every lane is its own load and insert; a G2P's particle reads and writes took 1.35-2.30x
as long on 2 threads at 64k-1M points, 1.66-2.34x on one (``benchmarks/bench_layout.py``). A one-point kernel (a
GPU's, and the reference) addresses point p as ``a[p // LANES, c][p % LANES]`` (:func:`get_vec2`
and siblings). The last block's missing points ("pads") are copies of the last point: a kernel that
updates points updates every slot of the blocks, so they stay copies; a kernel that sums over points
(P2G, the fluidity's sources, the guards) stops at the n points; :meth:`Particles.to_numpy` drops them.

Components: x, v (x, z); C row by row (C_xx, C_xz, C_zx, C_zz); sigma, which is symmetric, as
(sigma_xx, sigma_zz, sigma_xz) (``XX, ZZ, XZ``); the scalars as one component.
"""

import numpy as np
import taichi as ti

from ._taichi_private import free_ndarrays
from .backend import info

LANES = 8  # points per block (8 f32: Taichi's CPU target computes them as two SSE registers)
XX, ZZ, XZ = 0, 1, 2  # sigma's components in its block array

#: name -> (shape suffix, description with unit); order defines the checkpoint layout
FIELDS: dict[str, tuple[tuple[int, ...], str]] = {
    "x": ((2,), "position (x, z), m"),
    "v": ((2,), "velocity, m/s"),
    "C": ((2, 2), "APIC affine matrix = velocity gradient dv_i/dx_j, 1/s"),
    "mass": ((), "mass per unit width, kg/m"),
    "vol": ((), "area (volume per unit width), m^2"),
    "sigma": ((2, 2), "in-plane Cauchy stress (symmetric), Pa"),
    "s_yy": ((), "out-of-plane normal stress, Pa"),
    "eps_p": ((), "equivalent plastic shear strain, -"),
    "gdot_p": ((), "equivalent plastic shear strain rate, 1/s"),
}
COMPONENTS = {"x": 2, "v": 2, "C": 4, "sigma": 3}  # stored components per point (others: 1)


def n_blocks(n: int) -> int:
    """Blocks of LANES points holding n points."""
    return (int(n) + LANES - 1) // LANES


def _components(name: str, a: np.ndarray) -> np.ndarray:
    """(n, components) of a field given in its FIELDS shape (sigma: its symmetric part's 3 components)."""
    if name == "sigma":
        return np.stack([a[:, 0, 0], a[:, 1, 1], 0.5 * (a[:, 0, 1] + a[:, 1, 0])], axis=1)
    return a.reshape(len(a), -1)


def _field(name: str, comps: np.ndarray) -> np.ndarray:
    """The field in its FIELDS shape from its (n, components)."""
    n = len(comps)
    if name == "sigma":
        out = np.empty((n, 2, 2), comps.dtype)
        out[:, 0, 0], out[:, 1, 1] = comps[:, XX], comps[:, ZZ]
        out[:, 0, 1] = out[:, 1, 0] = comps[:, XZ]
        return out
    return comps.reshape((n, *FIELDS[name][0]))


def to_blocks(comps: np.ndarray) -> np.ndarray:
    """(n, k) per-point components -> (blocks, k, LANES), the last block padded with the last point."""
    n, k = comps.shape
    pad = n_blocks(n) * LANES - n
    if pad:
        comps = np.concatenate([comps, np.repeat(comps[-1:], pad, axis=0)])
    return np.ascontiguousarray(comps.reshape(-1, LANES, k).transpose(0, 2, 1))


def from_blocks(blocks: np.ndarray, n: int) -> np.ndarray:
    """(blocks, k, LANES) -> the (n, k) components of the first n points."""
    return blocks.transpose(0, 2, 1).reshape(-1, blocks.shape[1])[:n]


class Particles:
    """Particle arrays on the Taichi device, in blocks of LANES points (see the module's text).

    Parameters
    ----------
    data : dict of name -> numpy array with leading dimension N (see :data:`FIELDS`);
        missing entries start at zero.
    """

    def __init__(self, data: dict[str, np.ndarray]):
        real = info().real
        self.n = int(len(data["x"]))
        if self.n == 0:
            raise ValueError("no particles: the bed is empty")
        self.blocks = n_blocks(self.n)
        self.arrays: dict[str, ti.Ndarray] = {
            name: ti.Vector.ndarray(LANES, real, shape=(self.blocks, COMPONENTS.get(name, 1))) for name in FIELDS
        }
        self.load({k: data.get(k, np.zeros((self.n, *FIELDS[k][0]))) for k in FIELDS})

    def __getattr__(self, name: str):
        arrays = self.__dict__.get("arrays", {})
        if name in arrays:
            return arrays[name]
        raise AttributeError(name)

    def load(self, data: dict[str, np.ndarray]) -> None:
        """Copy host arrays (FIELDS shapes, n points each) into the device arrays."""
        dtype = info().np_real
        for name, arr in data.items():
            arr = np.asarray(arr)
            if arr.shape != (self.n, *FIELDS[name][0]):
                raise ValueError(f"particle field {name!r}: shape {arr.shape}, expected {(self.n, *FIELDS[name][0])}")
            self.arrays[name].from_numpy(to_blocks(_components(name, arr.astype(dtype, copy=False))))

    def release(self) -> None:
        """Free the device arrays now (:func:`~intrusim.mpm._taichi_private.free_ndarrays`); they
        must not be used after this."""
        arrays, self.arrays = self.arrays, {}
        free_ndarrays(arrays.values())

    def to_numpy(self, names: list[str] | None = None, pads: bool = False) -> dict[str, np.ndarray]:
        """Copy device arrays to the host in FIELDS shapes (a synchronisation: do it only at output times);
        ``pads``: with the last block's pads after the n points (blocks x LANES rows)."""
        rows = self.blocks * LANES if pads else self.n
        return {k: _field(k, from_blocks(self.arrays[k].to_numpy(), rows)) for k in (names or list(FIELDS))}


# ---------------------------------------------------------------- one point of the block arrays
@ti.func
def get_scalar(a: ti.template(), p):
    """Point p's value of a one-component field."""
    return a[p // LANES, 0][p % LANES]


@ti.func
def set_scalar(a: ti.template(), p, value):
    a[p // LANES, 0][p % LANES] = value


@ti.func
def get_vec2(a: ti.template(), p):
    """Point p's (x, z) vector (x, v)."""
    b, k = p // LANES, p % LANES
    return ti.Vector([a[b, 0][k], a[b, 1][k]])


@ti.func
def set_vec2(a: ti.template(), p, value):
    b, k = p // LANES, p % LANES
    a[b, 0][k], a[b, 1][k] = value[0], value[1]


@ti.func
def get_mat2(a: ti.template(), p):
    """Point p's 2 x 2 matrix stored row by row (C)."""
    b, k = p // LANES, p % LANES
    return ti.Matrix([[a[b, 0][k], a[b, 1][k]], [a[b, 2][k], a[b, 3][k]]])


@ti.func
def set_mat2(a: ti.template(), p, value):
    b, k = p // LANES, p % LANES
    a[b, 0][k], a[b, 1][k], a[b, 2][k], a[b, 3][k] = value[0, 0], value[0, 1], value[1, 0], value[1, 1]


@ti.func
def get_sym2(a: ti.template(), p):
    """Point p's symmetric 2 x 2 matrix from its (xx, zz, xz) components (sigma)."""
    b, k = p // LANES, p % LANES
    return ti.Matrix([[a[b, XX][k], a[b, XZ][k]], [a[b, XZ][k], a[b, ZZ][k]]])


@ti.func
def set_sym2(a: ti.template(), p, value):
    """Store a symmetric matrix's (xx, zz, xz) (its [0, 1] entry as xz)."""
    b, k = p // LANES, p % LANES
    a[b, XX][k], a[b, ZZ][k], a[b, XZ][k] = value[0, 0], value[1, 1], value[0, 1]


@ti.func
def chunk_blocks(c, n_chunks, blocks):
    """Blocks [first, end) of chunk c of n_chunks (a whole number of blocks each, so that a chunk's
    vectorised loop and its one-point loop cover the same points)."""
    return c * blocks // n_chunks, (c + 1) * blocks // n_chunks


def split_points(arrays: dict[str, np.ndarray], spacing: float, factor: int) -> dict[str, np.ndarray]:
    """Each point -> factor^2 points on a sub-lattice of its (undeformed) spacing, for finer cells.

    x_child = x + d, d on a factor x factor lattice of step spacing / factor centred on x;
    mass and volume are shared out equally; v_child = v + C d (the APIC field at the child), so
    mass, momentum and the centre of mass are kept; C, stress and plastic strain are copied.
    """
    if factor < 1 or int(factor) != factor:
        raise ValueError(f"factor must be a positive integer, got {factor!r}")
    if not spacing > 0:
        raise ValueError(f"spacing must be > 0, got {spacing!r}")
    frac = (np.arange(factor) + 0.5) / factor - 0.5
    offsets = spacing * np.array([(a, b) for a in frac for b in frac])  # (factor^2, 2)
    n, k = len(arrays["x"]), len(offsets)
    out = {name: np.repeat(np.asarray(a), k, axis=0) for name, a in arrays.items()}
    d = np.tile(offsets, (n, 1))
    out["x"] = out["x"] + d
    if "C" in out and "v" in out:
        out["v"] = out["v"] + np.einsum("nij,nj->ni", out["C"], d)
    for name in ("mass", "vol"):
        if name in out:
            out[name] = out[name] / k
    return out
