"""Self-propelled locomotors: the grousered wheel, the small wheel (Fig S1), the four-flap runner.

All three are a circular hub with rectangular lugs (grousers or flaps), driven at a prescribed
omega and free to translate in x and z. One config class,
:class:`LocomotorScenario`, holds the geometry, the effective inertias, the force-model
parameters and the run control; the shipped defaults come from Table S1
(:func:`intrusim.params.table_s1`):

* :func:`grousered_wheel_scenario`: Table S1 wheel; m_x = 23.0 kg, m_z = 6.3 kg; DRFT with
  xi = 0.35, rho = rho_c = 638 kg/m^3, lambda = 1, structural correction on the rear half of the
  contact arc; grouser elements at 1/3 of the true height (shadowing, paper Methods). The MPM
  runs' constant 4 N forward push compensates rig friction in MPM only, so RFT/DRFT use 0 N.
* :func:`small_wheel_scenario`: Fig S1, every length of the wheel halved, the out-of-plane width
  included. The paper keeps rho_wheel / rho_c (and mu_s, h_g / D, N) fixed, so the wheel's mass
  scales with its volume: both inertias x (1/2)^3 = 1/8 (2.875 kg and 0.7875 kg). RFT forces
  scale the same way (alpha |z| dA ~ L^3), so the scaled wheel is dynamically similar except
  for the rate terms (r omega^2 / g and rho v^2), which is what Fig S1 tests.
* :func:`four_flap_runner_scenario`: Table S1 runner, m = 10.5 kg in x and z, W = 1 m, no
  structural correction, lambda in {0, 2, 4} (Fig 7). The paper's statement that the mass
  ratio m / (rho_c l^2 W) is ~6 does not hold for these numbers: 10.5 / (638 x 0.190^2 x 1)
  = 0.46. We keep 10.5 kg as printed (Table S1) and record the inconsistency in
  docs/locomotion.md.
"""

from __future__ import annotations

import math
import sys
from pathlib import Path
from typing import Any, Literal

import numpy as np
from pydantic import Field, PrivateAttr, model_validator

from intrusim._checks import InputError, finite, positive_int
from intrusim.bodies import Drive, RigidBody
from intrusim.geometry import Shape, hub_with_lugs
from intrusim.kinematics import BodyState
from intrusim.params import table_s1
from intrusim.scenarios.base import ALL_KINDS, ForceModelConfig, ModelKindsMixin, RunConfig


def _deep_merge(base: dict[str, Any], update: dict[str, Any]) -> dict[str, Any]:
    out = dict(base)
    for k, v in update.items():
        out[k] = _deep_merge(out[k], v) if isinstance(v, dict) and isinstance(out.get(k), dict) else v
    return out


class LocomotorScenario(ModelKindsMixin):
    """A driven hub-with-lugs body free to translate in x and z.

    Attributes (SI)
    ---------------
    name : label.
    body : "wheel" or "runner" (which shipped defaults a partial TOML file is merged onto).
    hub_diameter : m, inner (hub) diameter.
    lug_height, lug_width : m, true grouser / flap size (radial length, thickness).
    lug_count : number of lugs.
    width : m, out-of-plane width W (element area = length x W).
    lug_height_scale : RFT element height / true lug height (grouser shadowing: 1/3 for the
        wheel; 1 for the runner's flaps). Sinkage always uses the TRUE outline.
    hub_elements_per_segment, lug_elements_per_face : RFT discretisation.
    mass_x, mass_z : kg, effective horizontal / vertical inertia; weight = mass_z * gravity.
    gravity : m/s^2.
    external_fx : N, constant forward force.
    length_scale : m, l of the non-dimensional axes (outer diameter; Table S1).
    mpm_scale : the MPM set-up's size relative to the paper's for its body (box, cells, bed and
        start times this, times of the run times its square root: a geometrically similar
        simulation, :func:`~intrusim.scenarios.mpm_locomotion.similar_settings`); 0.5 for Fig
        S1's half-size wheel, so its grousers span as many cells as the Table S1 wheel's.
    """

    name: str
    body: Literal["wheel", "runner"]
    hub_diameter: float = Field(gt=0.0)
    lug_height: float = Field(gt=0.0)
    lug_width: float = Field(gt=0.0)
    lug_count: int = Field(ge=1)
    width: float = Field(gt=0.0)
    lug_height_scale: float = Field(1.0, gt=0.0, le=1.0)
    hub_elements_per_segment: int = Field(14, ge=1)
    lug_elements_per_face: int = Field(8, ge=1)
    mass_x: float = Field(gt=0.0)
    mass_z: float = Field(gt=0.0)
    gravity: float = Field(gt=0.0)
    external_fx: float = 0.0
    length_scale: float = Field(gt=0.0)
    mpm_scale: float = Field(1.0, gt=0.0, le=10.0)
    run: RunConfig = Field(default_factory=RunConfig)

    @model_validator(mode="after")
    def _geometry_fits(self) -> "LocomotorScenario":
        self.rft_shape()  # raises InputError (a ValueError) if the lugs overlap
        return self

    # the keys a body file gives or takes from its body's shipped values (said when it is loaded)
    _defaulted: tuple[str, ...] = PrivateAttr(default=())

    @classmethod
    def from_dict(cls, data: dict[str, Any], source: str = "config") -> "LocomotorScenario":
        """Validate ``data`` merged onto the shipped defaults of ``data['body']`` ("wheel": the Table
        S1 wheel, "runner": the four-flap runner; required). ``length_scale``, when not given, is the
        body's outer diameter (``hub_diameter + 2 lug_height``). The :data:`BODY_KEYS` taken from the
        shipped body are kept in :attr:`defaulted` (:func:`describe_body` says them)."""
        if "body" not in data:
            raise InputError(
                f"{source}: body is required: 'wheel' or 'runner' (whose shipped values fill the keys the file does not give)"
            )
        body = data["body"]
        if body not in DEFAULTS:
            raise InputError(f"{source}: body must be one of {list(DEFAULTS)}, got {body!r}")
        base = DEFAULTS[body]().model_dump()
        merged = _deep_merge(base, data)
        if "length_scale" not in data:
            hub, lug = merged.get("hub_diameter"), merged.get("lug_height")
            if all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in (hub, lug)):
                merged["length_scale"] = hub + 2 * lug  # a bad value is refused, naming its own key, below
        out: LocomotorScenario = super().from_dict(merged, source)  # type: ignore[assignment]
        out._defaulted = tuple(k for k in BODY_KEYS if k not in data)
        return out

    @classmethod
    def _file_defaults(cls, data: dict[str, Any], path: Path) -> dict[str, Any]:
        """A body file without ``name`` is named after the file (``my_wheel.toml``: my_wheel)."""
        return data if "name" in data else {**data, "name": path.stem}

    @classmethod
    def from_toml(cls, path: str | Path) -> "LocomotorScenario":
        """A body file, its effective body said once on stderr (:func:`describe_body`)."""
        out: LocomotorScenario = super().from_toml(path)  # type: ignore[assignment]
        key = (str(Path(path).resolve()), Path(path).stat().st_mtime_ns)
        if key not in _DESCRIBED:
            _DESCRIBED.add(key)
            print(describe_body(out, source=str(path)), file=sys.stderr)
        return out

    @property
    def defaulted(self) -> tuple[str, ...]:
        """The :data:`BODY_KEYS` this body took from its shipped body (its file did not give them)."""
        return self._defaulted

    # --- geometry -------------------------------------------------------------------------
    def _shape(self, scale: float) -> Shape:
        return hub_with_lugs(
            0.5 * self.hub_diameter, self.lug_height, self.lug_width, self.lug_count, self.width,
            hub_elements_per_segment=self.hub_elements_per_segment,
            lug_elements_per_face=self.lug_elements_per_face, lug_height_scale=scale, name=self.name,
        )  # fmt: skip

    def rft_shape(self) -> Shape:
        """Shape whose elements RFT sees (lugs at lug_height_scale); polygon = true outline."""
        return self._shape(self.lug_height_scale)

    def finer_elements(self, factor: int) -> "LocomotorScenario":
        """This body with ``factor`` x as many RFT elements on every rim segment and lug face (the
        rim's outline polygon takes the finer arcs too): the element-converged answer of a model,
        against which its default discretisation is measured (benchmarks/bench_integrator.py)."""
        f = positive_int("factor", factor)
        return self.validated_copy(
            hub_elements_per_segment=self.hub_elements_per_segment * f,
            lug_elements_per_face=self.lug_elements_per_face * f,
        )

    def finer_steps(self, dt: float, omega: float, factor: int = 16, revolutions: int = 8) -> "LocomotorScenario":
        """This body run at steps of about ``dt`` / ``factor`` (``dt`` the step a run at ``omega`` rad/s
        took; at most that, the step rule then putting k + 0.618 steps in a lug pitch), its steady
        state averaged over ``revolutions``: the dt -> 0 reference against which a default step is
        measured (benchmarks/bench_integrator.py)."""
        f = positive_int("factor", factor)
        run = self.run.model_copy(
            update=dict(steps_per_revolution=round(f * self.run.period(omega) / dt), dt_max=dt / f,
                        average_revolutions=positive_int("revolutions", revolutions))
        )  # fmt: skip
        return self.model_copy(update=dict(run=run))

    @property
    def radius(self) -> float:
        """Nominal (outer) radius r = hub radius + true lug height, m: the r of slip and dh."""
        return 0.5 * self.hub_diameter + self.lug_height

    # --- dynamics -------------------------------------------------------------------------
    def rigid_body(self) -> RigidBody:
        return RigidBody(self.mass_x, self.mass_z, self.gravity, self.external_fx, 0.0)

    def drive(self, omega_rpm: float) -> Drive:
        """Forward rolling (towards +x) at ``omega_rpm`` > 0: omega = -omega_rpm 2 pi / 60 rad/s."""
        w = finite("omega_rpm", omega_rpm)
        if w <= 0.0:
            raise InputError(f"omega_rpm must be > 0 (forward rolling), got {omega_rpm!r}")
        return Drive(-w * 2.0 * math.pi / 60.0, self.run.ramp_time)

    def initial_state(self, shape: Shape | None = None) -> BodyState:
        """At rest, lowest TRUE outline point ``run.initial_sinkage`` below the surface z = 0."""
        shp = shape or self.rft_shape()
        lowest = float(np.min(shp.polygon[:, 1]))
        return BodyState(0.0, -lowest - self.run.initial_sinkage, 0.0, 0.0, 0.0, 0.0)

    # --- non-dimensional scales (paper Fig 3) ----------------------------------------------
    @property
    def velocity_scale(self) -> float:
        """sqrt(g l), m/s."""
        return math.sqrt(self.gravity * self.length_scale)

    @property
    def omega_0(self) -> float:
        """sqrt(g / l), rad/s."""
        return math.sqrt(self.gravity / self.length_scale)


def grousered_wheel_scenario() -> LocomotorScenario:
    """The Table S1 grousered wheel with the paper's DRFT parameters (Fig 4-5)."""
    w, ps = table_s1()["grousered_wheel"], table_s1()["poppy_seeds"]
    return LocomotorScenario(
        name="grousered_wheel", body="wheel",
        hub_diameter=w["inner_diameter"], lug_height=w["grouser_height"], lug_width=w["grouser_width"],
        lug_count=w["grouser_count"], width=w["width"], lug_height_scale=1.0 / 3.0,
        hub_elements_per_segment=14, lug_elements_per_face=8,
        mass_x=w["effective_horizontal_inertia"], mass_z=w["effective_vertical_inertia"],
        gravity=w["gravity"], external_fx=0.0, length_scale=w["outer_diameter"],
        supported_models=ALL_KINDS,
        force_model=ForceModelConfig(
            xi=ps["rft_scaling_coefficient"], rho=ps["critical_density"], lam=1.0, structural="wheel-rear-half",
            internal_friction=ps["internal_friction"],
        ),
    )  # fmt: skip


def without_lugs(scenario: LocomotorScenario, stub: float = 0.0005) -> LocomotorScenario:
    """The same body with its outer radius but lugs cut to ``stub`` m (a smooth rim, for checks of
    the rim alone; 0.5 mm is a fifth of a 2.5 mm MPM cell and leaves the RFT lug elements no area
    to speak of)."""
    r_outer = scenario.radius
    if not 0.0 < stub < r_outer:
        raise InputError(f"stub must be in (0, {r_outer:g}) m, got {stub!r}")
    return scenario.validated_copy(name=scenario.name + "_smooth", lug_height=stub, hub_diameter=2.0 * (r_outer - stub))


def with_lug_count(scenario: LocomotorScenario, lug_count: int) -> LocomotorScenario:
    """The same body with ``lug_count`` lugs of the same size (hub, inertias and force model kept),
    named ``NAME_Nlugs``; validated (the lugs must fit on the hub)."""
    return type(scenario).model_validate(
        {**scenario.model_dump(), "lug_count": lug_count, "name": f"{scenario.name}_{lug_count}lugs"}
    )


def with_mass_z(scenario: LocomotorScenario, mass_z: float) -> LocomotorScenario:
    """The same body under another load: vertical inertia ``mass_z`` (kg; weight mass_z * g), with
    the name, the horizontal inertia, the push and the force model kept (the body is the same, so
    run folders keep their names; callers tag the load); validated (mass_z > 0)."""
    return scenario.validated_copy(mass_z=mass_z)


def small_wheel_scenario() -> LocomotorScenario:
    """Fig S1: the Table S1 wheel with every length (width included) halved; inertias x 1/8."""
    big = grousered_wheel_scenario()
    s = float(table_s1()["small_grousered_wheel"]["scale"])
    return big.model_copy(
        update=dict(
            name="small_grousered_wheel",
            hub_diameter=big.hub_diameter * s, lug_height=big.lug_height * s, lug_width=big.lug_width * s,
            width=big.width * s, mass_x=big.mass_x * s**3, mass_z=big.mass_z * s**3,
            length_scale=big.length_scale * s, mpm_scale=s,
        )
    )  # fmt: skip


def ten_grouser_wheel_scenario() -> LocomotorScenario:
    """The Table S1 wheel with 10 grousers of the same size (the reduced-order model's reference set)."""
    return with_lug_count(grousered_wheel_scenario(), 10)


def thirty_grouser_wheel_scenario() -> LocomotorScenario:
    """The Table S1 wheel with 30 grousers of the same size (the reduced-order model's reference set)."""
    return with_lug_count(grousered_wheel_scenario(), 30)


def tall_grouser_wheel_scenario() -> LocomotorScenario:
    """The Table S1 wheel with grousers twice as tall (hub, grouser thickness and count, inertias and
    force model kept; l the new outer diameter): the reduced-order model's reference set."""
    s = grousered_wheel_scenario()
    return s.validated_copy(
        name=f"{s.name}_tall_lugs", lug_height=2 * s.lug_height, length_scale=s.hub_diameter + 4 * s.lug_height
    )


RUNNER_STEPS_PER_REVOLUTION, RUNNER_DT_MAX = 200, 0.004


def four_flap_runner_scenario(lam: float = 4.0) -> LocomotorScenario:
    """The Table S1 four-flap runner (Fig 7): inertial correction only, lambda = ``lam``."""
    r, ps = table_s1()["four_flap_runner"], table_s1()["poppy_seeds"]
    return LocomotorScenario(
        name="four_flap_runner", body="runner",
        hub_diameter=r["inner_diameter"], lug_height=r["flap_length"], lug_width=r["flap_width"],
        lug_count=r["flap_count"], width=r["width"], lug_height_scale=1.0,
        hub_elements_per_segment=14, lug_elements_per_face=16,
        mass_x=r["mass"], mass_z=r["mass"], gravity=r["gravity"], external_fx=0.0,
        length_scale=r["outer_diameter"], supported_models=ALL_KINDS,
        force_model=ForceModelConfig(xi=ps["rft_scaling_coefficient"], rho=ps["critical_density"], lam=lam, structural="none",
                                     internal_friction=ps["internal_friction"]),
        # its long flaps make its steady state more step-sensitive than the wheel's: 200 steps a
        # revolution, of at most 4 ms, keep v and sinkage within 0.12 % of the dt -> 0 answer at 10-300 RPM
        # (600 steps: 0.03 %, at 3 x the cost; 400 steps of at most 10 ms: 0.2 %; benchmarks/bench_integrator.py,
        # docs/locomotion.md)
        run=RunConfig(steps_per_revolution=RUNNER_STEPS_PER_REVOLUTION, dt_max=RUNNER_DT_MAX),
    )  # fmt: skip


DEFAULTS = {"wheel": grousered_wheel_scenario, "runner": four_flap_runner_scenario}
SHIPPED_BODY = {"wheel": "the Table S1 wheel", "runner": "the Table S1 four-flap runner"}

# what makes a body: its geometry, inertias, gravity and the scale of its non-dimensional axes
BODY_KEYS = ("hub_diameter", "lug_height", "lug_width", "lug_count", "width", "mass_x", "mass_z", "gravity",
             "external_fx", "length_scale")  # fmt: skip
_UNITS = {"hub_diameter": "m", "lug_height": "m", "lug_width": "m", "lug_count": "", "width": "m", "mass_x": "kg",
          "mass_z": "kg", "gravity": "m/s^2", "external_fx": "N", "length_scale": "m"}  # fmt: skip
_DESCRIBED: set[tuple[str, int]] = set()  # body files already described in this process


def effective_body(scenario: LocomotorScenario) -> dict[str, Any]:
    """The body as it is run: name, body, each of :data:`BODY_KEYS` (SI), the outer radius, and which
    keys were taken from the shipped body (``defaulted``); for ``body.json`` beside results."""
    out: dict[str, Any] = {"name": scenario.name, "body": scenario.body}
    out.update({k: getattr(scenario, k) for k in BODY_KEYS})
    out.update(radius=scenario.radius, units={k: u for k, u in _UNITS.items() if u}, defaulted=list(scenario.defaulted))
    return out


def write_body(path: str | Path, scenario: LocomotorScenario, external_fx_as_run: float | None = None) -> Path:
    """Write :func:`effective_body` of ``scenario`` as JSON to ``path`` (whole or not at all), beside
    the results it made; ``external_fx_as_run`` (N): the forward push the results were computed with,
    where it is not the body's own (a model file's or calibrate's MPM push)."""
    import json

    from intrusim.mpm.io import atomic_write_bytes

    p = Path(path)
    body = effective_body(scenario)
    if external_fx_as_run is not None and external_fx_as_run != scenario.external_fx:
        body["external_fx_as_run"] = external_fx_as_run
        body["units"]["external_fx_as_run"] = "N"
    atomic_write_bytes(p, json.dumps(body, indent=1).encode())
    return p


def describe_body(scenario: LocomotorScenario, source: str | None = None) -> str:
    """One paragraph: the effective body, every value with its unit, those not given by the body's
    file marked as taken from the shipped body."""
    parts = []
    for k in BODY_KEYS:
        v, u = getattr(scenario, k), _UNITS[k]
        derived = k == "length_scale" and k in scenario.defaulted
        tag = " (= hub_diameter + 2 lug_height)" if derived else (" *" if k in scenario.defaulted else "")
        parts.append(f"{k} = {v:g}{' ' + u if u else ''}{tag}")
    head = f"{source}: " if source else ""
    text = f"{head}{scenario.body} '{scenario.name}': " + ", ".join(parts)
    taken = [k for k in scenario.defaulted if k != "length_scale"]
    if taken:
        text += f"; * not in the file: taken from {SHIPPED_BODY[scenario.body]}"
    return text
