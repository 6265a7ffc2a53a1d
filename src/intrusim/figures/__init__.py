"""The paper's figures, one function each, and their registry (``intrusim reproduce NAME``).

Each figure is ``fig(out_dir, quick=False, parallel=True, runs=None, mpm=False) -> list[Path]``
(PNG plus the CSV of the plotted numbers). :data:`FIGURES` maps a figure's name to its function;
a figure's module (and with it matplotlib, or the MPM solver) is imported only when the figure is
asked for.

* :mod:`intrusim.figures.rft`: RFT / DRFT figures (Fig 4B, 5A-B, 6A, 7B-C, S1), with MPM overlays;
* :mod:`intrusim.figures.mpm`: MPM wheel figures (Fig 3A-D, 5C-D; and where the wheel bears on the grains);
* :mod:`intrusim.figures.mpm_plates`: MPM plate intrusions (Fig 6A, S3B);
* :mod:`intrusim.figures.calibration`: DRFT calibrated on MPM runs (``intrusim calibrate``).
"""

from __future__ import annotations

import importlib
from collections.abc import Callable, Iterator, Mapping
from pathlib import Path

#: figure name -> (module under intrusim.figures, function)
REGISTRY: dict[str, tuple[str, str]] = {
    "fig3ab": ("mpm", "fig3ab"),
    "fig3cd": ("mpm", "fig3cd"),
    "fig4b": ("rft", "fig4b"),
    "fig5ab": ("rft", "fig5ab"),
    "fig5c": ("mpm", "fig5c"),
    "fig5d": ("mpm", "fig5d"),
    "fig6a": ("rft", "fig6a"),
    "fig6a-mpm": ("mpm_plates", "fig6a_mpm"),
    "fig7bc": ("rft", "fig7bc"),
    "figs1": ("rft", "figs1"),
    "figs3b": ("mpm_plates", "figs3b"),
    "wheel-load": ("mpm", "wheel_load"),
}

FigureFunction = Callable[..., list[Path]]


def figure(name: str) -> FigureFunction:
    """The function of figure ``name`` (a key of :data:`REGISTRY`)."""
    if name not in REGISTRY:
        raise KeyError(f"unknown figure {name!r}; choose one of {sorted(REGISTRY)}")
    module, function = REGISTRY[name]
    return getattr(importlib.import_module(f"intrusim.figures.{module}"), function)


class _Figures(Mapping[str, FigureFunction]):
    """Read-only mapping name -> figure function, importing each figure's module on first use."""

    def __getitem__(self, name: str) -> FigureFunction:
        return figure(name)

    def __iter__(self) -> Iterator[str]:
        return iter(REGISTRY)

    def __len__(self) -> int:
        return len(REGISTRY)


FIGURES: Mapping[str, FigureFunction] = _Figures()

__all__ = ["FIGURES", "REGISTRY", "figure"]
