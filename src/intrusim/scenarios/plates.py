"""Plates at a set speed: horizontal drag (Fig 6) and vertical push (Fig S3B).

A plate moves at a prescribed constant velocity at a set depth; RFT/DRFT have no memory, so the
force is a function of (depth, velocity) alone: no integration is needed. The paper's MPM
results follow F = K |z| + lambda rho A v^2 (A = plate area); :func:`drag_force_table` gives the
DRFT force over a (depth, speed) grid and :func:`intrusim.analysis.plates.fit_static_plus_inertial`
recovers K and lambda from it.

* :func:`plate_drag_scenario` (Fig 6): a VERTICAL plate (normal along the motion, as in the
  Coulomb-wedge picture of Fig 6B) of length 0.016 m, dragged horizontally at 0.04-0.64 m/s with
  its centre 20, 30, 40 mm deep; rho = 900 kg/m^3 (printed "900 kg/m^2", taken as a volume
  density); plane strain, so W = 1 m and forces are per metre of width; lambda = 1.1;
  inertial correction only. The paper's fit: K = 580 N/m, lambda = 1.1.
* :func:`vertical_plate_scenario` (Fig S3B): a HORIZONTAL plate of length 0.16 m pushed straight
  down; rho = 2500 kg/m^3 (printed as the granular volume density); lambda = 2.8.

Depth is the depth of the plate centre below the free surface z = 0 (m).
"""

from __future__ import annotations

import math
from typing import Literal

import numpy as np
from pydantic import Field

from intrusim._checks import InputError
from intrusim.geometry import Shape, plate
from intrusim.kinematics import BodyState
from intrusim.params import table_s1
from intrusim.scenarios.base import ForceModelConfig, ModelKindsMixin


class PlateScenario(ModelKindsMixin):
    """A thin plate moved at constant velocity at set depths.

    Attributes (SI)
    ---------------
    name : label.
    motion : "drag" (horizontal, towards +x) or "push" (vertical, towards -z).
    plate_length : m.
    width : m, out-of-plane (1 m: plane strain, forces per metre).
    angle : rad, plate tilt from +x (pi/2 = vertical plate).
    n_elements : RFT elements per face.
    depths : m, depths of the plate centre.
    speeds : m/s, speeds of the sweep.
    paper_K : N/m, the paper's static coefficient (None if not reported).
    paper_lambda : the paper's lambda.
    """

    name: str
    motion: Literal["drag", "push"]
    plate_length: float = Field(gt=0.0)
    width: float = Field(1.0, gt=0.0)
    angle: float = 0.0
    n_elements: int = Field(20, ge=1)
    depths: list[float]
    speeds: list[float]
    paper_K: float | None = None
    paper_lambda: float | None = None

    def rft_shape(self) -> Shape:
        return plate(self.plate_length, self.width, self.angle, n_elements=self.n_elements)

    @property
    def area(self) -> float:
        """Plate area A = length x width, m^2."""
        return self.plate_length * self.width

    def state(self, depth: float, speed: float) -> BodyState:
        """Plate centre ``depth`` m below the surface, moving at ``speed`` m/s (drag: +x, push: -z)."""
        if depth <= 0 or speed <= 0 or not (math.isfinite(depth) and math.isfinite(speed)):
            raise InputError(f"depth and speed must be > 0, got depth={depth!r}, speed={speed!r}")
        if self.motion == "drag":
            return BodyState(0.0, -depth, 0.0, speed, 0.0, 0.0)
        return BodyState(0.0, -depth, 0.0, 0.0, -speed, 0.0)


def plate_drag_scenario() -> PlateScenario:
    """Fig 6: vertical plate dragged horizontally, DRFT inertial correction with lambda = 1.1."""
    p, ps = table_s1()["plate_drag"], table_s1()["poppy_seeds"]
    lo, hi = p["speeds"]
    return PlateScenario(
        name="plate_drag", motion="drag", plate_length=p["plate_length"], width=1.0, angle=0.5 * math.pi,
        depths=list(p["depths"]), speeds=list(np.geomspace(lo, hi, 5)),
        paper_K=p["K"], paper_lambda=p["lambda"], supported_models=("rft", "drft-inertial", "drft"),
        force_model=ForceModelConfig(xi=ps["rft_scaling_coefficient"], rho=p["effective_density"], lam=p["lambda"]),
    )  # fmt: skip


def vertical_plate_scenario() -> PlateScenario:
    """Fig S3B: horizontal plate pushed down, DRFT inertial correction with lambda = 2.8."""
    p, ps = table_s1()["vertical_plate"], table_s1()["poppy_seeds"]
    L = p["plate_length"]
    return PlateScenario(
        name="vertical_plate", motion="push", plate_length=L, width=1.0, angle=0.0,
        depths=[0.25 * L, 0.5 * L, 0.75 * L], speeds=list(np.geomspace(0.04, 0.64, 5)),
        paper_K=None, paper_lambda=p["lambda"], supported_models=("rft", "drft-inertial", "drft"),
        force_model=ForceModelConfig(xi=ps["rft_scaling_coefficient"], rho=p["grain_density"], lam=p["lambda"]),
    )  # fmt: skip


def drag_force_table(scenario: PlateScenario, kind: str = "drft") -> np.ndarray:
    """Resistive force along the motion (N; per metre for W = 1 m), shape (n_depths, n_speeds).

    Drag: -F_x (force opposing +x motion); push: +F_z (force opposing -z motion).
    """
    model = scenario.build_model(kind)  # type: ignore[arg-type]
    out = np.empty((len(scenario.depths), len(scenario.speeds)))
    for i, d in enumerate(scenario.depths):
        for j, v in enumerate(scenario.speeds):
            w = model.wrench(scenario.state(float(d), float(v)))
            out[i, j] = -w.fx if scenario.motion == "drag" else w.fz
    return out
