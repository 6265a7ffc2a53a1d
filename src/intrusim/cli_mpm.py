"""`intrusim mpm ...`: the continuum (MPM) side of the command line."""

from __future__ import annotations

import math
from pathlib import Path
from typing import TYPE_CHECKING

import typer

from intrusim._checks import InputError, check_writable
from intrusim.errors import guarded_group, validation_message

if TYPE_CHECKING:
    from intrusim.scenarios.mpm_locomotion import MPMSteadyState

mpm_app = typer.Typer(
    help="Continuum (MPM) simulations: wheels and runner, sweeps, movies.", no_args_is_help=True, cls=guarded_group()
)

SCENARIOS = ("wheel", "small-wheel", "runner", "wheel-10-grousers", "wheel-30-grousers", "wheel-tall-grousers")


def _finite(name: str, value: float | None) -> float | None:
    """A flag's number: None (not given) or finite (an InputError names the flag)."""
    if value is not None and not math.isfinite(value):
        raise InputError(f"--{name.replace('_', '-')} must be a finite number, got {value!r}")
    return value


SETTINGS_HELP = (
    "Settings TOML file: keys of MPMSettings (docs/mpm.md), applied over the base settings "
    "(quick or paper, by the scenario's body) and under --set."
)
SET_HELP = (
    "KEY=VALUE, repeatable, applied in order after --settings: a setting (cell_size, length, t_max, "
    "contact_band, flip, shape, treadmill=[X_TRIGGER, X_TARGET], drop_escaped, arch, frames_every, "
    "max_steps, mu_i_diameter, fluidity_diameter, or any MPMSettings field, dotted for its parts: "
    "mu_i.grain_diameter=1e-3). VALUE is read as TOML, else as a bare string (docs/mpm.md)."
)


def _case(
    scenario: str,
    quick: bool,
    out: Path | None = None,
    settings: Path | None = None,
    sets: list[str] | tuple[str, ...] = (),
    threads: int | None = None,
    preset: str | None = None,
):
    """The MPM locomotion case of a command: the base settings of the scenario's body (``preset``:
    paper, quick or reference; ``quick``: the quick one), then the ``--settings`` file, then each
    ``--set`` in order, then ``threads``; all validated as one (MPMSettings), so a bad key or value
    is refused before any compute."""
    from intrusim.scenarios import load_scenario
    from intrusim.scenarios.mpm_locomotion import MPMLocomotion
    from intrusim.scenarios.mpm_settings import case_settings

    sc = load_scenario(scenario)  # a shipped name, or the user's own wheel or runner (the TOML rft / drft take)
    s = case_settings(sc, quick, settings, sets or (), preset=preset)
    if threads is not None:
        if threads < 1:
            raise InputError(f"--threads must be >= 1, got {threads}")
        s = s.validated_copy(cpu_threads=threads)
    return MPMLocomotion(scenario=sc, mpm=s, out_root=None if out is None else str(out))


PRESET_HELP = (
    "Base settings: paper (the paper's set-up: its rate-independent law, 5 mm cells, 1 m box; the default), "
    "quick (as --quick: 2 cm cells, short: trends only) or reference (the nonlocal law at a fifth of the body's "
    "thinnest feature, a bed that follows the body, run until settled: hours of CPU a point; docs/convergence.md)."
)
SCENARIO_HELP = (
    f"One of {', '.join(SCENARIOS)}, or a scenario .toml file (as for `intrusim steady`; MPM settings by its body)."
)


@mpm_app.command("steady")
def steady(
    scenario: str = typer.Option("wheel", help=SCENARIO_HELP),
    omega_rpm: float = typer.Option(30.0, help="Spin, RPM (forward rolling)."),
    quick: bool = typer.Option(False, help="Coarse grid (2 cm cells), short run: seconds, not minutes."),
    preset: str = typer.Option(None, help=PRESET_HELP),
    out: Path = typer.Option(
        None,
        help="Folder of the run folder (time series, config, checkpoints, fields). A larger t_max on a finished run's folder extends that run from its checkpoint.",
    ),
    settings: Path = typer.Option(None, "--settings", help=SETTINGS_HELP),
    sets: list[str] = typer.Option([], "--set", help=SET_HELP),
    threads: int = typer.Option(None, help="CPU threads (default: all cores)."),
) -> None:
    """One MPM locomotion run to steady state; prints v, sinkage, slip and the rear surface drop."""
    try:
        case = _case(scenario, quick, out, settings, sets, threads, preset)
        _finite("omega_rpm", omega_rpm)
        if out is not None:
            check_writable(out)
        typer.echo(f"{case.name}: omega = {omega_rpm:g} RPM, grid {case.mpm.cells}, t_max {case.mpm.t_max} s")
        last = [-1.0]

        def progress(d: dict) -> None:
            if d["t"] - last[0] >= 0.25 - 1e-9:
                last[0] = d["t"]
                typer.echo(f"  t = {d['t']:.2f} s  x = {d['x']:.3f} m  vx = {d['vx']:.3f} m/s  wall {d['wall']:.0f} s")

        from intrusim.mpm.io import run_lock, safe_child
        from intrusim.scenarios.mpm_locomotion import refuse_other_settings, run_mpm_steady, write_result

        run_dir = None if out is None else safe_child(out, f"{case.scenario.name}_{omega_rpm:g}rpm")
        with run_lock(run_dir):  # one writer per run folder
            refuse_other_settings(run_dir, case.mpm)
            if run_dir is not None:  # a result.json is true of the run that wrote it: gone until this one ends
                from intrusim.mpm.io import refuse_other_run
                from intrusim.scenarios.mpm_locomotion import mpm_config

                refuse_other_run(run_dir, mpm_config(case.scenario, case.mpm, omega_rpm, run_dir))  # before touching it
                (run_dir / "result.json").unlink(missing_ok=True)
            st = run_mpm_steady(case.scenario, case.mpm, omega_rpm, run_dir, progress)
            if run_dir is not None:  # finished: a sweep or figure on this folder reuses it
                write_result(run_dir, st)
    except InputError as err:
        typer.echo(f"error: {err}", err=True)
        raise typer.Exit(2) from None
    typer.echo(steady_line(st))


def steady_line(st: MPMSteadyState) -> str:
    """The one-line summary of an MPM locomotion run: "steady state over ..." only when the run
    settled (v and sinkage each within the test's tolerance over its last two revolutions,
    :mod:`intrusim.analysis.settling`); otherwise the numbers are called window averages, what the
    body was still doing is said (still sinking at X mm/s ...) and the way to extend the run named."""
    judged = st.settling
    head = f"steady state over t = {st.window[0]:.2f}-{st.window[1]:.2f} s"
    if st.settled and judged is not None:
        head += f" ({judged.text})"
    if not st.settled:
        h = st.meta.get("cell_size")
        finer = "" if h is None else f", or halve the cells, --set cell_size={h / 2:.4g}"
        known = (  # what was measured for this body (docs/convergence.md)
            ": at 30 RPM this wheel did not settle in 8 s at 5 mm cells and did after 3 s at 2.5 mm; at 90 RPM "
            "it kept sinking through 6 s at both"
            if st.meta.get("scenario") == "grousered_wheel"
            else ""
        )
        what = judged.text if judged is not None else f"the window's halves differ by {st.drift:.1%}"
        if st.meta.get("stop") == "wall":
            what += "; stopped at the wall: --set 'treadmill=[x_trigger, x_target]' keeps the bed under it"
        head = (
            f"NOT settled ({what}; extend the run with --set t_max=T (--set settle_tol=0.01 stops it once settled) "
            f"or start its window later with --set settle_time=S, on the same --out{finer}; docs/convergence.md"
            f"{known}): averages over t = {st.window[0]:.2f}-{st.window[1]:.2f} s"
        )
    return (
        f"{head}: v = {st.velocity:.4f} m/s, sinkage = {st.sinkage * 1e3:.2f} mm, slip = {st.slip:.3f}, "
        f"rear surface drop = {st.surface_drop * 1e3:.1f} mm "
        f"({st.steps} steps, {st.meta['particles']} particles, {st.wall_time:.0f} s wall)"
    )


@mpm_app.command("sweep")
def sweep(
    scenario: str = typer.Option("wheel", help=SCENARIO_HELP),
    omega_rpm: str = typer.Option(
        "10,20,30,40,50,60,70,80,90", help="RPM list 'a,b,c' or range 'start:stop:step' (as `intrusim sweep`)."
    ),
    quick: bool = typer.Option(False, help="Coarse grid, short runs."),
    preset: str = typer.Option(None, help=PRESET_HELP),
    out: Path = typer.Option(Path("runs/mpm"), help="Folder for the sweep CSV and one run folder per point."),
    settings: Path = typer.Option(None, "--settings", help=SETTINGS_HELP),
    sets: list[str] = typer.Option([], "--set", help=SET_HELP),
    workers: int = typer.Option(
        2,
        help="MPM runs at once, each in a Dask worker process on cores / workers threads (at most the points; "
        "1: one after another in this process).",
    ),
    scheduler: str = typer.Option(None, help="Address of an existing Dask scheduler (default: a local cluster)."),
    serial: bool = typer.Option(False, help="Run the points one after another in this process (as --workers 1)."),
    oversubscribe: bool = typer.Option(
        False, "--oversubscribe", help="Allow more --workers than this machine's cores."
    ),
) -> None:
    """An omega sweep of MPM runs on a Dask cluster; writes SCENARIO_mpm_sweep.csv in --out (and the
    runs' settings beside it, SCENARIO_mpm_sweep.settings.json) and prints a table. Each run prints
    its progress (simulated time reached, speed, ETA) every few seconds, and a line when it ends.
    Exit code 1 if a point failed (the others are kept in the CSV and their run folders)."""
    import os

    from intrusim.analysis.sweep import omega_list, sweep_omega
    from intrusim.figures.mpm import run_count
    from intrusim.mpm.io import safe_child
    from intrusim.scenarios.locomotor import write_body
    from intrusim.scenarios.mpm_locomotion import check_run
    from intrusim.scenarios.mpm_settings import write_record

    try:
        omegas = omega_list(omega_rpm)  # before anything is made on disk
        if not omegas:
            raise InputError(f"--omega-rpm gives no angular velocity, got {omega_rpm!r}")
        cores = os.cpu_count() or 1
        if workers < 1:
            raise InputError(f"--workers must be >= 1, got {workers}")
        if workers > cores and scheduler is None and not serial and not oversubscribe:
            raise InputError(
                f"--workers {workers} is more than this machine's {cores} cores "
                "(--oversubscribe to run them anyway, or --scheduler for a bigger cluster)"
            )
        at_once = run_count(workers, not serial, len(omegas))  # no more workers than points: idle cores
        serial = serial or (at_once == 1 and scheduler is None)  # one at a time: in this process
        threads = max(1, cores // at_once) if not serial else None
        case = _case(scenario, quick, out, settings, sets, threads, preset)
        csv_path = safe_child(out, f"{case.scenario.name}_mpm_sweep.csv")
        for w in omegas:  # each point's run folder name and run (grid, steps, fit), checked before any compute
            check_run(case.scenario, case.mpm, w, case.run_dir(w))
        check_writable(out)
        out.mkdir(parents=True, exist_ok=True)
    except InputError as err:
        typer.echo(f"error: {err}", err=True)
        raise typer.Exit(2) from None
    res = sweep_omega(case, "mpm", omegas, parallel=not serial, scheduler_address=scheduler, n_workers=at_once)
    path = res.to_csv(csv_path)
    write_record(csv_path, case.scenario.name, {w: case.mpm for w in omegas})
    body = write_body(csv_path.with_suffix(".body.json"), case.scenario)
    typer.echo(res.table())
    typer.echo(f"wrote {path} and {body}")
    if res.errors:
        typer.echo(f"error: {len(res.errors)} of {len(res.records)} points failed (see the table)", err=True)
        raise typer.Exit(1)


@mpm_app.command("references")
def references(
    out: Path = typer.Option(
        Path("runs/references"), help="Root folder of the runs and the tables (reused: run again to finish)."
    ),
    quick: bool = typer.Option(False, help="2 cm cells for the bodies, 5 mm for the plates, fewer points: minutes."),
    only: str = typer.Option(
        None,
        help="Comma-separated parts of the set (default all): wheel, small-wheel, wheel-10-grousers, "
        "wheel-30-grousers, wheel-tall-grousers, runner, plate-drag, alpha-map.",
    ),
    workers: int = typer.Option(
        None,
        min=1,
        help="MPM runs at once: each sweep's omegas and the RFT-map plates, each in a worker process "
        "(default: one per core; 1: the sweeps' runs one after another in this process).",
    ),
) -> None:
    """The MPM reference set of the reduced-order model (intrusim.figures.reference_set): omega sweeps
    of six bodies, plate drag and the medium's RFT map; every run kept under --out and reused.
    Exit code 1 if a point failed (the others are kept in the tables)."""
    from intrusim.figures.reference_set import make_references, selected

    try:
        parts = selected(None if only is None else [s.strip() for s in only.split(",") if s.strip()])
        check_writable(out)
    except InputError as err:
        typer.echo(f"error: {err}", err=True)
        raise typer.Exit(2) from None
    index = make_references(out, quick=quick, only=parts, workers=workers, echo=typer.echo)
    bad = {k: v for k, v in index["parts"].items() if v.get("failed_omega_rpm") or v.get("failed")}
    for name, part in index["parts"].items():
        typer.echo(f"{name}: {out / part['table']}")
    typer.echo(f"wrote {out / 'references.json'}")
    if bad:
        typer.echo(f"error: points failed in {', '.join(bad)} (see references.json); run again to retry them", err=True)
        raise typer.Exit(1)


@mpm_app.command("collect")
def collect(
    folder: Path = typer.Argument(..., help="Folder of finished run folders (each with result.json)."),
    out: Path = typer.Option(None, help="Sweep CSV to write (default FOLDER/SCENARIO_mpm_sweep.csv)."),
    window_from: float = typer.Option(
        None,
        "--from",
        help="Average from this time on, s (default: ramp + settle time; "
        "a runner: whole revolutions from the end). For runs that settled late.",
    ),
    last: float = typer.Option(
        None,
        "--last",
        help="Average over each run's last LAST seconds, s (runs of different "
        "lengths, each settled by its own end; not with --from).",
    ),
) -> None:
    """Gather finished runs (e.g. `mpm steady` runs of one case on beds of different lengths) into
    the sweep CSV that `reproduce --mpm --runs` and `calibrate --mpm` read."""
    import json

    from intrusim.analysis.sweep import SweepResult, steady_record
    from intrusim.scenarios.mpm_locomotion import load_result

    _finite("from", window_from)
    _finite("last", last)
    if last is not None and (window_from is not None or not last > 0):
        typer.echo("error: --last must be > 0 and cannot be given with --from", err=True)
        raise typer.Exit(2)

    infos = {
        r.parent: json.loads((r.parent / "locomotion.json").read_text())
        for r in sorted(folder.glob("*/result.json"))
        if (r.parent / "locomotion.json").exists()
    }
    names = {info["scenario"]["name"] for info in infos.values()}
    if not infos or len(names) != 1:
        typer.echo(
            f"error: {folder} needs finished run folders (result.json, locomotion.json) of one scenario; "
            f"found {len(infos)} runs of {sorted(names) or 'none'}",
            err=True,
        )
        raise typer.Exit(2)

    def start(run: Path) -> float | None:  # --last: the window ends where the run's own window ends
        return window_from if last is None else json.loads((run / "result.json").read_text())["window"][1] - last

    try:
        records = sorted(
            (
                steady_record(float(info["omega_rpm"]), load_result(run, t_start=start(run)))
                for run, info in infos.items()
            ),
            key=lambda rec: rec["omega_rpm"],
        )
    except InputError as err:
        typer.echo(f"error: {err}", err=True)
        raise typer.Exit(2) from None
    res = SweepResult(names.pop(), "mpm", None, records, meta={"source": str(folder)})
    path = res.to_csv(out or folder / f"{res.scenario}_mpm_sweep.csv")
    from intrusim.scenarios.mpm_settings import record_path, write_record

    recorded = {float(info["omega_rpm"]): info["settings"] for info in infos.values() if "settings" in info}
    if recorded:  # the runs' settings, which `reproduce` checks against the case a figure asks for
        write_record(path, res.scenario, recorded)
    else:  # none recorded: a record of an earlier sweep beside this CSV is not true of it
        record_path(path).unlink(missing_ok=True)
    typer.echo(res.table())
    typer.echo(f"wrote {path}")


@mpm_app.command("movie")
def movie(
    run_dir: Path = typer.Argument(..., help="Run folder holding frames/ (run with --set frames_every=SECONDS)."),
    field: str = typer.Option("gdot_p", help="gdot_p, speed or eps_p."),
    out: Path = typer.Option(None, help="MP4 path (default RUN_DIR/FIELD.mp4)."),
    fps: float = typer.Option(20.0, help="Frames per second."),
) -> None:
    """Render a run's saved frames to an MP4 movie (Movies S7, S8)."""
    from intrusim.io.movie import movie_from_frames

    try:
        vmax = {"gdot_p": 100.0, "speed": 0.5, "eps_p": 2.0}.get(field, 1.0)
        vmin = 0.1 if field == "gdot_p" else 0.0
        path = movie_from_frames(run_dir / "frames", out or run_dir / f"{field}.mp4", field, fps, vmin=vmin, vmax=vmax)
    except (FileNotFoundError, ValueError) as err:
        typer.echo(f"error: {err}", err=True)
        raise typer.Exit(2) from None
    typer.echo(f"wrote {path}")


def _progress_bar(total: float, start: float = 0.0):
    """A tqdm bar over physical time, updated at each record (a callback for ``Solver.run``); its
    count never passes its total (the last step may end a fraction of dt past t_end)."""
    from tqdm import tqdm

    total = round(total, 6)
    bar = tqdm(
        total=total,
        initial=min(round(start, 6), total),
        unit="s(sim)",
        desc="MPM",
        bar_format="{l_bar}{bar}| {n:.3f}/{total:.3f} s [{elapsed}<{remaining}]",
    )

    def update(solver) -> None:
        bar.update(max(0.0, min(round(solver.t, 9), total) - bar.n))

    return bar, update


def _run_solver(solver, t_end: float) -> None:
    from intrusim.mpm.diagnostics import SimulationError

    bar, update = _progress_bar(t_end, solver.t)
    try:
        solver.run(
            t_end=t_end, progress=update, checkpoint_end=False
        )  # the end state below, with or without a schedule
        update(solver)
    except SimulationError as err:
        bar.close()  # the error on its own line, not at the end of the bar's
        typer.echo(f"error: {err}", err=True)
        raise typer.Exit(1) from None
    finally:
        bar.close()
    if (
        solver.run_dir is not None
    ):  # the end state: a longer run (resume --t-end, or run with a later t_end) goes on from here
        solver.checkpoint_run_folder()
    last = solver.rows[-1]
    typer.echo(
        f"done: t = {solver.t:.4g} s, {solver.step_count} steps of {solver.dt:.3g} s, {solver.particles.n} points"
    )
    if solver.run_dir is not None:
        typer.echo(f"run folder: {solver.run_dir} (config.json, timeseries.csv, snapshots/, checkpoint.npz)")
    forces = {k: last[k] for k in ("fx", "fz", "moment") if k in last}
    if forces:
        typer.echo("last forces (N, N m): " + ", ".join(f"{k} = {v:.4g}" for k, v in forces.items()))


@mpm_app.command("run")
def run(
    config: Path = typer.Argument(..., help="MPM configuration, TOML (any MPMConfig field; see docs/mpm.md)."),
    out: Path = typer.Option(None, help="Run folder (overrides output.directory of the file)."),
    max_steps: int = typer.Option(
        None,
        "--max-steps",
        help="Most time steps the run may take (overrides time.max_steps, default 2e7): a run estimated to take more (t_end / dt) is refused before it starts.",
    ),
    threads: int = typer.Option(None, help="CPU threads (overrides backend.cpu_threads; default: all cores)."),
) -> None:
    """Run an MPM simulation from a configuration file (validated before any compute).

    On a run folder that already holds this configuration the run goes on from its checkpoint (a
    later t_end extends a finished run); a folder of another configuration is refused."""
    import tomllib

    from pydantic import ValidationError

    from intrusim.mpm.config import MPMConfig
    from intrusim.mpm.io import run_lock

    if not config.is_file():
        raise InputError(f"no such file: {config}" if not config.exists() else f"{config} is not a file")
    try:
        data = tomllib.loads(config.read_text())
        if out is not None:
            data = {**data, "output": {**data.get("output", {}), "directory": str(out)}}
        if max_steps is not None:
            data = {**data, "time": {**data.get("time", {}), "max_steps": max_steps}}
        if threads is not None:
            data = {**data, "backend": {**data.get("backend", {}), "cpu_threads": threads}}
        cfg = MPMConfig.model_validate(data)
    except UnicodeDecodeError:
        raise InputError(f"invalid configuration {config}: not a text (TOML) file") from None
    except tomllib.TOMLDecodeError as err:
        raise InputError(f"invalid configuration {config}: {err}") from None
    except ValidationError as err:
        raise InputError(f"invalid configuration {config}: {validation_message(err)}") from None
    from intrusim.mpm.solver import Solver

    run_dir = None if cfg.output.directory is None else Path(cfg.output.directory)
    with run_lock(run_dir):  # one writer per run folder
        solver = Solver(cfg)
        if solver.continue_in_run_dir():
            typer.echo(
                f"continuing {solver.run_dir} from its checkpoint at t = {solver.t:.4g} s (step {solver.step_count})"
            )
        _run_solver(solver, cfg.time.t_end)


@mpm_app.command("resume")
def resume(
    run_dir: Path = typer.Argument(..., help="Run folder of an interrupted run (config.json, checkpoint.npz)."),
    t_end: float = typer.Option(None, help="New end time, s (default: the configured one)."),
) -> None:
    """Continue an interrupted (or finished) run from its last checkpoint."""
    from intrusim.mpm.io import run_lock
    from intrusim.mpm.solver import Solver
    from intrusim.validation import check_run_size

    if not (run_dir / "config.json").is_file():
        raise InputError(f"{run_dir} has no config.json (not a run folder)")
    if (run_dir / "locomotion.json").exists():  # its result.json, progress.json and fields are kept by `mpm steady`
        raise InputError(
            f"{run_dir} is an `mpm steady` / `mpm sweep` run: go on with the same command and a larger "
            "t_max (--set t_max=SECONDS) on its --out folder, which keeps its result consistent"
        )
    if t_end is not None and not (math.isfinite(t_end) and t_end > 0):
        raise InputError(f"--t-end must be a finite time > 0 s, got {t_end!r}")
    with run_lock(run_dir):
        solver = Solver.resume(run_dir)
        end = t_end if t_end is not None else solver.cfg.time.t_end
        if end > solver.cfg.time.t_end:
            time = solver.cfg.time.model_copy(update={"t_end": end})
            check_run_size(solver.cfg.model_copy(update={"time": time}), solver.dt)
            solver.cfg.time.t_end = end  # config.json records the run's new end
        typer.echo(f"resuming {run_dir} at t = {solver.t:.4g} s (step {solver.step_count})")
        _run_solver(solver, end)
