"""Input checks shared by the whole package: fail early, name the parameter, never return NaN."""

from __future__ import annotations

import math
import os
import tempfile
from pathlib import Path
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


def check_writable(folder: str | Path, flag: str = "--out") -> None:
    """Refuse (InputError) an output folder that cannot be made or written, before any compute;
    nothing is left behind (a file is made and removed in the folder, or in its nearest existing
    parent when the folder is still to be made)."""
    folder = Path(folder)
    if folder.exists() and not folder.is_dir():
        raise InputError(f"{flag} {folder} is a file, not a folder")
    place = folder
    while not place.exists() and place != place.parent:
        place = place.parent
    if not place.is_dir():
        raise InputError(f"{flag} {folder} cannot be made: {place} is a file")
    try:
        fd, probe = tempfile.mkstemp(dir=place, prefix=".intrusim-write-test-")
        os.close(fd)
        os.unlink(probe)
    except OSError as err:
        raise InputError(f"{flag} {folder} is not writable ({place}: {err.strerror or err})") from None


def check_workers(workers: int | None, flag: str = "--workers") -> None:
    """Refuse (InputError) a count of processes below 1 or above this machine's cores (None: not given)."""
    if workers is None:
        return
    cores = os.cpu_count() or 1
    if workers < 1:
        raise InputError(f"{flag} must be >= 1, got {workers}")
    if workers > cores:
        raise InputError(f"{flag} {workers} is more than this machine's {cores} cores")
