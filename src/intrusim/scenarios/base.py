"""Pieces shared by the scenario configs: force-model settings, run control, TOML loading.

Scenarios are data: pydantic v2 models, validated on construction, loadable from TOML
(``from_toml(path)``). The shipped defaults are built from :func:`intrusim.params.table_s1`, the
single source of truth for the paper's numbers.
"""

from __future__ import annotations

import math
import os
import tomllib
from pathlib import Path
from typing import Any, Literal

from pydantic import BaseModel, ConfigDict, Field, ValidationError, model_validator

from intrusim._checks import InputError, positive_int
from intrusim.errors import validation_message
from intrusim.forces import ModelKind, ResistiveForceModel, make_force_model
from intrusim.geometry import Shape
from intrusim.laws.drft import free_surface_law
from intrusim.laws.rft import load_coefficients
from intrusim.params import GRAVITY
from intrusim.validation import reject_bool_numbers

ALL_KINDS: tuple[str, ...] = ("rft", "drft-inertial", "drft")


class Config(BaseModel):
    """Base of every config: unknown keys are errors, values are validated on assignment."""

    # finite numbers only (inf and NaN are refused, naming the field); true/false are not numbers
    model_config = ConfigDict(extra="forbid", validate_assignment=True, frozen=False, allow_inf_nan=False)

    _no_bool_numbers = model_validator(mode="before")(classmethod(reject_bool_numbers))

    @classmethod
    def from_toml(cls, path: str | Path) -> "Config":
        """Load and validate a config from a TOML file (errors name the offending field)."""
        p = Path(path)
        if not p.is_file():
            raise InputError(f"scenario file not found: {p}")
        with p.open("rb") as f:
            try:
                data = tomllib.load(f)
            except tomllib.TOMLDecodeError as err:
                raise InputError(f"{p}: invalid TOML ({err})") from None
        return cls.from_dict(cls._file_defaults(_paths_relative_to(data, p.parent), p), source=str(p))

    @classmethod
    def _file_defaults(cls, data: dict[str, Any], path: Path) -> dict[str, Any]:
        """A hook for values a file's own name or place gives (a body's name: the file's stem)."""
        return data

    def validated_copy(self, **update: Any) -> "Config":
        """A copy with ``update`` applied, validated as a new instance (field and model validators
        included; ``model_copy(update=...)`` validates nothing)."""
        return type(self).model_validate({**self.model_dump(), **update})

    @classmethod
    def from_dict(cls, data: dict[str, Any], source: str = "config") -> "Config":
        try:
            return cls.model_validate(data)
        except ValidationError as err:
            raise InputError(f"{source}: invalid {cls.__name__}: {validation_message(err)}") from None


def _paths_relative_to(data: dict[str, Any], folder: Path) -> dict[str, Any]:
    """``data`` with its file paths (``force_model.rft_coefficients``) read relative to ``folder``
    (the TOML's own), as a file's paths are; absolute paths are kept."""
    fm = data.get("force_model")
    path = fm.get("rft_coefficients") if isinstance(fm, dict) else None
    if not isinstance(path, str) or Path(path).is_absolute():
        return data
    return {**data, "force_model": {**fm, "rft_coefficients": os.path.normpath(folder / path)}}


class ForceModelConfig(Config):
    """Parameters of the RFT / DRFT force model (paper, Eqs. 3-4).

    Attributes
    ----------
    xi : media scaling coefficient of the Li (2013) fit (poppy seeds 0.35, Table S1).
    rho : media density of the inertial correction, kg/m^3 (rho_c = 638 for poppy seeds).
    lam : lambda of the inertial correction (wheel 1; runner 0, 2 or 4; plate drag 1.1).
    structural : dynamic structural correction: "wheel-rear-half" (wheels), "none", or
        "wheel-rear-half-effective" (the contact arc ends at the lowered rear surface), or
        "wheel-rear-half-circle" (the same, with the arc's ends on the wheel's outer circle).
    psi_slope, psi_offset : free-surface law of the structural correction,
        dh = r psi(r omega^2 / g) with psi(x) = psi_offset + psi_slope x (dimensionless; the
        paper: the identity, 1 and 0; fitted on MPM by :mod:`intrusim.analysis.calibration`).
    rft_coefficients : file of an RFT coefficient table (TOML or JSON, N/cm^3, laid out as
        ``data/rft_li2013.toml``; e.g. one measured on the MPM medium by
        ``examples/mpm_rft_map.py``), scaled by xi. None: the generic Li (2013) fit.
    bulldozing : k_b of a body-level bulldozing resistance k_b (1/2) K_p rho g W d^2 against the
        body's travel, d the depth of its outer circle (:mod:`intrusim.laws.bulldozing`). Not in
        the paper: 0 (default) leaves RFT / DRFT as published; fitted on MPM by
        :mod:`intrusim.analysis.calibration`.
    internal_friction : mu = tan(phi) of the medium, for the bulldozing term's Rankine K_p
        (Table S1: 0.56).
    zone_width : rad, the angular band across which the wheel's lowered rear surface rises from -dh
        to 0 (``laws.drft.zone_weight``). Not in the paper: 0 (default) is its sharp split.
    """

    xi: float = Field(0.35, ge=0.0)
    rho: float = Field(638.0, ge=0.0)
    lam: float = Field(1.0, ge=0.0)
    structural: Literal["none", "wheel-rear-half", "wheel-rear-half-effective", "wheel-rear-half-circle"] = "none"
    psi_slope: float = Field(1.0, ge=0.0, allow_inf_nan=False)
    psi_offset: float = Field(0.0, allow_inf_nan=False)
    rft_coefficients: str | None = None
    bulldozing: float = Field(0.0, ge=0.0, allow_inf_nan=False)
    internal_friction: float = Field(0.56, ge=0.0, allow_inf_nan=False)
    zone_width: float = Field(0.0, ge=0.0, le=math.pi, allow_inf_nan=False)


GOLDEN_FRACTION = 0.5 * (math.sqrt(5.0) - 1.0)  # 0.618...: the fraction farthest from any ratio of small whole numbers


class RunConfig(Config):
    """Time integration and steady-state window of a locomotion run.

    The run lasts ramp_time + settle_time + average_revolutions * (2 pi / omega); the steady
    state is the average over the last ``average_revolutions`` whole revolutions (so a
    non-round body, whose long-time motion is a limit cycle, is averaged over whole cycles).

    Attributes
    ----------
    ramp_time : s, linear spin-up of omega from rest.
    settle_time : s, extra time after the ramp for transients to decay (RFT has no memory; the
        slowest transient is the horizontal one, m_x / (dF_x/dv_x), a fraction of a second).
    average_revolutions : whole revolutions averaged over (>= 1).
    dt_max : s, largest time step.
    steps_per_revolution : the step is also at most one revolution / steps_per_revolution.
        Within those bounds :meth:`dt` takes the largest step with a whole number plus the golden
        fraction 0.618 of steps per lug pitch, so that successive lugs meet the medium at
        different phases of a step.
    initial_sinkage : m, initial depth of the lowest outline point (0 = resting on the surface).
    drift_tol : the run is extended by ``average_revolutions`` more revolutions while the window's
        drift (relative change of mean speed, or of mean sinkage over the radius, between its two
        halves) exceeds this.
    max_extensions : most extensions before giving up (the result is then flagged unsettled).
    """

    ramp_time: float = Field(0.5, ge=0.0)
    settle_time: float = Field(1.5, ge=0.0)
    average_revolutions: int = Field(2, ge=1)
    dt_max: float = Field(0.01, gt=0.0)
    steps_per_revolution: int = Field(72, ge=8)
    initial_sinkage: float = Field(0.0, ge=0.0)
    drift_tol: float = Field(5e-4, gt=0.0)
    max_extensions: int = Field(20, ge=0)

    def period(self, omega: float) -> float:
        """One revolution at |omega| rad/s, s."""
        return 2.0 * math.pi / abs(omega)

    def duration(self, omega: float) -> float:
        """Total simulated time at |omega| rad/s, s."""
        return self.ramp_time + self.settle_time + self.average_revolutions * self.period(omega)

    def dt(self, omega: float, symmetry: int = 1) -> float:
        """Time step at |omega| rad/s for a body that repeats ``symmetry`` times a turn, s.

        The period / dt steps per revolution are the fewest >= max(steps_per_revolution,
        period / dt_max) that put k + 0.618 (k whole, 0.618 the golden fraction) steps in each of
        the ``symmetry`` lug pitches. With a whole number of steps per pitch every lug would enter
        the medium at the same phase of a step and the steady state would lock onto that phase:
        at 5 steps per pitch (the paper's 100 steps a revolution, 20 grousers) the Table S1
        wheel's speed is 1.6 % low at 90 RPM; at 3.618, 4.618 or 5.618 steps per pitch it is
        within 0.15 % of the dt -> 0 answer (docs/locomotion.md).
        """
        period = self.period(omega)
        n = positive_int("symmetry", symmetry)
        per_pitch = max(self.steps_per_revolution, period / self.dt_max) / n
        return period / (n * (math.ceil(per_pitch - GOLDEN_FRACTION) + GOLDEN_FRACTION))


class ModelKindsMixin(Config):
    """Which force-model kinds a scenario supports, and how to build its model."""

    supported_models: tuple[str, ...] = ALL_KINDS
    force_model: ForceModelConfig = Field(default_factory=ForceModelConfig)

    @model_validator(mode="after")
    def _kinds_known(self) -> "ModelKindsMixin":
        bad = [k for k in self.supported_models if k not in ALL_KINDS]
        if bad:
            raise ValueError(f"unknown force-model kinds {bad}; known: {list(ALL_KINDS)}")
        return self

    def rft_shape(self) -> Shape:  # pragma: no cover - abstract
        raise NotImplementedError

    def build_model(self, kind: ModelKind, lam: float | None = None) -> ResistiveForceModel:
        """The force model of ``kind`` with this scenario's parameters (``lam`` overrides lambda)."""
        if kind not in self.supported_models:
            raise InputError(
                f"scenario {getattr(self, 'name', '?')!r} supports force models {list(self.supported_models)}, got {kind!r}"
            )
        fm = self.force_model
        lam_v = fm.lam if lam is None else lam
        if lam_v < 0 or not math.isfinite(lam_v):
            raise InputError(f"lambda must be a finite number >= 0, got {lam!r}")
        psi = free_surface_law(fm.psi_slope, fm.psi_offset)
        coef = None if fm.rft_coefficients is None else load_coefficients(fm.rft_coefficients)
        return make_force_model(
            kind,
            self.rft_shape(),
            xi=fm.xi,
            rho=fm.rho,
            lam=lam_v,
            structural=fm.structural,
            psi=psi,
            coef=coef,
            bulldozing=fm.bulldozing,
            mu=fm.internal_friction,
            gravity=getattr(self, "gravity", GRAVITY),
            zone_width=fm.zone_width,
        )
