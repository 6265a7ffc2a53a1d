"""Lazy, once-per-process initialisation of the Taichi backend.

Taichi can be initialised only once per process in practice (re-initialising destroys every
field and ndarray). All MPM objects call :func:`ensure_initialized` before allocating memory;
the first call wins and later calls with a different request only warn.
"""

from __future__ import annotations

import os
import warnings
from contextlib import contextmanager
from dataclasses import asdict, dataclass, fields

import taichi as ti

from ._taichi_private import current_cfg

ARCHES = ("cpu", "cuda", "vulkan", "metal", "gpu")
PRECISIONS = ("f32", "f64")


@dataclass(frozen=True)
class BackendInfo:
    """What Taichi was initialised with: ``arch`` is the backend in use ("cpu", "cuda", "vulkan"
    or "metal"), ``requested`` the one asked for (Taichi falls back to the CPU when the requested
    GPU backend is missing)."""

    arch: str
    precision: str
    cpu_threads: int | None
    requested: str = ""

    @property
    def fell_back(self) -> bool:
        """True when a GPU was asked for and Taichi runs on the CPU instead."""
        return self.requested not in ("", "cpu") and self.arch == "cpu"

    @property
    def real(self):
        """Taichi dtype of the particle and grid arrays."""
        return ti.f64 if self.precision == "f64" else ti.f32

    @property
    def np_real(self) -> str:
        return "float64" if self.precision == "f64" else "float32"


@dataclass(frozen=True)
class BenchmarkSwitches:
    """Internal: the other code paths of the MPM step, kept as references for the benchmarks and the
    tests that compare them with the default (``Solver(cfg, switches=BenchmarkSwitches(...))``).

    Not settings of a run: they are no fields of :class:`~intrusim.mpm.config.MPMConfig` (a run's
    TOML that names one is refused, :data:`~intrusim.mpm.config.REMOVED_BACKEND_KEYS`). A run folder
    or checkpoint written while they were ``backend`` settings still loads: there they are read as the
    switches of its run (:func:`intrusim.mpm.io.split_switches`), and a run made with switches other
    than the defaults records them beside its configuration (``"switches"``), so it resumes on them.

    step_graph : the kernels of a step launched as one compiled Taichi graph (arguments bound in
        C++: ~0.1 ms instead of ~0.7 ms of Python per step); False: one call per kernel (the same
        numbers bit for bit, ``test_mpm_step_graph.py``).
    device_bodies : a coupled body's dynamics (prescribed omega, free x and z) in a kernel at the end
        of each step, its pose kept on the device: no read-back of the step's impulse (on a GPU, a
        wait for the device every step); False: read back and advanced on the host (the reference).
    simd_lanes : CPU: the G2P kernel (velocity, position, density, stress), the chunked P2G and the
        nonlocal fluidity's sources and relaxation compute 8 points at once as vectors (SIMD);
        False: one point per loop iteration (the reference; a GPU's always, and float64's).
    """

    step_graph: bool = True
    device_bodies: bool = True
    simd_lanes: bool = True

    def __post_init__(self):
        for f in fields(self):
            if not isinstance(getattr(self, f.name), bool):
                raise TypeError(f"BenchmarkSwitches.{f.name} must be True or False, got {getattr(self, f.name)!r}")

    def changed(self) -> dict[str, bool]:
        """The switches not at their default, by name ({} for the defaults)."""
        return {k: v for k, v in asdict(self).items() if v != getattr(DEFAULT_SWITCHES, k)}


DEFAULT_SWITCHES = BenchmarkSwitches()  # the solver's path: every run's, unless a benchmark or test asks otherwise

_INFO: BackendInfo | None = None

SERIAL_LOOPS = False
"""True when Taichi runs on one CPU thread: the hot kernels then serialise their loops.

Taichi's CPU thread pool keeps the launching thread busy (~100 % of a core) while its worker
threads run a parallel loop; with one worker, a process thus occupies two cores, and two such
processes (a sweep's 1-thread workers on 2 cores) slow each other down. A serialised loop runs
on the launching thread alone (and on one thread it is also ~15 % faster: no task dispatch).
Read by the kernels when they are compiled (after initialisation).
"""


def ensure_initialized(arch: str = "cpu", precision: str = "f32", cpu_threads: int | None = None) -> BackendInfo:
    """Initialise Taichi once for this process and return what is in use.

    Parameters
    ----------
    arch : {"cpu", "cuda", "vulkan", "metal", "gpu"}
        Requested backend; "gpu" lets Taichi pick any available GPU. A missing GPU backend falls
        back to the CPU with a RuntimeWarning (``BackendInfo.arch`` says what runs).
        ``INTRUSIM_TI_ARCH`` overrides (e.g. to run the test suite on a GPU).
    precision : {"f32", "f64"}
        Floating-point type of particle and grid arrays. Force reductions are always f64.
    cpu_threads : int, optional
        Number of CPU threads (``None``: all cores; ``INTRUSIM_TI_THREADS`` overrides).
    """
    global _INFO
    arch = os.environ.get("INTRUSIM_TI_ARCH") or arch
    if arch not in ARCHES:
        raise ValueError(f"arch must be one of {ARCHES}, got {arch!r} (INTRUSIM_TI_ARCH or the caller's)")
    if precision not in PRECISIONS:
        raise ValueError(f"precision must be one of {PRECISIONS}, got {precision!r}")
    env_threads = os.environ.get("INTRUSIM_TI_THREADS")
    if env_threads:
        cpu_threads = int(env_threads)
    if _INFO is not None:
        if (arch, precision) != (_INFO.requested, _INFO.precision) and (arch, precision) != (
            _INFO.arch,
            _INFO.precision,
        ):
            warnings.warn(
                f"Taichi already initialised with arch={_INFO.arch}, precision={_INFO.precision}; "
                f"ignoring request arch={arch}, precision={precision}",
                stacklevel=2,
            )
        return _INFO
    kwargs = dict(
        arch=getattr(ti, arch),
        default_fp=ti.f64 if precision == "f64" else ti.f32,
        log_level=ti.WARN,
        offline_cache=True,
    )
    if cpu_threads is not None:
        kwargs["cpu_max_num_threads"] = int(cpu_threads)
    ti.init(**kwargs)
    actual = arch_in_use()
    if arch != "cpu" and actual == "cpu":  # Taichi's own message is a log line that is easy to miss
        warnings.warn(
            f"arch={arch} was requested but Taichi found no such device: running on the CPU",
            RuntimeWarning,
            stacklevel=2,
        )
    global SERIAL_LOOPS
    SERIAL_LOOPS = actual == "cpu" and cpu_threads == 1
    _INFO = BackendInfo(arch=actual, precision=precision, cpu_threads=cpu_threads, requested=arch)
    return _INFO


@contextmanager
def unscalarized():
    """Kernels compiled inside keep Taichi's vectors as vectors (``real_matrix_scalarize`` off).

    Taichi splits every vector and matrix into scalars before code generation by default; with the
    option off a vector of 8 floats is one LLVM vector, i.e. SIMD code on the CPU. The option is
    global and read when a kernel compiles, so it is switched for that moment only: most kernels do
    not compile without it (Taichi 1.7 rejects a unary minus or a cast on such a vector). Taichi's
    key for a compiled kernel (in memory and in its offline cache on disk) leaves the option out, so
    whichever form is compiled first is the one every later call and graph runs: a kernel meant to
    run unscalarised must be compiled under this switch the first time (``step_graph`` does it). See
    ``transfer.g2p_kernel(..., lanes=True)``.
    """
    cfg = current_cfg()
    before = cfg.real_matrix_scalarize
    cfg.real_matrix_scalarize = False
    try:
        yield
    finally:
        cfg.real_matrix_scalarize = before


def arch_in_use() -> str:
    """The backend Taichi runs on ("cpu", "cuda", "vulkan", "metal", ...), read from Taichi itself."""
    arch = current_cfg().arch
    return "cpu" if arch in (ti.x64, ti.arm64) else arch.name


def info() -> BackendInfo:
    """Backend in use (initialising the default one if needed)."""
    return _INFO if _INFO is not None else ensure_initialized()
