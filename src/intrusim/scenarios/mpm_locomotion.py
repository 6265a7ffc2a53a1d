"""MPM locomotion: the paper's wheels and runner in the continuum solver (Fig 3, 5, 7, S1).

A :class:`MPMLocomotion` case pairs a :class:`~intrusim.scenarios.locomotor.LocomotorScenario`
(geometry, inertias, gravity: the same body that RFT/DRFT drive) with :class:`MPMSettings`
(bed, resolution, material, run length). ``case.run_steady("mpm", omega_rpm)`` builds the
:class:`~intrusim.mpm.config.MPMConfig`, runs the coupled simulation (prescribed omega ramped
from rest, free x and z) and averages it over a documented window:

* the run stops at ``t_max`` or as soon as the body's front comes within ``wall_margin`` of the
  right wall (1 m bed: the paper's experiments and simulations use a 1 m long bed);
* the steady state is the average over t >= ``ramp_time + settle_time``; for a non-round
  runner the window is trimmed to whole revolutions, counted back from the end.

Sinkage is the depth of the lowest TRUE outline point below the undisturbed surface (as for
RFT/DRFT). The rear free-surface drop dh (Fig 5C) is measured on particle snapshots taken
during the window (:func:`intrusim.analysis.free_surface.rear_contact_drop`).
"""

from __future__ import annotations

import json
import math
import sys
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Annotated, Any, Callable, get_args

import numpy as np
from pydantic import Field, ValidationInfo, field_validator, model_validator

from intrusim._checks import InputError, finite
from intrusim.analysis.free_surface import rear_contact_drop
from intrusim.analysis.settling import SETTLE_TOL, Settling, settle_window, settling
from intrusim.analysis.steady import outline_sinkage, window_drift
from intrusim.geometry import posed_polygon, signed_area
from intrusim.mpm.config import DEFAULT_CONTACT, Contact, FluidityConfig, MuIConfig, Precision, Shape
from intrusim.mpm.io import atomic_file, atomic_write_bytes
from intrusim.params import table_s1
from intrusim.scenarios.base import Config
from intrusim.scenarios.locomotor import LocomotorScenario

_Length = Annotated[float, Field(gt=0.0)]
_Count = Annotated[int, Field(ge=1)]


class MPMSettings(Config):
    """How an MPM locomotion run is set up (SI). Defaults: the paper's resolution (Table S1).

    Attributes
    ----------
    domain : (Lx, Lz) m; cells : grid cells (nx, nz); particles_per_cell : per direction.
    bed_depth : m, height of the undisturbed free surface above the floor.
    start_x : m, initial x of the body centre.
    start_depth : m, initial depth of the body's lowest point below the bed surface, the grains
        in its place left out (0: the body starts resting half a cell above the bed, as in the
        paper; > 0: it starts embedded, without the bulge that sinking in would push up).
    rho_c, mu_s : poppy seeds (Table S1): 638 kg/m^3, 0.56.
    mu_w : body-grain friction (Table S1: 0.35).
    youngs_modulus, poisson_ratio : numerical elastic stiffness (the paper does not give it).
    mu_i : inertial-number friction mu(I) (not the paper's law); None: the paper's rate-independent friction.
    fluidity : nonlocal granular fluidity in place of the Drucker-Prager return (not the paper's law).
    forward_force : N, constant forward push (rig-friction compensation). None (the wheel's
        default): Table S1's 4 N scaled by the body's horizontal inertia over the Table S1 wheel's
        23.0 kg, since rig friction scales with the carried mass (small wheel: 0.5 N); runner: 0.
    ramp_time : s, linear spin-up of omega; settle_time : s, transient excluded from averages.
    t_max : s, longest run; wall_margin : m, stop when the body's front is this close to the wall.
    settle_tol : the stop test (:mod:`intrusim.analysis.settling`): the run ends as soon as its mean v
        and mean sinkage each moved by less than this fraction between its last two revolutions,
        t_max then the cap, and the answer is the last revolution's means; None (the default): the
        run lasts t_max and is averaged from ramp_time + settle_time. Either way the run's outcome
        (settled, still sinking, ...) is judged by this test (at 1 % when None).
    treadmill : (x_trigger, x_target), m, or None. A moving window: at a chunk's end with the body
        centre past x_trigger, the scene moves back a whole number of cells to put it at (just
        above) x_target, the rut that leaves the left side is dropped and fresh bed comes in on the
        right (:meth:`~intrusim.mpm.solver.Solver.shift_window`). A run then lasts t_max in a
        short box; the time series' x stays in the bed's frame. None: the body runs to the wall.
    chunk : s, run-control interval (progress, stop test, particle snapshots for dh).
    cfl : C of dt = C h sqrt(rho_c / E).
    flip : FLIP's share of the points' velocity update (``TransferConfig.flip``; None: the default
        transfer, FLIP with a PIC share per step that falls with dt; 0: APIC, the former default;
        1: FLIP, the method of the paper's group's mpm-2d code).
    pic_time : the default transfer's relaxation time in elastic cell-crossing times
        (``TransferConfig.pic_time``; None: its default).
    shape : shape functions of the transfers (``TransferConfig.shape``): "quadratic" (B-splines, as
        every run of docs/results.md) or "linear" (the cell's bilinear functions, as mpm-2d; with flip 1).
    drop_escaped : a point thrown out of the box leaves the run (``OutputConfig.escaped = "drop"``, as
        mpm-2d marks such points inactive) instead of stopping it with a diagnosis (the default).
    contact : "nodes" (the default): the grid nodes inside the body projected, then the points at
        its surface corrected; "surface": the points that touch the body's exact surface enforced on
        the grid by sweeps, then corrected;
        "band": at the grid nodes within ``contact_band_cells`` (docs/mpm.md).
    contact_band_cells : with contact "band", grid nodes closer than this many cells outside the
        body are in contact (the body acts about this much larger on the grid; docs/mpm.md).
    arch, precision, cpu_threads : Taichi backend.
    keep_fields : particle snapshots saved to the run folder (last ones of the window).
    frames_every : s, interval of the movie frames (positions, speed, plastic strain rate) saved
        to ``frames/`` in the run folder; None: no frames.
    """

    domain: tuple[_Length, _Length] = (1.0, 1.0)
    cells: tuple[_Count, _Count] = (200, 200)
    particles_per_cell: int = Field(2, ge=1, le=4)
    bed_depth: float = Field(0.3, gt=0.0)
    start_x: float = Field(0.16, gt=0.0)
    start_depth: float = Field(0.0, ge=0.0)
    rho_c: float = Field(638.0, gt=0.0)
    mu_s: float = Field(0.56, ge=0.0)
    mu_w: float = Field(0.35, ge=0.0)
    youngs_modulus: float = Field(1.0e6, gt=0.0)
    poisson_ratio: float = Field(0.3, gt=-1.0, lt=0.5)
    mu_i: MuIConfig | None = None
    fluidity: FluidityConfig | None = None
    forward_force: float | None = None
    ramp_time: float = Field(0.15, ge=0.0)
    settle_time: float = Field(0.5, ge=0.0)
    t_max: float = Field(4.0, gt=0.0)
    settle_tol: float | None = Field(None, gt=0.0, lt=1.0)
    wall_margin: float = Field(0.08, ge=0.0)
    treadmill: tuple[float, float] | None = None
    chunk: float = Field(0.05, gt=0.0)
    cfl: float = Field(0.3, gt=0.0, le=1.0)
    flip: float | None = Field(None, ge=0.0, le=1.0)
    pic_time: float | None = Field(None, gt=0.0)
    shape: Shape = "quadratic"
    drop_escaped: bool = False
    contact: Contact = DEFAULT_CONTACT  # MPMConfig.contact
    contact_band_cells: float = Field(1.0, ge=0.0)
    arch: str = "cpu"
    precision: Precision = "f32"  # the backend's: f32 or f64
    cpu_threads: int | None = Field(None, ge=1)
    keep_fields: int = Field(3, ge=0)
    frames_every: float | None = Field(None, gt=0.0)
    max_steps: int = Field(20_000_000, ge=1)  # time.max_steps: a run estimated to take more steps is refused

    @property
    def h(self) -> float:
        return self.domain[0] / self.cells[0]

    @field_validator("arch")
    @classmethod
    def _known_arch(cls, arch: str) -> str:
        from intrusim.mpm.config import BackendConfig

        names = get_args(BackendConfig.model_fields["arch"].annotation)
        if arch not in names:
            raise ValueError(f"must be one of {', '.join(names)}")
        return arch

    @model_validator(mode="after")
    def _square_cells(self, info: ValidationInfo) -> "MPMSettings":
        if info.context and info.context.get("partial"):  # a few fields read alone (mpm_settings._fields_read)
            return self
        hx, hz = self.domain[0] / self.cells[0], self.domain[1] / self.cells[1]
        if not math.isclose(hx, hz, rel_tol=1e-9):
            raise ValueError(
                f"cells must be square: domain {list(self.domain)} m over cells {list(self.cells)} gives "
                f"{hx:.4g} x {hz:.4g} m; set the box with --set domain=[Lx, Lz] then --set cell_size=H (which sets cells)"
            )
        return self

    @model_validator(mode="after")
    def _treadmill_in_box(self) -> "MPMSettings":
        if self.treadmill is not None:
            trigger, target = self.treadmill
            if not 0.0 < target < trigger < self.domain[0] - self.wall_margin:
                raise ValueError(
                    f"treadmill (x_trigger, x_target) = {self.treadmill} must satisfy "
                    f"0 < x_target < x_trigger < domain length - wall_margin ({self.domain[0] - self.wall_margin:g} m)"
                )
            if self.start_x >= trigger:
                raise ValueError(f"treadmill: x_trigger ({trigger:g} m) must lie ahead of start_x ({self.start_x:g} m)")
            if trigger - target < self.h:
                raise ValueError(f"treadmill: x_trigger - x_target must be at least one cell ({self.h:g} m)")
        return self


def similar_settings(settings: MPMSettings, scale: float) -> MPMSettings:
    """``settings`` for a geometrically similar body ``scale`` times the size: every length (the
    box, so the cell size, the bed, the start, the wall margin, the treadmill) times ``scale``,
    every time (ramp, settle, run length, chunk, frames) times ``sqrt(scale)`` (Froude similarity:
    the same v / sqrt(g l) and omega sqrt(l / g) at the same point of a run); the grid's cell count,
    the material and the numerical stiffness E kept."""
    if not (math.isfinite(scale) and scale > 0.0):
        raise InputError(f"scale must be a finite number > 0, got {scale!r}")
    if scale == 1.0:
        return settings
    ts = math.sqrt(scale)
    s = settings
    return s.validated_copy(
        domain=(s.domain[0] * scale, s.domain[1] * scale), bed_depth=s.bed_depth * scale, start_x=s.start_x * scale,
        start_depth=s.start_depth * scale, wall_margin=s.wall_margin * scale,
        treadmill=None if s.treadmill is None else (s.treadmill[0] * scale, s.treadmill[1] * scale),
        ramp_time=s.ramp_time * ts, settle_time=s.settle_time * ts, t_max=s.t_max * ts, chunk=s.chunk * ts,
        frames_every=None if s.frames_every is None else s.frames_every * ts,
    )  # fmt: skip


def paper_settings(body: str, scale: float = 1.0) -> MPMSettings:
    """The paper's set-up (Table S1) for a "wheel" or "runner" body; ``scale`` != 1: the same set-up
    for a body ``scale`` times the size (:func:`similar_settings`; the scenario's ``mpm_scale``)."""
    return similar_settings(_paper_settings(body), scale)


def _paper_settings(body: str) -> MPMSettings:
    t = table_s1()
    ps = t["poppy_seeds"]
    res = t["mpm_resolution"]
    common = dict(
        domain=tuple(res["domain"]), cells=tuple(res["grid"]), particles_per_cell=int(res["particles_per_cell"][0]),
        rho_c=ps["critical_density"], mu_s=ps["internal_friction"], mu_w=ps["wheel_surface_friction"],
    )  # fmt: skip
    if body == "wheel":
        return MPMSettings(**common, forward_force=None)
    if body == "runner":
        # the runner reaches ~3 m/s at 300 RPM: a 4 m long bed (same 5 mm cells) gives it room,
        # and the flaps fling grains ~0.5 m high (tip speed 3 m/s): the domain keeps the paper's 1 m height
        lz = float(res["domain"][1])
        h = float(res["domain"][0]) / int(res["grid"][0])
        common.update(domain=(4.0, lz), cells=(int(round(4.0 / h)), int(round(lz / h))))
        return MPMSettings(**common, bed_depth=0.25, forward_force=0.0, t_max=2.5, settle_time=0.4, start_x=0.12)
    raise InputError(f"body must be 'wheel' or 'runner', got {body!r}")


def quick_settings(body: str, scale: float = 1.0) -> MPMSettings:
    """A coarse, short version of :func:`paper_settings` (2 cm cells, 1.2 s): trends in seconds;
    ``scale``: as for :func:`paper_settings`."""
    long = body == "runner"
    base = _paper_settings(body).validated_copy(
        domain=(2.0 if long else 1.0, 0.5), cells=(100 if long else 50, 25), bed_depth=0.25, t_max=1.2,
        ramp_time=0.1, settle_time=0.5, start_x=0.16,
    )  # fmt: skip
    return similar_settings(base, scale)


def base_settings(body: str, quick: bool, scale: float = 1.0) -> MPMSettings:
    """:func:`quick_settings` or :func:`paper_settings` of ``body`` for a body ``scale`` times the size
    (a scenario's ``mpm_scale``): the base every command's and figure's settings go over."""
    return quick_settings(body, scale) if quick else paper_settings(body, scale)


PRESETS = ("paper", "quick", "reference")  # the bases of a command's settings (--preset)
POPPY_SEED_DIAMETER = 1.0e-3  # m, the grain size of Table S1's medium (FluidityConfig's default)
REFERENCE_CAP = 20.0  # s, the longest a reference run goes on before it is reported unsettled


def reference_settings(scenario: LocomotorScenario) -> MPMSettings:
    """The reference route's settings for ``scenario`` (``--preset reference``): a law that converges
    at the resolution this body needs, run until settled on a bed that follows the body.

    * law: the nonlocal granular fluidity (:class:`~intrusim.mpm.config.FluidityConfig`, Henann &
      Kamrin 2013), whose grain size gives shear bands a width of their own (the paper's law has
      none: docs/convergence.md); grain diameter d = max(poppy seeds' 1 mm, 2.5 cells), the
      smallest the cells resolve;
    * cells: a fifth of the body's thinnest feature (:func:`thinnest_feature`; 1.2 mm for the
      Table S1 wheel's 6 mm grousers);
    * box: 6 radii plus the wall margin long, with a treadmill (the scene moves back a whole number
      of cells whenever the body passes 3 radii, to 2.5 radii), so the bed never ends; a wheel's bed
      is half the paper's deep (0.15 m for the Table S1 wheel: with the nonlocal law at 5 mm cells,
      90 RPM, v and sinkage within 0.8 % of the 0.3 m bed's at half the points; docs/convergence.md)
      and its box the bed plus 4 radii high; a runner keeps the paper's bed and height (its flaps
      fling grains);
    * run: until the settle test holds (``settle_tol`` 1 % over the last two revolutions), at most
      :data:`REFERENCE_CAP` s;
    * the rest as the paper's set-up (:func:`paper_settings`: the medium, E, the bed's depth, the
      push, the transfer and the contact)."""
    base = paper_settings(scenario.body, scenario.mpm_scale)
    radius, _ = _extent(scenario)
    h = thinnest_feature(scenario) / RESOLUTION_FRACTION
    nx = math.ceil((6 * radius + base.wall_margin) / h - 1e-9)
    wheel = scenario.body == "wheel"
    bed = 0.5 * base.bed_depth if wheel else base.bed_depth
    lz = bed + 4 * radius if wheel else base.domain[1]
    nz = math.ceil(lz / h - 1e-9)
    start = math.ceil(2.5 * radius / h - 1e-9) * h
    trigger = start + max(h, math.floor(0.5 * radius / h) * h)
    out = base.validated_copy(
        domain=(nx * h, nz * h), cells=(nx, nz), bed_depth=bed, start_x=start, treadmill=(trigger, start),
        fluidity={"grain_diameter": max(POPPY_SEED_DIAMETER, 2.5 * h)}, settle_tol=0.01,
        t_max=max(REFERENCE_CAP, base.t_max),
    )  # fmt: skip
    return fit_box(out, scenario, echo=False)


RESOLUTION_FRACTION = 5  # cells at most a fifth of the body's thinnest feature (docs/convergence.md)


def thinnest_feature(scenario: LocomotorScenario) -> float:
    """The body's thinnest feature, m: its lugs' thickness or height, whichever is smaller."""
    return float(min(scenario.lug_width, scenario.lug_height))


def resolution_warning(scenario: LocomotorScenario, cell_size: float, quick: bool = False) -> str | None:
    """A warning when cells are coarser than a fifth of the body's thinnest feature, else None."""
    feature = thinnest_feature(scenario)
    if cell_size <= feature / RESOLUTION_FRACTION * (1 + 1e-9):
        return None
    what = "quick runs: trends only" if quick else "the answer moves with the cells"
    return (
        f"{scenario.name}: cells of {cell_size * 1e3:.3g} mm are coarser than a fifth of the body's thinnest feature "
        f"({feature * 1e3:.3g} mm lugs: {feature / RESOLUTION_FRACTION * 1e3:.3g} mm); {what} (docs/convergence.md)"
    )


def _extent(scenario: LocomotorScenario) -> tuple[float, float]:
    """(outer radius, depth of the lowest point below the centre) of the body's TRUE outline, m."""
    outline = scenario.rft_shape().polygon
    return float(np.max(np.linalg.norm(outline, axis=1))), -float(outline[:, 1].min())


def start_height(settings: MPMSettings, below: float) -> float:
    """z of the body's centre at the start: its lowest point (``below`` m under the centre) half a
    cell above the bed, or ``start_depth`` into it."""
    s = settings
    return s.bed_depth + below + (0.5 * s.h if s.start_depth == 0.0 else -s.start_depth)


def fit_box(
    settings: MPMSettings,
    scenario: LocomotorScenario,
    echo: bool | Callable[[str], None] = True,
    height: bool = True,
    start: bool = True,
) -> MPMSettings:
    """``settings`` with the box grown in whole cells (the cell size kept) so that ``scenario``'s body
    fits: its centre at least its radius and a cell from the left wall (``start_x`` moved, the bed
    lengthened by as much; unless ``start`` is False), and room for the body plus one radius of
    headroom above the bed (the domain's height; unless ``height`` is False). A body that fits gets
    ``settings`` itself. ``echo``: say what was grown on stderr (True) or to this callable."""
    s, (radius, below) = settings, _extent(scenario)
    h = s.h
    domain, cells, start_x = list(s.domain), list(s.cells), s.start_x
    if start and start_x - radius < h:
        shift = math.ceil((radius + 2 * h - start_x) / h - 1e-9) * h
        start_x += shift
        cells[0] += round(shift / h)
        domain[0] = cells[0] * h
    top = start_height(s, below) + radius
    if height and top > s.domain[1] - h:
        cells[1] = math.ceil((top + max(radius, 2 * h)) / h - 1e-9)
        domain[1] = cells[1] * h
    if (tuple(domain), tuple(cells), start_x) == (s.domain, s.cells, s.start_x):
        return s
    out = s.validated_copy(domain=tuple(domain), cells=tuple(cells), start_x=start_x)
    if echo:
        text = (
            f"{scenario.name}: the MPM box grown to {domain[0]:.4g} x {domain[1]:.4g} m ({cells[0]} x {cells[1]} cells "
            f"of {h * 1e3:.3g} mm, start_x {start_x:.4g} m) to hold the body (radius {radius:.4g} m); "
            "--set domain=[Lx, Lz] --set cell_size=H sets it by hand"
        )
        echo(text) if callable(echo) else print(text, file=sys.stderr)
    return out


@dataclass(frozen=True)
class MPMSteadyState:
    """Window averages of one MPM locomotion run (SI) and its time series."""

    omega: float
    velocity: float
    sinkage: float
    slip: float
    velocity_std: float
    sinkage_std: float
    drift: float
    settled: bool
    surface_drop: float  # m, rear free-surface drop dh (Fig 5C); NaN if never measured
    surface_drop_std: float
    window: tuple[float, float]
    radius: float
    wall_time: float  # s
    steps: int
    series: dict[str, np.ndarray] = field(repr=False)
    meta: dict[str, Any] = field(default_factory=dict, repr=False)
    settling: Settling | None = field(default=None, repr=False)  # the run's outcome (settled = its test)

    @property
    def outcome(self) -> str:
        """What the run did by its end (:data:`~intrusim.analysis.settling.OUTCOMES`)."""
        return self.settling.outcome if self.settling is not None else ("settled" if self.settled else "unknown")

    def summary(self) -> dict[str, Any]:
        return {
            "omega": self.omega, "velocity": self.velocity, "sinkage": self.sinkage, "slip": self.slip,
            "velocity_std": self.velocity_std, "sinkage_std": self.sinkage_std, "drift": self.drift,
            "surface_drop": self.surface_drop, "surface_drop_std": self.surface_drop_std,
            "wall_time": self.wall_time, "steps": float(self.steps), "settled": float(self.settled),
            "window_start": self.window[0], "window_end": self.window[1],
            **(self.settling.summary() if self.settling is not None else {}),
        }  # fmt: skip


def forward_force(scenario: LocomotorScenario, settings: MPMSettings) -> float:
    """The constant forward push, N: ``settings.forward_force``, or Table S1's 4 N scaled by the
    body's horizontal inertia relative to the Table S1 wheel (23.0 kg) when it is None."""
    if settings.forward_force is not None:
        return float(settings.forward_force)
    wheel = table_s1()["grousered_wheel"]
    return float(wheel["mpm_forward_force"]) * scenario.mass_x / float(wheel["effective_horizontal_inertia"])


def mpm_config(scenario: LocomotorScenario, settings: MPMSettings, omega_rpm: float, out_dir: str | Path | None = None):
    """The :class:`~intrusim.mpm.config.MPMConfig` of ``scenario`` spinning forward at ``omega_rpm``."""
    from intrusim.mpm.config import (
        BackendConfig,
        BedConfig,
        CoupledMotion,
        DomainConfig,
        IntruderConfig,
        MaterialConfig,
        MPMConfig,
        OutputConfig,
        Rectangle,
        TimeConfig,
        TransferConfig,
    )  # fmt: skip

    w = finite("omega_rpm", omega_rpm)
    if w <= 0.0:
        raise InputError(f"omega_rpm must be > 0 (forward rolling), got {omega_rpm!r}")
    s = settings
    outline = scenario.rft_shape().polygon  # the TRUE outline (lug shadowing only affects RFT elements)
    radius = float(np.max(np.linalg.norm(outline, axis=1)))
    if s.start_depth >= s.bed_depth:
        raise InputError(f"start_depth ({s.start_depth:g} m) must be less than the bed depth ({s.bed_depth:g} m)")
    z0 = start_height(s, -float(outline[:, 1].min()))
    if s.start_x - radius < s.h:
        raise InputError(
            f"the body (radius {radius:.3g} m) does not fit at start_x = {s.start_x:g} m: start_x must be at least "
            f"its radius plus a cell ({radius + s.h:.4g} m; --set start_x=...)"
        )
    if z0 + radius > s.domain[1] - s.h:
        need = math.ceil((z0 + radius + s.h) * 1e3) / 1e3  # mm, rounded up
        raise InputError(
            f"the body (radius {radius:.3g} m) does not fit under the box's top: its height {s.domain[1]:g} m must be at "
            f"least bed_depth + the body + a cell ({need:.4g} m; --set domain=[{s.domain[0]:g}, {need:.3g}] "
            f"--set cell_size={s.h:g}, or let the box size itself: leave domain and cells unset)"
        )
    return MPMConfig(
        domain=DomainConfig(size=s.domain, cells=s.cells, particles_per_cell=s.particles_per_cell),
        material=MaterialConfig(rho_c=s.rho_c, mu_s=s.mu_s, youngs_modulus=s.youngs_modulus, poisson_ratio=s.poisson_ratio,
                                mu_i=s.mu_i, fluidity=s.fluidity),
        bed=BedConfig(rectangles=[Rectangle(x0=0.0, z0=0.0, x1=s.domain[0], z1=s.bed_depth)]),
        intruders=[IntruderConfig(
            vertices=outline.tolist(), width=scenario.width, mu_w=s.mu_w, x=s.start_x, z=z0,
            motion=CoupledMotion(
                omega=-w * 2 * math.pi / 60, ramp_time=s.ramp_time, mass_x=scenario.mass_x, mass_z=scenario.mass_z,
                external_force=(forward_force(scenario, s), 0.0),
            ),
        )],
        gravity=(0.0, -scenario.gravity),
        contact=s.contact, contact_band_cells=s.contact_band_cells,
        time=TimeConfig(t_end=s.t_max, cfl=s.cfl, v_max_expected=1.0, max_steps=s.max_steps),
        transfer=TransferConfig(flip=s.flip, shape=s.shape, **({} if s.pic_time is None else {"pic_time": s.pic_time})),
        output=OutputConfig(directory=None if out_dir is None else str(out_dir), record_every=0.01, checkpoint_every=0.5,
                            escaped="drop" if s.drop_escaped else "stop"),
        backend=BackendConfig(arch=s.arch, precision=s.precision, cpu_threads=s.cpu_threads),
    )  # fmt: skip


def _window_mask(t: np.ndarray, t_start: float, omega: float, whole_revolutions: bool) -> np.ndarray:
    """Samples in the averaging window; optionally trimmed to whole revolutions from the end."""
    t_end = float(t[-1])
    if whole_revolutions:
        period = 2 * math.pi / omega
        n_rev = math.floor((t_end - t_start) / period)
        if n_rev >= 1:
            t_start = t_end - n_rev * period
    return t > t_start


def _save_frame(folder: Path, solver: Any, outline: np.ndarray) -> None:
    """One movie frame: particle positions, speed and plastic strain rate, body pose (float32)."""
    folder.mkdir(parents=True, exist_ok=True)
    f = solver.particles.to_numpy(["x", "v", "gdot_p", "eps_p"])
    st = solver.intruders[0].state
    with atomic_file(folder / f"frame_{solver.step_count:08d}.npz") as fh:  # never a partial file under the final name
        np.savez_compressed(
            fh, x=f["x"].astype(np.float32),
            speed=np.linalg.norm(f["v"], axis=1).astype(np.float32), gdot_p=f["gdot_p"].astype(np.float32),
            eps_p=f["eps_p"].astype(np.float32), body=np.array([st.x, st.z, st.theta]), outline=outline, t=solver.t,
        )  # fmt: skip


PROGRESS_FILE = "progress.json"  # rear surface drops measured so far and wall time, per chunk


def write_progress(run_dir: Path, drops: list[tuple[float, float]], wall: float) -> None:
    """Save what a resumed run needs besides the solver checkpoint (atomic)."""
    atomic_write_bytes(run_dir / PROGRESS_FILE, json.dumps({"drops": drops, "wall_time": wall}).encode())


def read_progress(run_dir: Path) -> tuple[list[tuple[float, float]], float]:
    """(rear surface drops (t, dh) measured so far, wall time so far) from ``progress.json``;
    ([], 0) if the folder has none."""
    path = Path(run_dir) / PROGRESS_FILE
    info = json.loads(path.read_text()) if path.exists() else {}
    return [(float(a), float(b)) for a, b in info.get("drops", [])], float(info.get("wall_time", 0.0))


def resume_run(
    solver: Any, run_dir: Path | None, keep_fields: int
) -> tuple[list[tuple[float, float]], list[Path], float]:
    """Continue an interrupted run from its folder: (drops, kept field files, wall time so far).

    The solver state comes from its checkpoint (:meth:`Solver.continue_in_run_dir`: a folder
    holding a run of another configuration is refused with an InputError); the rear surface drops and the wall time from
    ``progress.json``, kept up to the checkpoint's time. Kept field snapshots after the checkpoint
    are deleted (the run writes them again).
    """
    if run_dir is None:
        return [], [], 0.0
    if not solver.continue_in_run_dir():
        (run_dir / PROGRESS_FILE).unlink(missing_ok=True)  # the progress of a run killed before its first checkpoint
        return [], [], 0.0
    t = solver.t + 0.5 * solver.dt
    drops, wall = read_progress(run_dir)
    drops = [(a, b) for a, b in drops if a <= t]
    kept = []
    for path in sorted(run_dir.glob("fields_*.npz")):
        if int(path.stem.split("_")[1]) > solver.step_count:
            path.unlink()
        else:
            kept.append(path)
    print(f"{run_dir}: resumed at t = {solver.t:.3f} s (step {solver.step_count})", file=sys.stderr)
    return drops, kept[-keep_fields:] if keep_fields else [], wall


def treadmill_shift(solver: Any, body: Any, treadmill: tuple[float, float] | None) -> None:
    """At a chunk's end: the moving window's shift, if ``body`` is past the trigger
    (``treadmill`` = (x_trigger, x_target), m; None: no treadmill); back to the target in whole cells."""
    if treadmill is not None and body.state.x > treadmill[0]:
        solver.shift_window(math.floor((body.state.x - treadmill[1]) / solver.h) * solver.h)


def check_run(scenario: LocomotorScenario, settings: MPMSettings, omega_rpm: float, out_dir: str | Path | None = None):
    """The :func:`mpm_config` of a run, refused (InputError) before any compute where the run
    cannot be made: a body that does not fit, a grid or step count beyond reach
    (:func:`~intrusim.validation.check_run_size`), no time to settle, a treadmill the body would
    carry into a wall. ``mpm sweep`` checks each of its points with this before running any."""
    from intrusim.mpm.solver import time_step_limits
    from intrusim.validation import check_run_size

    cfg = mpm_config(scenario, settings, omega_rpm, out_dir)
    limits = time_step_limits(cfg)
    check_run_size(cfg, cfg.time.dt or min(limits["dt_elastic"], limits["dt_motion"]))
    s = settings
    t_avg = s.ramp_time + s.settle_time
    if t_avg >= s.t_max:
        raise InputError(f"ramp_time + settle_time ({t_avg} s) must be shorter than t_max ({s.t_max} s)")
    if s.settle_tol is not None:
        need = t_avg + 2 * settle_window(omega_rpm * 2 * math.pi / 60)
        if s.t_max < need:
            raise InputError(
                f"t_max ({s.t_max:g} s) is shorter than the settle test needs at {omega_rpm:g} RPM: ramp_time + "
                f"settle_time and two revolutions, {need:.3g} s (--set t_max=..., the cap of a run that stops once settled)"
            )
    if s.treadmill is not None:  # the body's size: the settings' own validator does not know it
        radius = float(np.max(np.linalg.norm(np.asarray(cfg.intruders[0].vertices), axis=1)))
        trigger, target = s.treadmill
        if trigger + radius > s.domain[0] - s.wall_margin:
            raise InputError(
                f"treadmill: the body (radius {radius:.3g} m) at x_trigger {trigger:g} m would reach "
                f"the wall margin; use a smaller x_trigger or a longer domain"
            )
        if target - radius < s.h:
            raise InputError(
                f"treadmill: the body (radius {radius:.3g} m) at x_target {target:g} m would touch the left wall"
            )
    return cfg


# settings that choose how a run is computed or saved, not what it computes: a recorded run that
# differs from the case asked for only in these is the same case
# (frames_every is not one: it sets the chunks a run advances by, so when the rear drop is sampled,
# the treadmill shifts and the stop tests)
RUN_CONTROL = frozenset({"cpu_threads", "arch", "keep_fields", "max_steps"})


def _flat(data: Any, prefix: str = "") -> dict[str, Any]:
    if isinstance(data, dict):
        out: dict[str, Any] = {}
        for k, v in data.items():
            out.update(_flat(v, f"{prefix}{k}."))
        return out if out or not prefix else {prefix[:-1]: {}}
    return {prefix[:-1]: data}


def settings_differences(recorded: dict[str, Any], wanted: Any, longer_ok: bool = False) -> list[str]:
    """Keys at which recorded settings (a dict, read as MPMSettings: a setting added since is its
    default) differ from ``wanted`` (an MPMSettings); :data:`RUN_CONTROL` keys are not differences,
    nor, with ``longer_ok``, a recorded t_max shorter than the wanted one (the run is extended)."""
    try:
        recorded = MPMSettings.model_validate(recorded).model_dump(mode="json")
    except ValueError:
        pass  # not settings of this version: compared as written
    a, b = _flat(recorded), _flat(wanted.model_dump(mode="json"))
    diff = [k for k in sorted(set(a) | set(b)) if k.split(".")[0] not in RUN_CONTROL and a.get(k) != b.get(k)]
    if longer_ok and "t_max" in diff and isinstance(a.get("t_max"), (int, float)) and a["t_max"] < b["t_max"]:
        diff.remove("t_max")
    return diff


def recorded_differences(run_dir: str | Path | None, settings: MPMSettings, longer_ok: bool = True) -> list[str]:
    """The keys at which a run folder's recorded settings (``locomotion.json``) differ from ``settings``
    (:func:`settings_differences`); none for a folder without a record."""
    info = None if run_dir is None else Path(run_dir) / "locomotion.json"
    if info is None or not info.is_file():
        return []
    return settings_differences(json.loads(info.read_text()).get("settings") or {}, settings, longer_ok=longer_ok)


def refuse_other_settings(run_dir: str | Path | None, settings: MPMSettings) -> None:
    """Refuse (InputError) a run folder whose recorded settings (``locomotion.json``) differ from
    ``settings`` in what they compute (the stop test, the window, the medium ...: settings the
    solver's own configuration does not hold); how a run is computed (threads, arch) and a longer
    t_max (the run is extended) are not differences."""
    # t_max is left to the solver's own check: a longer one extends the run, a shorter one is refused there
    diff = [k for k in recorded_differences(run_dir, settings, longer_ok=False) if k != "t_max"]
    if diff:
        shown = ", ".join(diff[:8]) + (f" and {len(diff) - 8} more" if len(diff) > 8 else "")
        raise InputError(
            f"{run_dir} holds a run of another configuration (differs in {shown}): give another --out, or remove that folder"
        )


def run_mpm_steady(
    scenario: LocomotorScenario,
    settings: MPMSettings,
    omega_rpm: float,
    out_dir: str | Path | None = None,
    progress: Callable[[dict], None] | None = None,
) -> MPMSteadyState:
    """Run one MPM locomotion case to steady state (see module docstring for the window)."""
    from intrusim.mpm.solver import Solver

    cfg = check_run(scenario, settings, omega_rpm, out_dir)
    s = settings
    solver = Solver(cfg)
    run_dir = None if out_dir is None else Path(out_dir)
    body = solver.intruders[0]
    outline = np.asarray(body.contact.vertices)
    radius = float(np.max(np.linalg.norm(outline, axis=1)))
    t_avg = s.ramp_time + s.settle_time
    step_t = min(s.chunk, s.frames_every) if (s.frames_every and run_dir is not None) else s.chunk
    # a folder holding a run of another configuration is refused here, before anything is written
    drops, kept, wall_before = resume_run(solver, run_dir, s.keep_fields)  # nothing to resume: [], [], 0
    if run_dir is not None:
        run_dir.mkdir(parents=True, exist_ok=True)
        info = {
            "body": scenario.body,
            "scenario": scenario.model_dump(mode="json"),
            "settings": s.model_dump(mode="json"),
            "omega_rpm": omega_rpm,
        }
        atomic_write_bytes(run_dir / "locomotion.json", json.dumps(info, indent=1).encode())

    def sample() -> None:
        """Rear surface drop (and kept particle fields) of the window at this chunk's end."""
        st = body.state
        f = solver.particle_fields()
        dh = rear_contact_drop(
            f["x"], f["pressure"], body.world_vertices(), (st.x, st.z), 1.0, s.bed_depth,
            band=solver.h, pressure_tol=0.5 * s.rho_c * scenario.gravity * solver.h,
        )  # fmt: skip
        drops.append((solver.t, dh))
        if run_dir is not None and s.keep_fields:
            path = run_dir / f"fields_{solver.step_count:08d}.npz"
            with atomic_file(path) as fh:  # never a partial file under the final name
                np.savez_compressed(
                    fh, x=f["x"], v=f["v"], pressure=f["pressure"], gdot_p=f["gdot_p"], eps_p=f["eps_p"],
                    body=np.array([st.x, st.z, st.theta, st.vx, st.vz, st.omega]), outline=outline, t=solver.t,
                )  # fmt: skip
            if path not in kept:
                kept.append(path)
            while len(kept) > s.keep_fields:
                kept.pop(0).unlink(missing_ok=True)

    # chunk ends are t = k step_t; a resumed run goes on from the chunk its checkpoint lies in
    k0 = math.floor((solver.t + 0.5 * solver.dt) / step_t)
    t_next = k0 * step_t
    next_frame = 0.0
    if s.frames_every and solver.step_count > 0:  # resumed: the frames up to now are on disk
        next_frame = (math.floor((solver.t + 1e-9) / s.frames_every) + 1) * s.frames_every
    at_chunk_end = solver.step_count > 0 and solver.step_count == int(round(t_next / solver.dt))
    if at_chunk_end and solver.t >= t_avg and not any(abs(t - solver.t) < 0.5 * solver.dt for t, _ in drops):
        sample()  # killed between the checkpoint and the progress file of this chunk
    treadmill_shift(
        solver, body, s.treadmill
    )  # a run resumed at a chunk's end from the checkpoint written before that chunk's shift
    wall0 = time.perf_counter() - wall_before
    near_wall = lambda: body.state.x + radius > s.domain[0] - s.wall_margin  # noqa: E731
    omega = omega_rpm * 2 * math.pi / 60
    test_from = t_avg + 2 * settle_window(omega) if s.settle_tol is not None else math.inf

    def settled_now() -> bool:
        """The stop test on the samples so far (MPMSettings.settle_tol)."""
        if solver.t < test_from - 0.5 * solver.dt:
            return False
        t, z, th, vx = (np.array([r[k] for r in solver.rows], float) for k in ("time", "z", "theta", "vx"))
        sink = outline_sinkage(outline, z, th, s.bed_depth)
        return settling(t, vx, sink, omega, t_avg, s.settle_tol, radius).settled  # type: ignore[arg-type]

    stop = "t_max"
    while solver.t < s.t_max - 0.5 * solver.dt and not near_wall():
        t_next = min(t_next + step_t, s.t_max)
        solver.run(t_end=t_next, checkpoint_end=False)  # checkpoints on schedule; the end state below
        st = body.state
        if progress is not None:
            progress(
                {
                    "t": solver.t,
                    "x": st.x + solver.x_offset,
                    "z": st.z,
                    "vx": st.vx,
                    "wall": time.perf_counter() - wall0,
                }
            )
        if run_dir is not None and s.frames_every and solver.t + 1e-9 >= next_frame:
            next_frame += s.frames_every
            _save_frame(run_dir / "frames", solver, outline)
        if solver.t >= t_avg:
            sample()
        if run_dir is not None:
            write_progress(run_dir, drops, time.perf_counter() - wall0)
        if settled_now():
            stop = "settled"
            break
        treadmill_shift(solver, body, s.treadmill)
    if stop != "settled" and near_wall():
        stop = "wall"
    if run_dir is not None:  # a longer run on this folder (a later t_max) goes on from here
        solver.checkpoint_run_folder()
    wall = time.perf_counter() - wall0
    rows = solver.rows
    series = {k: np.array([r[k] for r in rows], float) for k in SERIES_KEYS}
    meta = {
        "scenario": scenario.name,
        "dt": solver.dt,
        "cell_size": solver.h,
        "particles": solver.particles.n,
        "omega_rpm": omega_rpm,
        "fields": [str(p) for p in kept],
        "x_offset": solver.x_offset,
        "dropped_points": solver.dropped["points"],
        "stop": stop,
    }
    return steady_from_series(
        series, outline, s.bed_depth, t_avg, scenario.body == "runner", drops, wall, solver.step_count, meta,
        s.settle_tol,
    )  # fmt: skip


SERIES_KEYS = ("time", "x", "z", "theta", "vx", "vz", "omega", "fx", "fz", "moment")


def steady_from_series(
    series: dict[str, np.ndarray],
    outline: np.ndarray,
    bed_depth: float,
    t_avg: float,
    whole_revolutions: bool,
    drops: list[tuple[float, float]],
    wall_time: float = math.nan,
    steps: int = 0,
    meta: dict[str, Any] | None = None,
    settle_tol: float | None = None,
) -> MPMSteadyState:
    """Average an MPM locomotion time series over t > ``t_avg`` (see the module docstring), and
    judge whether it settled (:func:`~intrusim.analysis.settling.settling`, at ``settle_tol``, 1 %
    when None). With ``settle_tol`` given and the run settled, the average is over its last
    revolution (the window the test passed on)."""
    series = dict(series)
    radius = float(np.max(np.linalg.norm(outline, axis=1)))
    series["sinkage"] = outline_sinkage(outline, series["z"], series["theta"], bed_depth)
    t = series["time"]
    if t[-1] <= t_avg:
        raise InputError(
            f"the run ended at t = {t[-1]:.3g} s (body reached the wall), before the averaging window starts "
            f"at {t_avg:.3g} s: use a longer bed, a smaller start_x or a shorter settle_time"
        )
    omega = abs(float(series["omega"][-1]))
    judged = settling(t, series["vx"], series["sinkage"], omega, t_avg, settle_tol or SETTLE_TOL, radius)
    if settle_tol is not None and judged.settled:
        sel = t > judged.t_end - judged.window
    else:
        sel = _window_mask(t, t_avg, omega, whole_revolutions)
    v, sk = series["vx"][sel], series["sinkage"][sel]
    v_mean = float(v.mean())
    drift = window_drift(v, sk, radius)
    dh = np.array([d for t_d, d in drops if t_d > t_avg], float)
    dh_ok = dh[np.isfinite(dh)]
    return MPMSteadyState(
        omega=omega, velocity=v_mean, sinkage=float(sk.mean()), slip=1.0 - v_mean / (radius * omega),
        velocity_std=float(v.std()), sinkage_std=float(sk.std()), drift=float(drift), settled=judged.settled,
        surface_drop=float(dh_ok.mean()) if len(dh_ok) else math.nan,
        surface_drop_std=float(dh_ok.std()) if len(dh_ok) else math.nan,
        window=(float(t[sel][0]), float(t[-1])), radius=radius, wall_time=wall_time, steps=steps,
        series=series, meta=meta or {}, settling=judged,
    )  # fmt: skip


def fields_drop(path: str | Path, bed_depth: float, rho_c: float, gravity: float, h: float) -> tuple[float, float]:
    """(t, dh) of one saved particle snapshot (``fields_*.npz`` of a run folder)."""
    d = np.load(path)
    x, z, th = (float(v) for v in d["body"][:3])
    poly = posed_polygon(d["outline"], x, z, th)
    dh = rear_contact_drop(
        d["x"], d["pressure"], poly, (x, z), 1.0, bed_depth, band=h, pressure_tol=0.5 * rho_c * gravity * h
    )
    return float(d["t"]), dh


def summarise_run(
    run_dir: str | Path,
    settings: MPMSettings | None = None,
    body: str = "wheel",
    t_end: float | None = None,
    t_start: float | None = None,
) -> MPMSteadyState:
    """Recompute the steady state of a finished (or interrupted) run folder.

    Reads ``timeseries.csv`` and ``config.json`` (written by the solver), the settings from
    ``locomotion.json`` when present (else ``settings`` or :func:`paper_settings` of ``body``), and
    the rear surface drop from the saved ``fields_*.npz`` snapshots. ``t_end``: average only up to
    this time (one window for runs of different lengths). ``t_start``: the window starts here
    instead of at ramp_time + settle_time (a run that settled late; for a runner, whole
    revolutions from the end within it); the rear surface drop is then the mean of the run's own
    measurements after ``t_start`` (``progress.json``, one per 0.05 s chunk) where the folder has them.
    """
    from intrusim.mpm.io import read_timeseries

    run_dir = Path(run_dir)
    ts = run_dir / "timeseries.csv"
    if not ts.exists():
        raise InputError(f"{run_dir} has no timeseries.csv")
    info_path = run_dir / "locomotion.json"
    if info_path.exists():
        info = json.loads(info_path.read_text())
        settings, body = MPMSettings.model_validate(info["settings"]), info["body"]
    settings = settings or paper_settings(body)
    cfg = json.loads((run_dir / "config.json").read_text())["config"]
    columns = read_timeseries(ts)  # the columns with their units in the header or without (older runs)
    keep = np.ones(len(columns["time"]), bool) if t_end is None else columns["time"] <= t_end + 1e-9
    series = {k: columns[k][keep] for k in SERIES_KEYS}
    outline = np.asarray(cfg["intruders"][0]["vertices"], float)
    if signed_area(outline) < 0:
        outline = outline[::-1]
    gravity = -float(cfg["gravity"][1])
    h = float(cfg["domain"]["size"][0]) / int(cfg["domain"]["cells"][0])
    if t_start is not None and (run_dir / PROGRESS_FILE).exists():
        drops = [d for d in read_progress(run_dir)[0] if t_end is None or d[0] <= t_end + 1e-9]
    else:
        drops = [
            fields_drop(p, settings.bed_depth, settings.rho_c, gravity, h) for p in sorted(run_dir.glob("fields_*.npz"))
        ]
    t_avg = settings.ramp_time + settings.settle_time if t_start is None else float(t_start)
    return steady_from_series(
        series, outline, settings.bed_depth, t_avg, body == "runner", drops, meta={"run_dir": str(run_dir)},
        settle_tol=settings.settle_tol,
    )  # fmt: skip


def write_result(run_dir: str | Path, st: MPMSteadyState) -> Path:
    """Mark a run folder finished: ``result.json`` holds the steady-state summary."""
    path = Path(run_dir) / "result.json"
    said = {} if st.settling is None else {"outcome_text": st.settling.text}
    atomic_write_bytes(
        path,
        json.dumps(
            {**st.summary(), **said, "window": list(st.window), "meta": st.meta}, indent=1, default=str
        ).encode(),
    )
    return path


def load_result(
    run_dir: str | Path, settings: MPMSettings | None = None, body: str = "wheel", t_start: float | None = None
) -> MPMSteadyState:
    """A finished run: time series from the folder, the scalars measured during the run from
    ``result.json`` (the rear surface drop is averaged over every snapshot of the window there,
    over the few kept ``fields_*.npz`` in :func:`summarise_run`). ``t_start``: another window
    start (see :func:`summarise_run`), whose rear surface drop comes from ``progress.json``."""
    from dataclasses import replace

    st = summarise_run(run_dir, settings, body, t_start=t_start)
    res = json.loads((Path(run_dir) / "result.json").read_text())
    measured = ("wall_time",) if t_start is not None else ("surface_drop", "surface_drop_std", "wall_time")
    keep = {k: res[k] for k in measured if k in res}
    return replace(st, steps=int(res.get("steps", 0)), **keep)


class MPMLocomotion(Config):
    """A locomotor scenario run with the MPM solver; usable wherever sweeps take a scenario."""

    scenario: LocomotorScenario
    mpm: MPMSettings
    out_root: str | None = None

    @property
    def name(self) -> str:
        return f"{self.scenario.name}-mpm"

    @property
    def supported_models(self) -> tuple[str, ...]:
        return ("mpm",)

    @property
    def radius(self) -> float:
        return self.scenario.radius

    def run_steady(
        self, kind: str, omega_rpm: float, lam: float | None = None, progress: Callable[[dict], None] | None = None
    ) -> MPMSteadyState:
        """Steady state at ``omega_rpm`` (``kind`` must be "mpm"; ``lam`` is not used by MPM): one
        writer per run folder, a finished run reused (or extended to a longer t_max), ``result.json``
        written at the end. ``progress``: called at each chunk's end (:func:`run_mpm_steady`); a
        ``say(text)`` method of it, if any, is told whether the run is reused or run."""
        if kind != "mpm":
            raise InputError(f"MPMLocomotion runs the 'mpm' model, got {kind!r}")
        from intrusim.mpm.io import run_lock

        say = getattr(progress, "say", None) or (lambda text: None)
        out = self.run_dir(omega_rpm)
        with run_lock(out):  # one writer per run folder
            refuse_other_settings(out, self.mpm)  # e.g. another stop test: the folder's answer is not this one's
            if out is not None and (out / "result.json").exists():  # finished before: reuse it, or extend it
                from intrusim.mpm.io import refuse_other_run

                if not refuse_other_run(out, mpm_config(self.scenario, self.mpm, omega_rpm, out)):
                    say(f"finished before, reused ({out})")
                    return load_result(out, self.mpm, self.scenario.body)
                (out / "result.json").unlink()  # extended: the folder is unfinished until the longer run ends
            say(f"running to t = {self.mpm.t_max:g} s" + ("" if out is None else f" in {out}"))
            st = run_mpm_steady(self.scenario, self.mpm, omega_rpm, out, progress)
            if out is not None:
                write_result(out, st)
        return st

    def run_dir(self, omega_rpm: float) -> Path | None:
        """The run folder of one omega (None without ``out_root``)."""
        if self.out_root is None:
            return None
        from intrusim.mpm.io import safe_child

        return safe_child(self.out_root, f"{self.scenario.name}_{omega_rpm:g}rpm")
