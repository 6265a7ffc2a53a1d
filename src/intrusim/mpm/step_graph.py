"""Kernel launches of an MPM step, direct or as one compiled Taichi graph.

A Taichi 1.7 kernel call spends ~20-30 us of Python per ndarray argument (type checks, the
compiled-kernel lookup, one binding call per argument). A step passes ~28 ndarrays (0.6-0.8 ms
per step on the 2-core machine, while the worker threads wait), so the solver records its
launches once in a ``ti.graph`` and replays them with a single call that binds the arguments
in C++ (measured: 3 kernels of 11 arguments, 650 us as calls, 97 us as a graph).

A step is a list of :class:`Launch` (kernel, arguments); an argument that changes from step to
step (a body's pose, its node box) is a :class:`Var` with a name, the rest are constants bound
once. :func:`run_direct` calls the kernels one by one (the reference path); :class:`StepGraph`
replays them.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Sequence

import taichi as ti

from ._taichi_private import Matrix, MatrixType, Ndarray, gen_cpp_kernel, program
from .backend import info, unscalarized


@dataclass(frozen=True)
class Var:
    """A kernel argument whose value is given at each run, under ``name``."""

    name: str


@dataclass(frozen=True)
class Launch:
    """One kernel launch: a Taichi kernel (no ``ti.template()`` parameters) and its arguments.

    ``unscalarized``: the kernel computes on vectors over points (``transfer.g2p_kernel(..., lanes=True)``) and
    is compiled without Taichi's scalarisation of vectors (``backend.unscalarized``).
    """

    kernel: Any
    args: tuple
    unscalarized: bool = False


def run_direct(launches: Sequence[Launch], values: dict[str, Any]) -> None:
    """Call each kernel with its arguments (``Var`` replaced by ``values[name]``)."""
    for launch in launches:
        args = [values[a.name] if isinstance(a, Var) else a for a in launch.args]
        if launch.unscalarized:  # compiled at its first call, with the config of that moment
            with unscalarized():
                launch.kernel(*args)
        else:
            launch.kernel(*args)


class StepGraph:
    """The launches of a step compiled into one Taichi graph.

    Parameters
    ----------
    launches : the kernels in order; their constant arguments are bound for the graph's life.
    values : a value of each ``Var`` (only its type is used here).
    """

    def __init__(self, launches: Sequence[Launch], values: dict[str, Any]):
        self._symbols: dict[str, Any] = {}
        self._values: dict[str, Any] = {}  # the constants, then each run's Var values
        builder = ti.graph.GraphBuilder()
        for k, launch in enumerate(launches):
            symbols = self._bind(k, launch, values)
            if launch.unscalarized:
                # a graph compiles its kernels at its first run, with the config of that moment, and
                # looks them up by kernel and config; Taichi's key of a config leaves this option out,
                # so the kernel compiled here, unscalarised, is the one the graph finds and runs
                prog = program()
                with unscalarized():
                    prog.compile_kernel(prog.config(), prog.get_device_caps(), gen_cpp_kernel(launch.kernel, symbols))
            builder.dispatch(launch.kernel, *symbols)
        self._graph = builder.compile()

    def _bind(self, k: int, launch: Launch, values: dict[str, Any]) -> list:
        """The graph symbols of launch k's arguments (one per array, shared by kernels); records the
        constants' values."""
        params = launch.kernel._primal.arguments
        if len(params) != len(launch.args):
            raise TypeError(f"{launch.kernel.__name__}: {len(launch.args)} arguments for {len(params)} parameters")
        symbols = []
        for j, (param, arg) in enumerate(zip(params, launch.args)):
            if isinstance(arg, Var):
                name, value = arg.name, values[arg.name]
            elif isinstance(arg, Ndarray):
                name, value = f"nd{id(arg)}", arg  # one symbol per array, shared by kernels
            else:
                name, value = f"k{k}_{j}", arg
            if name not in self._symbols:
                self._symbols[name] = _symbol(name, param.annotation, value)
                if not isinstance(arg, Var):
                    self._values[name] = _runtime_value(param.annotation, value)
            symbols.append(self._symbols[name])
        return symbols

    def run(self, values: dict[str, Any]) -> None:
        """Launch the step with this step's ``Var`` values (names as given at construction)."""
        self._values.update(values)
        self._graph.run(self._values)


def _symbol(name: str, annotation, value):
    """The graph argument for a kernel parameter (its annotation) bound to ``value``."""
    kind = ti.graph.ArgKind
    annotation = _concrete(annotation)
    if isinstance(value, Ndarray):
        shape = tuple(getattr(value, "element_shape", ()) or ())
        dtype = value.dtype
        if len(shape) == 1:
            dtype = ti.types.vector(shape[0], dtype)
        elif len(shape) == 2:
            dtype = ti.types.matrix(shape[0], shape[1], dtype)
        return ti.graph.Arg(kind.NDARRAY, name, dtype, ndim=len(value.shape))
    if isinstance(annotation, MatrixType):
        return ti.graph.Arg(kind.MATRIX, name, annotation)
    if annotation is float:
        return ti.graph.Arg(kind.SCALAR, name, info().real)
    if annotation is int:
        return ti.graph.Arg(kind.SCALAR, name, ti.i32)
    return ti.graph.Arg(kind.SCALAR, name, annotation)


def _concrete(annotation):
    """A vector/matrix annotation with Python ``float`` elements as the backend's real type."""
    if not isinstance(annotation, MatrixType) or annotation.dtype is not float:
        return annotation
    if annotation.ndim == 1:
        return ti.types.vector(annotation.n, info().real)
    return ti.types.matrix(annotation.n, annotation.m, info().real)


def _runtime_value(annotation, value):
    """A constant argument as ``Graph.run`` takes it (vectors as ti.Matrix)."""
    if isinstance(annotation, MatrixType) and not isinstance(value, Matrix):
        return Matrix(list(value), dt=_concrete(annotation).dtype)
    return value
