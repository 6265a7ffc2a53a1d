"""Validated configuration of an MPM run (pydantic v2).

Every number the solver uses lives here, with its unit. Bad input fails at construction with
an error naming the field, before any compute.
"""

from __future__ import annotations

import math
import tomllib
from pathlib import Path
from typing import Literal, get_args

from pydantic import BaseModel, ConfigDict, Field, field_validator, model_validator

from intrusim.validation import check_mpm_geometry, reject_bool_numbers

Vec2 = tuple[float, float]


# The rigid-body contact of every MPM run unless set (MPMConfig.contact): the grid nodes inside the body
# take its velocity, the points that touch its surface are corrected after G2P (docs/mpm.md, "Contact")
Contact = Literal["nodes", "surface", "band"]
CONTACTS: tuple[str, ...] = get_args(Contact)
DEFAULT_CONTACT: Contact = "nodes"


class _Model(BaseModel):
    # finite numbers only (inf and NaN are refused, naming the field); true/false are not numbers
    model_config = ConfigDict(extra="forbid", frozen=False, allow_inf_nan=False)

    _no_bool_numbers = model_validator(mode="before")(classmethod(reject_bool_numbers))


class MuIConfig(_Model):
    """Inertial-number friction mu(I) = mu_s + delta_mu I / (i0 + I), I = gdot d sqrt(rho_s / P).
    Defaults: glass beads (Jop, Forterre & Pouliquen 2006: delta_mu 0.26, I0 0.279); poppy seeds
    (~1 mm, 1100 kg/m^3, Table S1) have no measured mu(I)."""

    grain_diameter: float = Field(1.0e-3, gt=0, description="mean grain diameter d, m")
    grain_density: float = Field(1100.0, gt=0, description="solid density of the grains rho_s, kg/m^3")
    delta_mu: float = Field(0.26, ge=0, description="mu_2 - mu_s, the friction's rise at large I")
    i0: float = Field(0.279, gt=0, description="inertial number I0 at which half the rise is reached")


class FluidityConfig(_Model):
    """Nonlocal granular fluidity (Henann & Kamrin 2013): gdot_p = g mu, A^2 d^2 lap g = |mu - mu_s| (g - g_loc),
    g_loc = sqrt(P / (rho_s d^2)) (mu - mu_s) / (b mu). Defaults: glass beads' A 0.48 and b 0.9375
    (Henann & Kamrin 2013) with poppy seeds' ~1 mm and 1100 kg/m^3 (Table S1); poppy seeds' A and b are
    not measured."""

    grain_diameter: float = Field(1.0e-3, gt=0, description="mean grain diameter d, m")
    grain_density: float = Field(1100.0, gt=0, description="solid density of the grains rho_s, kg/m^3")
    amplitude: float = Field(
        0.48, gt=0, description="nonlocal amplitude A: cooperativity length xi = A d / sqrt(|mu - mu_s|)"
    )
    b: float = Field(0.9375, gt=0, description="local rheology mu = mu_s + b I")
    sweep_pairs: int = Field(
        2, ge=1, le=50, description="pairs of Jacobi sweeps of the fluidity per step (warm-started)"
    )


class MaterialConfig(_Model):
    """Drucker-Prager granular continuum with free separation (SPEC 1, Eq. 1-2)."""

    rho_c: float = Field(638.0, gt=0, description="critical (close-packed) density, kg/m^3")
    mu_s: float = Field(0.56, ge=0, description="internal friction coefficient tau/P at yield")
    youngs_modulus: float = Field(1.0e6, gt=0, description="numerical elastic stiffness E, Pa")
    poisson_ratio: float = Field(0.3, gt=-1.0, lt=0.5, description="Poisson ratio nu")
    viscosity: float = Field(
        0.0,
        ge=0,
        description="Pa s: viscous overstress at yield, tau = mu_s P + eta gdot (a diagnostic regularisation, "
        "not in the paper; 0 = the paper's rate-independent law)",
    )
    mu_i: MuIConfig | None = Field(
        None,
        description="inertial-number friction mu(I) at yield (not in the paper; None = the paper's "
        "rate-independent law)",
    )
    fluidity: FluidityConfig | None = Field(
        None,
        description="nonlocal granular fluidity in place of the Drucker-Prager return (not in the paper; "
        "None = the paper's rate-independent law)",
    )
    rho_floor_fraction: float = Field(
        0.1,
        gt=0,
        lt=1,
        description="lowest density a point dilutes to, / rho_c (a point alone in flight keeps its APIC "
        "velocity gradient, so without a floor its volume grows exponentially until it overflows)",
    )

    @model_validator(mode="after")
    def _one_rate_law(self):
        given = [
            name
            for name, on in (
                ("viscosity", self.viscosity > 0.0),
                ("mu_i", self.mu_i is not None),
                ("fluidity", self.fluidity is not None),
            )
            if on
        ]
        if len(given) > 1:
            raise ValueError(f"material: give one rate law of viscosity, mu_i and fluidity, not {' and '.join(given)}")
        return self

    @property
    def rho_floor(self) -> float:
        """Lowest point density, kg/m^3: rho_floor_fraction rho_c."""
        return self.rho_floor_fraction * self.rho_c

    @property
    def shear_modulus(self) -> float:
        """G = E / (2 (1 + nu)), Pa."""
        return self.youngs_modulus / (2.0 * (1.0 + self.poisson_ratio))

    @property
    def lame_lambda(self) -> float:
        """lambda = E nu / ((1 + nu)(1 - 2 nu)), Pa."""
        nu = self.poisson_ratio
        return self.youngs_modulus * nu / ((1.0 + nu) * (1.0 - 2.0 * nu))


class Rectangle(_Model):
    """Axis-aligned rectangle [x0, x1] x [z0, z1], m."""

    x0: float
    z0: float
    x1: float
    z1: float

    @model_validator(mode="after")
    def _ordered(self):
        if not (self.x1 > self.x0 and self.z1 > self.z0):
            raise ValueError("rectangle needs x1 > x0 and z1 > z0")
        return self


class BedConfig(_Model):
    """Initial granular bed: union of rectangles and polygons, minus excluded polygons."""

    rectangles: list[Rectangle] = Field(default_factory=list)
    polygons: list[list[Vec2]] = Field(default_factory=list, description="closed polygons, m")
    density_ratio: float = Field(1.0, gt=0, description="initial density / rho_c (< 1: loose, stress-free material)")
    k0: float | Literal["elastic", "jaky"] = Field(
        "elastic",
        description="lateral earth-pressure ratio: number, 'elastic' nu/(1-nu) or 'jaky' 1-sin(phi)",
    )
    geostatic: bool = Field(True, description="initialise the geostatic stress")

    @field_validator("k0")
    @classmethod
    def _k0_positive(cls, v):
        if isinstance(v, float) and v < 0:
            raise ValueError("k0 must be >= 0")
        return v


WallKind = Literal["frictionless", "sticky", "coulomb", "open"]


class WallConfig(_Model):
    kind: WallKind = "frictionless"
    mu: float = Field(0.0, ge=0, description="Coulomb friction coefficient (kind='coulomb')")


class BoundaryConfig(_Model):
    """Domain walls. A side of kind "open" has no wall: points that leave through it are removed and
    their mass counted as outflow (``Solver.outflow``, the time series' ``outflow_mass``). The top has
    no wall; ``top = "open"`` makes it an outflow side too (else a point above it is an escape,
    ``output.escaped``)."""

    left: WallConfig = Field(default_factory=WallConfig)
    right: WallConfig = Field(default_factory=WallConfig)
    floor: WallConfig = Field(default_factory=lambda: WallConfig(kind="sticky"))
    top: Literal["escape", "open"] = Field(
        "escape", description="escape: a point above the top is an escape (output.escaped); open: it leaves as outflow"
    )


class ObstacleConfig(_Model):
    """Static rigid polygon (world frame), optionally removed at a given time (a gate)."""

    vertices: list[Vec2] = Field(min_length=3)
    mu: float = Field(0.0, ge=0, description="grain-obstacle friction coefficient")
    removal_time: float | None = Field(None, ge=0, description="s; None: never removed")


class PrescribedMotion(_Model):
    """Body moved at constant velocity, reached by a linear ramp from rest."""

    kind: Literal["prescribed"] = "prescribed"
    vx: float = 0.0
    vz: float = 0.0
    omega: float = 0.0
    ramp_time: float = Field(0.0, ge=0, description="s, linear ramp from rest")


class CoupledMotion(_Model):
    """Prescribed omega(t), free x and z from the granular force (wheel, runner)."""

    kind: Literal["coupled"] = "coupled"
    omega: float = Field(0.0, description="target angular velocity (ccw), rad/s")
    ramp_time: float = Field(0.0, ge=0, description="s, linear ramp of omega from rest")
    mass_x: float = Field(gt=0, description="effective horizontal inertia, kg")
    mass_z: float = Field(gt=0, description="effective vertical inertia (weight = mass_z g), kg")
    external_force: Vec2 = Field((0.0, 0.0), description="constant 3D force on the body, N")
    free_x: bool = True
    free_z: bool = True


class IntruderConfig(_Model):
    """Rigid intruder: a polygon in the body frame (ccw, reference point at origin)."""

    vertices: list[Vec2] = Field(min_length=3, description="body-frame polygon, m")
    width: float = Field(1.0, gt=0, description="out-of-plane width converting N/m to N, m")
    mu_w: float = Field(0.35, ge=0, description="body-grain Coulomb friction")
    x: float = 0.0
    z: float = 0.0
    theta: float = 0.0
    motion: PrescribedMotion | CoupledMotion = Field(default_factory=PrescribedMotion, discriminator="kind")


class DomainConfig(_Model):
    size: Vec2 = Field((1.0, 1.0), description="domain (Lx, Lz), m")
    cells: tuple[int, int] = Field((200, 200), description="grid cells (nx, nz)")
    particles_per_cell: int = Field(2, ge=1, le=4, description="per direction")

    @field_validator("size")
    @classmethod
    def _pos_size(cls, v):
        if min(v) <= 0:
            raise ValueError("domain size must be positive")
        return v

    @field_validator("cells")
    @classmethod
    def _pos_cells(cls, v):
        if min(v) < 4:
            raise ValueError("need at least 4 cells per direction")
        return v

    @model_validator(mode="after")
    def _square_cells(self):
        hx = self.size[0] / self.cells[0]
        hz = self.size[1] / self.cells[1]
        if not math.isclose(hx, hz, rel_tol=1e-9):
            raise ValueError(f"cells must be square: size/cells gives hx={hx}, hz={hz}")
        return self

    @property
    def h(self) -> float:
        """Grid spacing, m."""
        return self.size[0] / self.cells[0]


class TimeConfig(_Model):
    t_end: float = Field(1.0, gt=0, description="physical end time, s")
    cfl: float = Field(0.3, gt=0, le=1.0, description="C in dt = C h sqrt(rho_c / E)")
    max_cell_fraction: float = Field(0.25, gt=0, le=1.0, description="max particle displacement per step, in cells")
    v_max_expected: float = Field(1.0, gt=0, description="m/s; dt <= max_cell_fraction h / v_max_expected")
    dt: float | None = Field(None, gt=0, description="override dt, s (must satisfy both limits)")
    max_steps: int = Field(
        20_000_000,
        ge=1,
        description="most time steps t_end / dt a run may take: a larger estimate is refused before any compute",
    )


Shape = Literal["quadratic", "linear"]  # shape functions of the transfers (TransferConfig.shape)
Precision = Literal["f32", "f64"]  # floating point of the fields (BackendConfig.precision; backend.PRECISIONS)
SHAPES: tuple[str, ...] = get_args(Shape)


class TransferConfig(_Model):
    flip: float | None = Field(
        None,
        ge=0.0,
        le=1.0,
        description="share of FLIP in the points' new velocity: v_p <- flip (v_p + sum w (v_i - v_i_old)) + "
        "(1 - flip) sum w v_i, with v_i_old the grid velocity P2G gave, before forces and contact. None (the "
        "default): exp(-dt / tau), tau = pic_time h sqrt(rho_c / E), so that the PIC part damps at a rate per "
        "second that does not depend on dt; 0: APIC (the default before: the grid's velocity replaces the "
        "point's every step, which damps flow at the grid's scale by an amount that grows as dt falls: "
        "docs/mpm.md); 1: FLIP, as the mpm-2d code of the paper's group. The affine matrix C and the positions "
        "follow the grid velocity either way",
    )
    pic_time: float = Field(
        10.0,
        gt=0.0,
        description="with flip = None: the time over which the PIC part relaxes a point's own velocity to the "
        "grid's, in elastic cell-crossing times h sqrt(rho_c / E) (at the default cfl 0.3, 10 gives a PIC "
        "share of 3 % per step; it falls with dt, so the damping per second stays the same)",
    )
    shape: Shape = Field(
        "quadratic",
        description="shape functions of P2G and G2P: quadratic B-splines (the default, with APIC's affine "
        "momentum) or linear: the bilinear functions of each point's cell, as the mpm-2d code of the paper's "
        "group, with the momentum m_p v_p alone and the stress force -V_p sigma_p grad w (APIC's affine part "
        "needs the quadratic splines, so use it with flip = 1; flip = 0 is then PIC). Linear runs the one-point "
        "kernels; the nonlocal fluidity field keeps its quadratic stencil",
    )


class OutputConfig(_Model):
    directory: str | None = Field(None, description="run folder; None: no files")
    record_every: float = Field(0.01, gt=0, description="time-series interval, s")
    snapshot_every: float | None = Field(None, gt=0, description="VTK snapshot interval, s")
    checkpoint_every: float | None = Field(None, gt=0, description="checkpoint interval, s")
    guard_every_steps: int = Field(50, ge=1, description="NaN/escape/CFL check interval, steps")
    escape_margin_cells: float = Field(
        1.0,
        ge=0,
        le=2.0,
        description="a point more than this many cells outside [0, Lx] x [0, Lz] has escaped "
        "(walls act on grid nodes, so points may sit a fraction of a cell beyond them)",
    )
    escaped: Literal["stop", "drop"] = Field(
        "stop",
        description="what an escaped point does: stop the run with a diagnosis and a failure checkpoint "
        "(the default), or leave the simulation (a grain thrown out of the box; its mass leaves the time "
        "series' grain_mass and is counted in Solver.dropped, as the paper's group's mpm-2d marks such "
        "points inactive). NaN and CFL breaches stop the run either way",
    )


# settings of BackendConfig until they became internal switches of the benchmarks and tests
# (intrusim.mpm.backend.BenchmarkSwitches): refused in a run's configuration; in a saved one (a run
# folder's config.json, a checkpoint) read as the switches of that run (intrusim.mpm.io.split_switches)
REMOVED_BACKEND_KEYS: tuple[str, ...] = ("step_graph", "device_bodies", "simd_lanes")


class BackendConfig(_Model):
    arch: Literal["cpu", "cuda", "vulkan", "metal", "gpu"] = "cpu"
    precision: Precision = "f32"
    cpu_threads: int | None = Field(None, ge=1)
    p2g_chunks: int = Field(
        16,
        ge=1,
        le=31,
        description="CPU: P2G into this many private grid copies (no atomics, deterministic sum "
        "order independent of the thread count; more chunks than threads balance the load, and "
        "the grid update sums each copy only over its chunk's box); GPU uses atomics instead",
    )
    deterministic_sums: bool = Field(
        True,
        description="where several threads add into one target (a GPU's P2G, body impulses and "
        "fluidity sources; the CPU's with p2g_chunks = 1): 64-bit fixed-point atomic adds, exact in "
        "any order, so that a run and its restart give the same numbers bit for bit; False: float "
        "atomic adds (their rounding follows the threads' order). Vulkan and Metal: float atomics "
        "always (64-bit integer atomics are not portable). The CPU's chunked P2G sums in a fixed order either way",
    )

    @model_validator(mode="before")
    @classmethod
    def _no_removed_keys(cls, data):
        given = [k for k in REMOVED_BACKEND_KEYS if isinstance(data, dict) and k in data]
        if given:
            raise ValueError(
                f"{' and '.join(given)} {'is' if len(given) == 1 else 'are'} no longer a setting of a run "
                "(every run takes the default path; the benchmarks switch it with "
                "intrusim.mpm.backend.BenchmarkSwitches): remove it"
            )
        return data


class MPMConfig(_Model):
    """Everything needed to build a :class:`~intrusim.mpm.solver.Solver`."""

    domain: DomainConfig = Field(default_factory=DomainConfig)
    material: MaterialConfig = Field(default_factory=MaterialConfig)
    bed: BedConfig = Field(default_factory=BedConfig)
    boundaries: BoundaryConfig = Field(default_factory=BoundaryConfig)
    obstacles: list[ObstacleConfig] = Field(default_factory=list)
    intruders: list[IntruderConfig] = Field(default_factory=list)
    gravity: Vec2 = Field((0.0, -9.8), description="m/s^2, (gx, gz)")
    contact: Contact = Field(
        DEFAULT_CONTACT,
        description="rigid-body contact (docs/mpm.md): 'nodes' (the default), the grid nodes inside the body "
        "projected and the points touching its surface corrected; 'surface', the points touching the "
        "body's surface enforced on the grid by sweeps, then corrected; 'band', the grid nodes within "
        "contact_band_cells of the body",
    )
    contact_band_cells: float = Field(
        1.0, ge=0, description="contact 'band': grid nodes within this distance (cells) of a body are in contact"
    )
    time: TimeConfig = Field(default_factory=TimeConfig)
    transfer: TransferConfig = Field(default_factory=TransferConfig)
    output: OutputConfig = Field(default_factory=OutputConfig)
    backend: BackendConfig = Field(default_factory=BackendConfig)

    @model_validator(mode="after")
    def _bed_inside(self):
        lx, lz = self.domain.size
        for r in self.bed.rectangles:
            if r.x0 < 0 or r.z0 < 0 or r.x1 > lx or r.z1 > lz:
                raise ValueError(f"bed.rectangles: {r} lies outside the domain {lx} x {lz}")
        if self.bed.density_ratio < self.material.rho_floor_fraction:
            raise ValueError(
                f"bed.density_ratio {self.bed.density_ratio} is below material.rho_floor_fraction "
                f"{self.material.rho_floor_fraction}: points would be compacted to the floor at once"
            )
        check_mpm_geometry(self)  # simple polygons of positive area, inside the box
        return self

    @classmethod
    def from_toml(cls, path: str | Path) -> "MPMConfig":
        with open(path, "rb") as fh:
            return cls.model_validate(tomllib.load(fh))
