"""The paper's tables as data: one source of truth for Table S1 and the Li (2013) RFT fit.

The TOML files in ``intrusim/data`` are copies of ``shared/reference``; SI units throughout.
"""

from __future__ import annotations

import math
import tomllib
from functools import lru_cache
from importlib import resources
from typing import Any

GRAVITY = 9.8  # m/s^2, Table S1 (printed as "9.8 kg/m^2")
RPM = 2.0 * math.pi / 60.0  # rad/s per RPM


@lru_cache(maxsize=None)
def _load(name: str) -> dict[str, Any]:
    with resources.files("intrusim.data").joinpath(name).open("rb") as f:
        return tomllib.load(f)


def table_s1() -> dict[str, Any]:
    """Table S1 of the paper (wheel and runner dimensions, poppy-seed properties), SI units."""
    return _load("table_s1.toml")


def li2013_coefficients() -> dict[str, Any]:
    """The generic Li-Zhang-Goldman (2013) Fourier coefficients, in N/cm^3 as published."""
    return _load("rft_li2013.toml")
