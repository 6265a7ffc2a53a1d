"""Material points: struct-of-arrays state held in Taichi ndarrays (2D plane strain, per unit width)."""

from __future__ import annotations

import numpy as np
import taichi as ti

from .backend import info

#: name -> (shape suffix, description with unit); order defines the checkpoint layout
FIELDS: dict[str, tuple[tuple[int, ...], str]] = {
    "x": ((2,), "position (x, z), m"),
    "v": ((2,), "velocity, m/s"),
    "C": ((2, 2), "APIC affine matrix = velocity gradient dv_i/dx_j, 1/s"),
    "mass": ((), "mass per unit width, kg/m"),
    "vol": ((), "area (volume per unit width), m^2"),
    "sigma": ((2, 2), "in-plane Cauchy stress, Pa"),
    "s_yy": ((), "out-of-plane normal stress, Pa"),
    "eps_p": ((), "equivalent plastic shear strain, -"),
    "gdot_p": ((), "equivalent plastic shear strain rate, 1/s"),
}


class Particles:
    """Particle arrays on the Taichi device.

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
        self.arrays: dict[str, ti.Ndarray] = {}
        for name, (shape, _) in FIELDS.items():
            if shape == ():
                arr = ti.ndarray(real, shape=self.n)
            elif len(shape) == 1:
                arr = ti.Vector.ndarray(shape[0], real, shape=self.n)
            else:
                arr = ti.Matrix.ndarray(shape[0], shape[1], real, shape=self.n)
            self.arrays[name] = arr
        self.load({k: data.get(k, np.zeros((self.n, *FIELDS[k][0]))) for k in FIELDS})

    def __getattr__(self, name: str):
        arrays = self.__dict__.get("arrays", {})
        if name in arrays:
            return arrays[name]
        raise AttributeError(name)

    def load(self, data: dict[str, np.ndarray]) -> None:
        """Copy host arrays into the device arrays."""
        dtype = info().np_real
        for name, arr in data.items():
            self.arrays[name].from_numpy(np.ascontiguousarray(arr, dtype=dtype))

    def to_numpy(self, names: list[str] | None = None) -> dict[str, np.ndarray]:
        """Copy device arrays to the host (a synchronisation: do it only at output times)."""
        return {k: self.arrays[k].to_numpy() for k in (names or list(FIELDS))}


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
