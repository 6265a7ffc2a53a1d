"""Every private Taichi API intrusim uses, imported here and only here, for the tested Taichi minor version.

The step graph (:mod:`intrusim.mpm.step_graph`) compiles kernels into a ``ti.graph`` itself and binds
ndarrays and vectors the way ``Graph.run`` takes them; the backend (:mod:`intrusim.mpm.backend`)
switches the matrix scalarisation option while a kernel compiles and reads the arch in use. None of
these is public Taichi API, so a Taichi outside the tested minor version is refused on import with
a message, not left to fail deep in a step (pyproject.toml pins the same range).
"""

from __future__ import annotations

import taichi as ti

TESTED = (1, 7)  # the Taichi minor version these private APIs are used with

if tuple(ti.__version__[:2]) != TESTED:  # pragma: no cover - the pin keeps other versions out
    raise ImportError(
        f"intrusim.mpm needs Taichi {TESTED[0]}.{TESTED[1]}.x (it uses private Taichi APIs), "
        f"found {'.'.join(map(str, ti.__version__))}: pip install 'taichi>=1.7.4,<1.8'"
    )

from taichi.graph._graph import gen_cpp_kernel  # noqa: E402
from taichi.lang import impl  # noqa: E402
from taichi.lang._ndarray import Ndarray  # noqa: E402
from taichi.lang.matrix import Matrix, MatrixType  # noqa: E402


def current_cfg():
    """Taichi's live compile configuration (``real_matrix_scalarize``, ``arch``)."""
    return impl.current_cfg()


def program():
    """Taichi's runtime program (compiles a graph's kernels)."""
    return impl.get_runtime().prog


def free_ndarrays(arrays) -> None:
    """Free these ndarrays' memory now; they must not be used after this. Taichi 1.7 frees a vector
    or matrix ndarray only at ``ti.reset`` (taichi-dev/taichi#8763: only the scalar ndarray frees
    itself when collected), so arrays replaced during a run (the points after an outflow or a
    treadmill shift, a contact's per-point scratch) would be kept for the process's life: a silo with
    outflow at 2.5 mm cells reached 24 GB. An ndarray whose class frees itself is left to it."""
    prog = program()
    if prog is None:
        return
    ti.sync()  # no kernel still to run on them (an asynchronous device)
    for a in arrays:
        if a is not None and getattr(type(a), "__del__", None) is None:
            prog.delete_ndarray(a.arr)


__all__ = ["Matrix", "MatrixType", "Ndarray", "current_cfg", "free_ndarrays", "gen_cpp_kernel", "program"]
