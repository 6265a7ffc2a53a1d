"""Input checks shared by the whole package: fail early, name the parameter, never return NaN."""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from intrusim.errors import InputError  # noqa: F401 - kept importable from here (one class)


def finite(name: str, value: Any) -> float:
    """Return ``value`` as a float, or raise :class:`InputError` if it is not a finite number."""
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise InputError(f"{name} must be a number, got {value!r}") from None
    if not math.isfinite(v):
        raise InputError(f"{name} must be finite, got {value!r}")
    return v


def positive(name: str, value: Any) -> float:
    """A finite number > 0."""
    v = finite(name, value)
    if v <= 0.0:
        raise InputError(f"{name} must be > 0, got {value!r}")
    return v


def non_negative(name: str, value: Any) -> float:
    """A finite number >= 0."""
    v = finite(name, value)
    if v < 0.0:
        raise InputError(f"{name} must be >= 0, got {value!r}")
    return v


def positive_int(name: str, value: Any) -> int:
    """An integer >= 1."""
    if isinstance(value, bool) or int(value) != value:
        raise InputError(f"{name} must be an integer, got {value!r}")
    if int(value) < 1:
        raise InputError(f"{name} must be >= 1, got {value!r}")
    return int(value)


def finite_array(name: str, value: Any, shape_tail: tuple[int, ...] = ()) -> np.ndarray:
    """A float64 array of finite numbers whose trailing dimensions are ``shape_tail``."""
    a = np.asarray(value, dtype=float)
    if shape_tail and a.shape[a.ndim - len(shape_tail) :] != shape_tail:
        raise InputError(f"{name} must have trailing shape {shape_tail}, got {a.shape}")
    if not np.all(np.isfinite(a)):
        raise InputError(f"{name} contains non-finite values")
    return a
