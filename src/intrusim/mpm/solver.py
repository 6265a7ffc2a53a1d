"""Explicit MPM solver for the granular continuum (SPEC 1; Dunatunga & Kamrin 2015).

``Solver.step`` follows the recipe: P2G, grid momentum with gravity, walls and static
obstacles, rigid-intruder contact, G2P with density and stress update, body integration.
"""

from __future__ import annotations

import math
import sys
from pathlib import Path
from typing import Any, Sequence

import numpy as np

from intrusim._checks import InputError
from intrusim.validation import check_run_size

from . import io as mpm_io
from .backend import DEFAULT_SWITCHES, BenchmarkSwitches, ensure_initialized
from .bed import build_bed
from .boundaries import SIDES, Walls
from .config import MPMConfig, PrescribedMotion
from .constitutive import NonlocalFluidity, material_from_config, pressure
from .contact import PolygonContact
from .diagnostics import (
    SimulationError,
    body_report,
    guard_report,
    guard_scan,
    kinetic_energy_and_mass,
    make_scratch,
)
from .fluidity import FluidityField, fluidity_jacobi_kernel, fluidity_relax_kernel, fluidity_sources_kernel
from .grid import PAD, Grid, grid_update_kernel
from .intruder import Intruder
from .particles import FIELDS, Particles
from .step_graph import Launch, StepGraph, run_direct
from .transfer import g2p_kernel, p2g_args, p2g_kernel

FLUIDITY_KEY = "grid_fluidity"  # checkpoint entry of the nonlocal fluidity's grid field
CHECKPOINT = "checkpoint.npz"  # in the run folder, rewritten every output.checkpoint_every


def flip_share(cfg: MPMConfig, dt: float) -> float:
    """FLIP's share of the points' velocity update per step (``TransferConfig``): ``transfer.flip`` where
    given, else exp(-dt / tau) with tau = ``transfer.pic_time`` elastic cell-crossing times h sqrt(rho_c / E),
    so that the PIC part relaxes the points' own velocity towards the grid's at a rate per second that
    does not depend on dt (docs/mpm.md, "The velocity transfer")."""
    if cfg.transfer.flip is not None:
        return float(cfg.transfer.flip)
    tau = cfg.transfer.pic_time * cfg.domain.h * math.sqrt(cfg.material.rho_c / cfg.material.youngs_modulus)
    return math.exp(-dt / tau)


def grid_padding(cfg: MPMConfig, walls: Walls) -> int:
    """Cells of padding around the domain: ``grid.PAD``, and where a side is open, enough more that a
    point leaving through it keeps its full stencil (a point moves at most ``max_cell_fraction`` cells
    a step, the CFL guard) until the next guard removes it, ``guard_every_steps`` later."""
    if not walls.open_sides:
        return PAD
    return PAD + math.ceil(cfg.output.escape_margin_cells + cfg.output.guard_every_steps * cfg.time.max_cell_fraction)


def time_step_limits(cfg: MPMConfig) -> dict[str, float]:
    """Elastic CFL dt = C h sqrt(rho_c / E) and the displacement limit dt = f h / v_max (s)."""
    h = cfg.domain.h
    v_max = cfg.time.v_max_expected
    for ic in cfg.intruders:
        m = ic.motion
        radius = float(np.max(np.linalg.norm(np.asarray(ic.vertices), axis=1)))
        v_body = abs(m.omega) * radius
        if isinstance(m, PrescribedMotion):
            v_body += math.hypot(m.vx, m.vz)
        v_max = max(v_max, v_body)
    dt_elastic = cfg.time.cfl * h * math.sqrt(cfg.material.rho_c / cfg.material.youngs_modulus)
    dt_motion = cfg.time.max_cell_fraction * h / v_max
    return {"dt_elastic": dt_elastic, "dt_motion": dt_motion, "v_max": v_max}


class Solver:
    """One MPM simulation. Several solvers may live in one process (each owns its arrays).

    Parameters
    ----------
    cfg : validated :class:`MPMConfig`.
    particles : optional initial particle arrays (see :data:`particles.FIELDS`); default: the
        bed of ``cfg.bed`` with geostatic stress.
    switches : internal, for the benchmarks and tests that compare the step's other code paths with
        the default (:class:`~intrusim.mpm.backend.BenchmarkSwitches`); a run leaves it out.
    """

    def __init__(
        self,
        cfg: MPMConfig,
        particles: dict[str, np.ndarray] | None = None,
        *,
        switches: BenchmarkSwitches = DEFAULT_SWITCHES,
    ):
        if not isinstance(switches, BenchmarkSwitches):
            raise TypeError(f"switches must be a BenchmarkSwitches, got {type(switches).__name__}")
        self.cfg = cfg
        self.switches = switches
        limits = time_step_limits(cfg)  # the run's size (cells, steps) is refused here if beyond reach
        check_run_size(cfg, cfg.time.dt or min(limits["dt_elastic"], limits["dt_motion"]))
        backend = ensure_initialized(cfg.backend.arch, cfg.backend.precision, cfg.backend.cpu_threads)
        chunks = cfg.backend.p2g_chunks if backend.arch == "cpu" else 1  # a GPU: P2G by atomics
        # atomic sums (one grid copy) in 64-bit fixed point: exact in any order, so runs are reproducible
        # (64-bit integer atomics: CPU and CUDA; not portable to Vulkan and Metal); scaled to rho_c h^2
        fixed = chunks == 1 and cfg.backend.deterministic_sums and backend.arch in ("cpu", "cuda")
        self.walls = Walls(cfg.boundaries)
        # the point kernels vectorised (switches.simd_lanes): float32 only, as in float64 the vectorised P2G crashes
        # the process (a segmentation fault in Taichi 1.7.4's code, measured; its G2P runs),
        # and quadratic splines only (linear shape functions run the one-point kernels)
        self.linear = cfg.transfer.shape == "linear"
        self._lanes = backend.arch == "cpu" and switches.simd_lanes and backend.precision == "f32" and not self.linear
        self.grid = Grid(
            cfg.domain.size,
            cfg.domain.cells,
            chunks,
            cfg.material.rho_c if fixed else None,
            flip=cfg.transfer.flip is None or cfg.transfer.flip > 0,
            pad=grid_padding(cfg, self.walls),
            flip_in_records=self._lanes,
        )
        self.fixed_scale = self.grid.fixed_scale
        self.h = self.grid.h
        self.gravity = tuple(float(g) for g in cfg.gravity)
        self.material = material_from_config(cfg.material)
        band = 0.0 if cfg.contact == "nodes" else cfg.contact_band_cells * self.h
        # contact at the points (the default, and "nodes"), at half a point spacing from the body's surface
        gap = 0.5 * self.h / cfg.domain.particles_per_cell if cfg.contact != "band" else None
        nodes = cfg.contact == "nodes"
        self.obstacles = [
            PolygonContact(np.asarray(o.vertices), o.mu, band, self.fixed_scale, gap, nodes) for o in cfg.obstacles
        ]
        self.intruders = [
            Intruder(ic, band, self.gravity, self.fixed_scale, switches.device_bodies, gap, nodes)
            for ic in cfg.intruders
        ]
        if particles is None:
            exclude = [np.asarray(o.vertices) for o in cfg.obstacles]
            exclude += [b.world_vertices() for b in self.intruders]
            particles = build_bed(
                cfg.domain.size,
                self.h,
                cfg.domain.particles_per_cell,
                cfg.bed,
                cfg.material,
                self.gravity,
                exclude,
            )
        self.particles = Particles(particles)
        self.limits = time_step_limits(cfg)
        dt_max = min(self.limits["dt_elastic"], self.limits["dt_motion"])
        if cfg.time.dt is not None and cfg.time.dt > dt_max * (1 + 1e-12):
            raise ValueError(f"time.dt={cfg.time.dt} exceeds the stable limit {dt_max:.4g} s")
        self.dt = cfg.time.dt or dt_max
        self.flip = flip_share(cfg, self.dt)  # FLIP's share of the points' velocity update
        self._g2p = g2p_kernel(
            self.material.taichi_update, len(self.material.params), self._lanes, self.flip > 0, self.linear
        )
        self.fluidity = (
            FluidityField(self.grid.shape, chunked=self.grid.chunks > 1, fixed_scale=self.fixed_scale)
            if isinstance(self.material, NonlocalFluidity)
            else None
        )
        # by the obstacles still in place: the step's launches, and its graph once compiled
        self._plans: dict[tuple[bool, ...], list[Launch]] = {}
        self._graphs: dict[tuple[bool, ...], StepGraph] = {}
        self._scratch = make_scratch()
        self.step_count = 0
        self.rows: list[dict] = []
        self._impulse_mark = [np.zeros(3) for _ in self.intruders]
        self._impulse_mark_ahead = [np.zeros(3) for _ in self.intruders]
        self._step_mark = 0
        self.x_offset = 0.0  # m, how far shift_window has moved the scene back (bed frame x = x + x_offset)
        self.dropped = {"points": 0, "mass": 0.0}  # escaped points left out (output.escaped = "drop"); mass kg/m
        self.outflow = {"points": 0, "mass": 0.0}  # points gone through open sides (BoundaryConfig); mass kg/m
        self.run_dir = Path(cfg.output.directory) if cfg.output.directory else None

    # ------------------------------------------------------------------ the MPM step
    @property
    def t(self) -> float:
        """Physical time, s (step_count * dt, so a restart lands on the same times)."""
        return self.step_count * self.dt

    def _launches(self, active: tuple[bool, ...]) -> list[Launch]:
        """The kernels of one step in order (SPEC 1 recipe, steps 1-6), for these obstacles."""
        g, p, dt = self.grid, self.particles, self.dt
        lanes = self._lanes and g.chunks > 1  # the vectorised scatters (P2G, fluidity sources) are the chunked ones
        launches = [
            # 1. P2G (copies left zeroed by 2.)
            Launch(
                p2g_kernel(g.chunks > 1, g.fixed_scale is not None, lanes, g.flip, self.linear),
                p2g_args(p, g, dt),
                unscalarized=lanes,
            ),
            Launch(
                grid_update_kernel(g.flip),
                (  # 2. momentum + gravity, walls
                    g.mp_parts,
                    g.box_parts,
                    g.box,
                    g.col_mask,
                    g.m,
                    g.v,
                    dt,
                    *self.gravity,
                    g.h,
                    g.pad,
                    g.size[0],
                    self.walls.kinds,
                    self.walls.mus,
                    g.inv_scale,
                    g.mo_parts,
                    g.v_old,
                ),
            ),
        ]
        for k, (o, a) in enumerate(zip(self.obstacles, active)):
            if a:
                launches += o.launches(g, dt, f"o{k}_", posed_by_host=False, particles=p)
        for k, b in enumerate(self.intruders):  # 3. bodies (their dynamics, on the device, at the step's end)
            launches += b.launches(g, dt, f"b{k}_", particles=p)
        launches.append(
            Launch(
                self._g2p,
                (  # 4-6. G2P, density, stress
                    p.x,
                    p.v,
                    p.C,
                    p.mass,
                    p.vol,
                    p.sigma,
                    p.s_yy,
                    p.eps_p,
                    p.gdot_p,
                    g.v,
                    g.h,
                    g.pad,
                    dt,
                    self.material.params,
                    1.0 / self.cfg.material.rho_floor,
                    g.v_old,
                    self.flip,
                ),
                unscalarized=self._lanes,
            )
        )
        for o, a in zip(self.obstacles, active):  # contact at the points (MPMConfig.contact "surface")
            if a:
                launches += o.point_launches(p, dt, 0.0)
        for k, b in enumerate(self.intruders):
            launches += b.point_launches(p, dt)
            launches += b.dynamics_launches(dt, f"b{k}_")  # on the device, from the step's whole impulse
        if self.fluidity is not None:  # nonlocal fluidity: the field from the step's first stress, then the flow
            f, m = self.fluidity, self.material
            kappa = (m.amplitude * m.grain_diameter / g.h) ** 2  # A^2 d^2 / h^2
            launches[:0] = [
                Launch(
                    fluidity_sources_kernel(f.chunked, f.fixed_scale is not None, lanes),
                    (
                        p.x,
                        p.mass,
                        p.sigma,
                        p.s_yy,
                        p.n,
                        f.parts,
                        f.box_parts,
                        f.box,
                        f.src,
                        g.h,
                        g.pad,
                        m.fluidity_params,
                        f.fixed_scale or 1.0,
                    ),
                    unscalarized=lanes,
                )
            ]
            sweeps = Launch(fluidity_jacobi_kernel(f.chunked), (f.src, f.g, f.g_tmp, f.excess, f.box, kappa))
            launches[1:1] = [sweeps] * m.sweep_pairs
            launches.append(
                Launch(
                    fluidity_relax_kernel(self._lanes),
                    (p.x, p.sigma, p.s_yy, p.eps_p, p.gdot_p, f.excess, g.h, g.pad, dt, m.relax_params),
                    unscalarized=self._lanes,
                )
            )
        return launches

    def step(self) -> None:
        """Advance one time step dt (SPEC 1 recipe, steps 1-6, then the rigid bodies).

        The kernels run as one compiled Taichi graph (see step_graph), or one call each with the
        benchmarks' ``BenchmarkSwitches(step_graph=False)``; both give the same numbers.
        """
        active = tuple(o.removal_time is None or self.t < o.removal_time for o in self.cfg.obstacles)
        launches = self._plans.get(active)
        if launches is None:
            launches = self._plans[active] = self._launches(active)
        values: dict = {}
        t_next = (self.step_count + 1) * self.dt
        for k, body in enumerate(self.intruders):  # rigid intruders (Coulomb, no tension)
            values.update(body.launch_values(t_next, f"b{k}_"))
        if self.switches.step_graph:
            graph = self._graphs.get(active)
            if graph is None:
                graph = self._graphs[active] = StepGraph(launches, values)
            graph.run(values)
        else:
            run_direct(launches, values)
        self.step_count += 1
        self._advance_bodies()

    def _advance_bodies(self) -> None:
        for body in self.intruders:
            body.after_step(self.t, self.dt)

    # ------------------------------------------------------------------ diagnostics
    def check_guards(self) -> None:
        """Stop with a diagnosis (after a failure checkpoint) on NaN, escape or CFL breach."""
        lx, lz = self.cfg.domain.size
        p = self.particles
        guard_scan(p.x, p.v, p.sigma, p.n, lx, lz, self.cfg.output.escape_margin_cells * self.h, self._scratch)
        out = self._scratch.to_numpy()
        if out[0] == 0 and out[1] > 0 and (self.walls.open_sides or self.cfg.output.escaped == "drop"):
            if self._remove_leaving(lx, lz, self.cfg.output.escape_margin_cells * self.h):
                out[1] = 0
        grains_ok = out[0] == 0 and out[1] == 0 and out[2] * self.dt <= self.cfg.time.max_cell_fraction * self.h
        diag = body_report(self.intruders, lx, lz, self.dt, self.h)  # the bodies' guards: NaN, escape, CFL
        if grains_ok and diag is None:
            return
        if not grains_ok:
            state = self.particles.to_numpy(["x", "v"])
            diag = guard_report(out, state["x"], state["v"], self.dt, self.h, self.cfg.time.max_cell_fraction)
        where = ""
        if self.run_dir is not None:
            path = self.run_dir / "checkpoint_failure.npz"
            self.save_checkpoint(path, require_finite=False)  # the broken state itself, for the diagnosis
            where = f"; state saved to {path}"
        raise SimulationError(f"{diag} at t={self.t:.6g} s (step {self.step_count}){where}")

    def _remove_leaving(self, lx: float, lz: float, margin: float) -> bool:
        """Remove the points more than ``margin`` outside [0, lx] x [0, lz]: beyond an open side
        (``BoundaryConfig``) as outflow, counted in ``outflow``; elsewhere as escapes with
        output.escaped = "drop" (counted in ``dropped``, a line on stderr). False, and nothing removed,
        if a point escaped through a side that is not open and escapes stop the run."""
        d = self.particles.to_numpy()
        x = d["x"]
        beyond = dict(zip(SIDES, (x[:, 0] < -margin, x[:, 0] > lx + margin, x[:, 1] < -margin, x[:, 1] > lz + margin)))
        outflow = np.zeros(len(x), dtype=bool)
        for side in self.walls.open_sides:
            outflow |= beyond[side]
        out = (beyond["left"] | beyond["right"] | beyond["floor"] | beyond["top"]) & ~outflow
        if out.any() and self.cfg.output.escaped != "drop":
            return False
        if (outflow | out).all():
            raise SimulationError(f"every point has left the domain at t={self.t:.6g} s (step {self.step_count})")
        self.outflow["points"] += int(outflow.sum())
        self.outflow["mass"] += float(d["mass"][outflow].sum())
        self._replace_particles({k: a[~(outflow | out)] for k, a in d.items()})
        if out.any():
            self._count_dropped(out, d)
        return True

    def _count_dropped(self, out: np.ndarray, d: dict[str, np.ndarray]) -> None:
        """Count the escaped points ``out`` of the state ``d`` (removed) in ``dropped``; say so on stderr."""
        x = d["x"]
        n, mass = int(out.sum()), float(d["mass"][out].sum())
        self.dropped["points"] += n
        self.dropped["mass"] += mass
        i = int(np.flatnonzero(out)[0])
        print(
            f"t = {self.t:.6g} s (step {self.step_count}): {n} escaped point(s) dropped, e.g. x={x[i]}, "
            f"v={d['v'][i]}; {self.dropped['points']} so far, {self.dropped['mass']:.3g} kg/m",
            file=sys.stderr,
        )

    def grain_energy_and_mass(self) -> tuple[float, float]:
        """Kinetic energy (J) and mass (kg) of the grains, 3D via the first intruder's width (else per m)."""
        kinetic_energy_and_mass(self.particles.v, self.particles.mass, self.particles.n, self._scratch)
        out = self._scratch.to_numpy()
        width = self.intruders[0].width if self.intruders else 1.0
        return float(out[0]) * width, float(out[1]) * width

    def record(self) -> dict:
        """Append one time-series row; forces are averaged since the previous row (3D, N)."""
        elapsed = (self.step_count - self._step_mark) * self.dt
        row: dict = {"time": self.t, "step": self.step_count}
        for k, body in enumerate(self.intruders):
            pre = "" if k == 0 else f"b{k}_"
            st = body.state
            row.update({f"{pre}{n}": getattr(st, n) for n in ("x", "z", "theta", "vx", "vz", "omega")})
            row[f"{pre}x"] += self.x_offset  # in the bed's frame, across window shifts
            # the total, then the part from the grid nodes ahead of the reference point (x > x_body;
            # behind = total - ahead)
            for suffix, impulse, marks in (
                ("", body.contact.read_impulse(), self._impulse_mark),
                ("_ahead", body.contact.read_impulse_ahead(), self._impulse_mark_ahead),
            ):
                f = (impulse - marks[k]) / elapsed if elapsed > 0 else np.zeros(3)
                marks[k] = impulse
                row.update({f"{pre}{n}{suffix}": f[i] * body.width for i, n in enumerate(("fx", "fz", "moment"))})
        ke, mass = self.grain_energy_and_mass()
        row.update({"kinetic_energy": ke, "grain_mass": mass})
        if self.walls.open_sides:  # grain_mass + outflow_mass is the mass of the start (less any dropped)
            row["outflow_mass"] = self.outflow["mass"] * (self.intruders[0].width if self.intruders else 1.0)
        self._step_mark = self.step_count
        self.rows.append(row)
        return row

    def particle_fields(self) -> dict[str, np.ndarray]:
        """Host copy of the particle state plus derived pressure and density."""
        d = self.particles.to_numpy()
        d["pressure"] = pressure(d["sigma"], d["s_yy"])
        d["density"] = d["mass"] / d["vol"]
        return d

    # ------------------------------------------------------------------ moving window
    def shift_window(self, shift: float) -> None:
        """Move the scene back by ``shift`` (m, a whole number of cells) along x: a treadmill under
        the bodies, so a long run fits a short domain.

        x -> x - shift for the points, the bodies and the fluidity's warm start; the points that
        leave through the left side are dropped; a strip of fresh bed (the configured bed's own
        points there, at rest in its geostatic state) fills the right side. Rows keep x in the bed's
        frame (``x_offset``). Only for scenes without static obstacles (they would move too)."""
        n_cells = int(round(shift / self.h))
        if n_cells < 1 or abs(n_cells * self.h - shift) > 1e-9 * self.h:
            raise InputError(f"shift must be a positive whole number of cells ({self.h:g} m), got {shift!r}")
        if self.cfg.obstacles:
            raise InputError("shift_window moves every body: it is not for scenes with static obstacles")
        lx = self.cfg.domain.size[0]
        if shift >= lx:
            raise InputError(f"shift ({shift:g} m) must be shorter than the domain ({lx:g} m)")
        d = self.particles.to_numpy()
        keep = d["x"][:, 0] >= shift
        fresh = self._fresh_bed(lx - shift)
        d = {k: np.concatenate([v[keep], fresh[k]]) for k, v in d.items()}
        d["x"][: int(keep.sum()), 0] -= shift
        self._replace_particles(d)
        if self.fluidity is not None:  # nodes move n_cells to the left; the fresh bed's start at rest
            g = self.fluidity.to_numpy()
            g[:-n_cells] = g[n_cells:]
            g[-n_cells:] = 0.0
            self.fluidity.load(g)
        for body in self.intruders:
            body.state.x -= shift
        self.x_offset += shift

    def _replace_particles(self, arrays: dict[str, np.ndarray]) -> None:
        """New particle arrays of another count; the step's launches and graphs, which hold the old
        arrays, are built again at the next step; the former arrays are freed."""
        old, self.particles = self.particles, Particles(arrays)
        self._plans.clear()
        self._graphs.clear()
        old.release()

    def _fresh_bed(self, x_from: float) -> dict[str, np.ndarray]:
        """Every particle field of the configured bed's points at x > ``x_from``, at rest."""
        cfg = self.cfg
        bed = build_bed(cfg.domain.size, self.h, cfg.domain.particles_per_cell, cfg.bed, cfg.material, self.gravity)
        sel = bed["x"][:, 0] > x_from
        n = int(sel.sum())
        return {name: (bed[name][sel] if name in bed else np.zeros((n, *shape))) for name, (shape, _) in FIELDS.items()}

    # ------------------------------------------------------------------ run loop and files
    def run(self, t_end: float | None = None, progress=None, checkpoint_end: bool = True) -> list[dict]:
        """Step to ``t_end`` (default cfg.time.t_end), recording, checking and saving on schedule.

        With ``output.checkpoint_every`` set and ``checkpoint_end``, the run folder's checkpoint is also
        written at ``t_end`` (when that is not on the schedule), so that the end state is kept and an
        extension of the run starts there; a run killed before its end resumes from its last scheduled
        checkpoint. A driver that calls ``run`` chunk by chunk passes ``checkpoint_end=False`` and
        checkpoints its own end."""
        out = self.cfg.output
        t_end = self.cfg.time.t_end if t_end is None else t_end
        n_end = int(round(t_end / self.dt))

        def every(period):
            return None if period is None else max(1, int(round(period / self.dt)))

        rec, snap, ckpt = every(out.record_every), every(out.snapshot_every), every(out.checkpoint_every)
        if self.run_dir is not None:
            mpm_io.write_resolved_config(self.run_dir, self.cfg, {"dt": self.dt, **self.limits}, self.switches)
        if self.step_count == 0 and not self.rows:
            self.record()
            if snap and self.run_dir is not None:
                self.write_snapshot()
        while self.step_count < n_end:
            self.step()
            n = self.step_count
            if n % out.guard_every_steps == 0 or n == n_end:
                self.check_guards()
            if n % rec == 0:
                self.record()
                if progress is not None:
                    progress(self)
            if self.run_dir is not None:
                if snap and n % snap == 0:
                    self.write_snapshot()
                if ckpt and n % ckpt == 0:
                    self.checkpoint_run_folder()
        if self.run_dir is not None:
            if checkpoint_end and ckpt and self.step_count % ckpt != 0:  # the end state: a longer run goes on from here
                self.checkpoint_run_folder()
            mpm_io.write_timeseries(self.run_dir / "timeseries.csv", self.rows)
        return self.rows

    def write_snapshot(self) -> Path:
        """VTK point cloud, the rigid bodies' outlines (VTK polygons with their pose), the
        ParaView collection ``snapshots.pvd`` of every snapshot in the folder at its physical
        time, and a PNG plot (equivalent plastic strain rate) of the particles."""
        d = self.particle_fields()
        snap_dir = self.run_dir / "snapshots"
        snap_dir.mkdir(parents=True, exist_ok=True)
        path = snap_dir / f"particles_{self.step_count:08d}.vtu"
        mpm_io.write_vtk(
            path,
            {
                "x": d["x"],
                "velocity": d["v"],
                "pressure": d["pressure"],
                "density": d["density"],
                "eps_p": d["eps_p"],
                "gdot_p": d["gdot_p"],
            },
        )
        polygons, poses = self.body_outlines()
        if polygons:
            mpm_io.write_bodies_vtk(snap_dir / f"bodies_{self.step_count:08d}.vtu", polygons, poses)
        self._write_snapshot_collection(snap_dir)
        mpm_io.plot_field(
            snap_dir / f"gdot_p_{self.step_count:08d}.png",
            d["x"],
            d["gdot_p"],
            "equivalent plastic strain rate (1/s)",
            polygons,
            self.cfg.domain.size,
            log=True,
        )
        return path

    def body_outlines(self) -> tuple[list[np.ndarray], dict[str, list[float]]]:
        """World-frame polygons of the intruders and of the obstacles still in place, and per
        polygon: body index (intruders 0, 1, ...; obstacles -1, -2, ...), pose and velocity."""
        polygons, poses = [], {k: [] for k in ("body", "x", "z", "theta", "vx", "vz", "omega")}
        for k, b in enumerate(self.intruders):
            s = b.state
            polygons.append(b.world_vertices())
            for key, value in zip(poses, (k, s.x, s.z, s.theta, s.vx, s.vz, s.omega)):
                poses[key].append(float(value))
        for k, o in enumerate(self.cfg.obstacles):
            if o.removal_time is None or self.t < o.removal_time:
                polygons.append(np.asarray(o.vertices, dtype=float))
                for key, value in zip(poses, (-1 - k, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0)):
                    poses[key].append(value)
        return polygons, poses

    def _write_snapshot_collection(self, snap_dir: Path) -> None:
        """snapshots.pvd listing every particles_/bodies_ file of the folder at step * dt (a
        resumed run's earlier snapshots included)."""
        entries = []
        for part, stem in enumerate(("particles", "bodies")):
            for f in sorted(snap_dir.glob(f"{stem}_*.vtu")):
                entries.append((int(f.stem.split("_")[1]) * self.dt, f.name, part))
        mpm_io.write_pvd(snap_dir / "snapshots.pvd", sorted(entries))

    def checkpoint_run_folder(self) -> None:
        """Save the state as the run folder's checkpoint, the one a resumed or extended run goes on from."""
        self.save_checkpoint(self.run_dir / CHECKPOINT)

    def save_checkpoint(self, path: Path, require_finite: bool = True) -> None:
        """Atomic checkpoint of everything needed to continue bit-for-bit (single thread); a state
        with NaN or inf is refused (SimulationError) unless ``require_finite`` is False."""
        meta = {
            "config": mpm_io.checkpoint_config(self.cfg),
            "step_count": self.step_count,
            "dt": self.dt,
            "rows": self.rows,
            "step_mark": self._step_mark,
            "x_offset": self.x_offset,
            "dropped": self.dropped,
            "outflow": self.outflow,
            "bodies": [b.state.as_dict() for b in self.intruders],
            "impulse": [b.contact.read_impulse().tolist() for b in self.intruders],
            "impulse_ahead": [b.contact.read_impulse_ahead().tolist() for b in self.intruders],
            "impulse_prev": [b.impulse_prev.tolist() for b in self.intruders],
            "impulse_mark": [a.tolist() for a in self._impulse_mark],
            "impulse_mark_ahead": [a.tolist() for a in self._impulse_mark_ahead],
        }
        if self.switches.changed():  # a benchmark's or test's run: resumed on its own switches
            meta[mpm_io.SWITCHES_KEY] = self.switches.changed()
        path.parent.mkdir(parents=True, exist_ok=True)
        arrays = self.particles.to_numpy()
        if self.fluidity is not None:  # the warm start of the next step's sweeps
            arrays[FLUIDITY_KEY] = self.fluidity.to_numpy()
        mpm_io.save_checkpoint(path, arrays, meta, require_finite=require_finite)
        if self.run_dir is not None and path.parent == self.run_dir:
            mpm_io.write_timeseries(self.run_dir / "timeseries.csv", self.rows)

    def load_checkpoint(self, path: Path) -> None:
        """Restore the state saved by :meth:`save_checkpoint` (same config: a checkpoint of another
        configuration is refused with an InputError naming the differences)."""
        arrays, meta = mpm_io.load_checkpoint(Path(path))
        diff = mpm_io.checkpoint_mismatch(meta.get("config"), self.cfg, self.switches, meta.get(mpm_io.SWITCHES_KEY))
        if diff:
            raise InputError(
                f"{path} is a checkpoint of another configuration (differs in {', '.join(diff[:6])}); it is not loaded"
            )
        self.restore(arrays, meta)

    def restore(self, arrays: dict[str, np.ndarray], meta: dict[str, Any]) -> None:
        """Restore a checkpoint already read (``mpm.io.load_checkpoint``; same config)."""
        if not math.isclose(meta["dt"], self.dt, rel_tol=1e-12):
            raise ValueError(f"checkpoint dt {meta['dt']} differs from this config's dt {self.dt}")
        arrays = dict(arrays)
        grid_fluidity = arrays.pop(FLUIDITY_KEY, None)
        if self.fluidity is not None and grid_fluidity is not None:
            self.fluidity.load(grid_fluidity)
        if len(arrays["x"]) == self.particles.n:
            self.particles.load(arrays)
        else:  # a moving window (shift_window) changed the number of points
            self._replace_particles(arrays)
        self.x_offset = float(meta.get("x_offset", 0.0))
        self.dropped = dict(meta.get("dropped", {"points": 0, "mass": 0.0}))
        self.outflow = dict(meta.get("outflow", {"points": 0, "mass": 0.0}))
        self.step_count = int(meta["step_count"])
        self.rows = list(meta["rows"])
        self._step_mark = int(meta["step_mark"])
        self._set_body_states(meta["bodies"])
        for k, body in enumerate(self.intruders):
            # a checkpoint from before the front / rear split has no part from ahead: it restarts at 0
            ahead = meta.get("impulse_ahead", [None] * len(self.intruders))[k]
            body.contact.write_impulse(meta["impulse"][k], ahead)
            body.impulse_prev = meta["impulse_prev"][k]
            self._impulse_mark[k] = np.asarray(meta["impulse_mark"][k])
            self._impulse_mark_ahead[k] = np.asarray(
                meta.get("impulse_mark_ahead", [np.zeros(3)] * len(self.intruders))[k]
            )

    def start_from(self, step_count: int, bodies: Sequence[dict[str, float]]) -> None:
        """Carry on another run's state (e.g. its points split for finer cells): the clock at
        ``step_count`` steps of this solver's dt, the bodies in ``bodies`` (``state.as_dict()``
        of each), and the force averages of the next rows starting here."""
        self._set_body_states(bodies)
        self.step_count = int(step_count)
        self._step_mark = self.step_count

    def _set_body_states(self, bodies: Sequence[dict[str, float]]) -> None:
        """Each intruder's state from a ``state.as_dict()`` (a checkpoint's "bodies")."""
        if len(bodies) != len(self.intruders):
            raise ValueError(f"{len(bodies)} body states for {len(self.intruders)} bodies")
        for body, state in zip(self.intruders, bodies):
            for name, val in state.items():
                setattr(body.state, name, val)

    @classmethod
    def resume(cls, run_dir: str | Path) -> "Solver":
        """Rebuild a solver from a run folder's config.json and continue from checkpoint.npz.

        The run's switches come with it (:func:`intrusim.mpm.io.split_switches`): those it recorded,
        or in a folder written while they were settings, its ``backend`` keys of them."""
        import json

        run_dir = Path(run_dir)
        path = run_dir / "config.json"
        payload = json.loads(path.read_text())
        config, switches = mpm_io.split_switches(payload["config"], payload.get(mpm_io.SWITCHES_KEY), str(path))
        cfg = MPMConfig.model_validate(config)
        cfg.output.directory = str(run_dir)  # this folder, wherever the run was first written
        solver = cls(cfg, switches=switches)
        ckpt = run_dir / CHECKPOINT
        if ckpt.exists():
            solver.load_checkpoint(ckpt)
        return solver

    def continue_in_run_dir(self) -> bool:
        """Load the run folder's checkpoint if there is one; True if loaded.

        A folder that holds a run of another configuration (:func:`intrusim.mpm.io.refuse_other_run`)
        is refused with an InputError naming the differences, before anything in it is touched:
        going on would overwrite that run's time series and its checkpoint."""
        if self.run_dir is None:
            return False
        mpm_io.refuse_other_run(self.run_dir, self.cfg, self.switches)
        ckpt = self.run_dir / CHECKPOINT
        if not ckpt.exists():
            return False
        self.load_checkpoint(ckpt)
        return True
