"""Command-line interface: ``intrusim --help``."""

from __future__ import annotations

from pathlib import Path
from typing import Any, Optional

import numpy as np
import typer

from intrusim._checks import InputError, check_workers, check_writable, finite
from intrusim._version import __version__
from intrusim.errors import guarded_group
from intrusim.forces import make_force_model
from intrusim.geometry import grousered_wheel
from intrusim.kinematics import BodyState
from intrusim.params import RPM, table_s1

app = typer.Typer(
    help="intrusim: granular intrusion with MPM, RFT and Dynamic RFT.", no_args_is_help=True, cls=guarded_group()
)


SCENARIO_HELP = (
    "wheel, small-wheel, runner, wheel-10-grousers, wheel-30-grousers, wheel-tall-grousers, or a scenario .toml file."
)
MODEL_HELP = (
    "Force model: rft, drft-inertial, drft, or a model file (*.model.json) written by `intrusim calibrate`: "
    "its kind and parameters drive this scenario's body."
)


def _show_version(value: bool) -> None:
    if value:
        typer.echo(f"intrusim {__version__}")
        raise typer.Exit()


@app.callback()
def main(
    ctx: typer.Context,
    debug: bool = typer.Option(False, "--debug", help="On an error show the traceback, not one line."),
    version: bool = typer.Option(
        False, "--version", callback=_show_version, is_eager=True, help="Print the version and exit."
    ),
) -> None:
    """Granular intrusion toolkit (Agarwal, Karsai, Goldman, Kamrin 2021).

    Exit codes: 0 done; 1 the run failed (its diagnosis printed, its run folder and checkpoint kept);
    2 bad input, refused before any compute (one line naming the field and the value)."""
    ctx.ensure_object(dict)["debug"] = debug


@app.command()
def version() -> None:
    """Print the package version."""
    typer.echo(f"intrusim {__version__}")


@app.command()
def forces(
    omega_rpm: float = typer.Option(30.0, help="Wheel spin, RPM (forward rolling)."),
    slip: float = typer.Option(0.3, help="Slip 1 - v/(r omega) used to set the forward speed."),
    sinkage_mm: str = typer.Option("5,10,15,20,25", help="Comma-separated sinkages of the lowest grouser tip, mm."),
    lam: float = typer.Option(1.0, help="lambda of the inertial correction."),
) -> None:
    """Granular force on the paper's grousered wheel (Table S1) from RFT, inertial-only DRFT and DRFT."""
    try:
        if omega_rpm <= 0 or not np.isfinite(omega_rpm):
            raise InputError(f"omega_rpm must be > 0, got {omega_rpm}")
        finite("--slip", slip)
        finite("--lam", lam)
        depths = [finite("--sinkage-mm", s) * 1e-3 for s in sinkage_mm.split(",") if s.strip()]
        if not depths:
            raise InputError(f"--sinkage-mm needs at least one number, got {sinkage_mm!r}")
        wheel_cfg = table_s1()["grousered_wheel"]
        true_wheel = grousered_wheel()
        wheel = grousered_wheel(grouser_height_scale=1 / 3)  # grouser shadowing (paper, Methods)
        omega = omega_rpm * RPM
        v = (1 - slip) * wheel.radius * omega
        models = {
            k: make_force_model(k, wheel, lam=lam, structural="wheel-rear-half")
            for k in ("rft", "drft-inertial", "drft")
        }
    except (InputError, ValueError) as err:
        typer.echo(f"error: {err}", err=True)
        raise typer.Exit(2) from None
    weight = wheel_cfg["effective_vertical_inertia"] * wheel_cfg["gravity"]
    typer.echo(
        f"grousered wheel (Table S1): D_out = {true_wheel.outer_diameter * 1e3:.0f} mm, "
        f"{len(wheel.elements)} elements, omega = {omega_rpm:g} RPM, v = {v * 1e3:.0f} mm/s (slip {slip:g}), "
        f"weight m_z g = {weight:.1f} N"
    )
    typer.echo(f"{'sinkage mm':>10} | {'model':>13} | {'Fx N':>8} | {'Fz N':>8} | {'M N m':>8}")
    for d in depths:
        state = BodyState(0.0, wheel.radius - d, 0.0, v, 0.0, -omega)
        for name, m in models.items():
            w = m.wrench(state)
            typer.echo(f"{d * 1e3:10.1f} | {name:>13} | {w.fx:8.2f} | {w.fz:8.2f} | {w.moment:8.3f}")


def _fail(err: Exception) -> None:
    typer.echo(f"error: {err}", err=True)
    raise typer.Exit(2)


@app.command()
def steady(
    scenario: str = typer.Option("wheel", help=SCENARIO_HELP),
    model: str = typer.Option("drft", help=MODEL_HELP),
    omega_rpm: float = typer.Option(30.0, help="Spin, RPM (> 0, forward rolling)."),
    lam: Optional[float] = typer.Option(None, help="lambda of the inertial correction (default: the scenario's)."),
    rft_coefficients: Optional[Path] = typer.Option(
        None,
        help="RFT coefficient table (JSON/TOML, N/cm^3; e.g. measured on the MPM medium by examples/mpm_rft_map.py) in place of the generic one, used as it is (xi = 1).",
    ),
) -> None:
    """Steady-state speed, sinkage and slip of a driven wheel or runner."""
    from intrusim.analysis.steady import NoContactError, run_steady
    from intrusim.bodies import IntegratorError
    from intrusim.scenarios import load_scenario

    try:
        kind, scn = with_model(model, load_scenario(scenario), rft_coefficients)
        st = run_steady(scn, kind, omega_rpm, lam)
    except (InputError, IntegratorError, NoContactError) as err:
        _fail(err)
    typer.echo(
        f"{scn.name}, {_model_name(model, kind)} (lambda = {st.meta['lam']:g}), omega = {omega_rpm:g} RPM, dt = {st.meta['dt'] * 1e3:.3g} ms, "
        f"window {st.window[0]:.2f}-{st.window[1]:.2f} s ({st.revolutions} rev){'' if st.settled else ', NOT SETTLED'}"
    )
    if st.meta.get("retried"):
        typer.echo(f"note: run with {st.meta['retried']}")
    typer.echo(
        f"{'v m/s':>8} | {'sinkage mm':>10} | {'slip':>6} | {'v/sqrt(gl)':>10} | {'sinkage/l':>9} | {'omega/omega0':>12}"
    )
    typer.echo(
        f"{st.velocity:8.4f} | {st.sinkage * 1e3:10.2f} | {st.slip:6.3f} | {st.velocity / scn.velocity_scale:10.4f} | "
        f"{st.sinkage / scn.length_scale:9.4f} | {st.omega / scn.omega_0:12.3f}"
    )


def with_model(model: str, scn: Any, rft_coefficients: Optional[Path]) -> tuple[str, Any]:
    """The kind and scenario of ``--model`` (a kind, or a model file's kind and force model) and
    ``--rft-coefficients`` (not with a model file, which names its own table)."""
    from intrusim.analysis.model_file import resolve_model, with_rft_table

    kind, out = resolve_model(model, scn)
    if out is not scn and rft_coefficients is not None:
        raise InputError("--rft-coefficients and a model file: the model file holds its own force model")
    return kind, with_rft_table(out, rft_coefficients)


def _model_name(model: str, kind: str) -> str:
    return kind if model == kind else f"{kind} of {model}"


@app.command()
def sweep(
    scenario: str = typer.Option("wheel", help=SCENARIO_HELP),
    model: str = typer.Option("drft", help=MODEL_HELP),
    omega_rpm: str = typer.Option("10:90:10", help="RPM list 'a,b,c' or range 'start:stop:step'."),
    lam: Optional[float] = typer.Option(None, help="lambda of the inertial correction."),
    parallel: bool = typer.Option(True, help="Run the points on a Dask cluster."),
    scheduler_address: Optional[str] = typer.Option(None, help="Existing Dask scheduler (default: a LocalCluster)."),
    csv: Optional[Path] = typer.Option(
        None, help="Also write the records to this CSV file (SI, the unit in each column: velocity_m_s, sinkage_m ...)."
    ),
    rft_coefficients: Optional[Path] = typer.Option(
        None,
        help="RFT coefficient table (JSON/TOML, N/cm^3; e.g. measured on the MPM medium by examples/mpm_rft_map.py) in place of the generic one, used as it is (xi = 1).",
    ),
    workers: Optional[int] = typer.Option(
        None,
        min=1,
        help="Points at once: processes of the local Dask cluster (default: one per core; 1: in this process).",
    ),
) -> None:
    """Steady states over a range of omega (failed points are reported, the rest kept)."""

    from intrusim.analysis.sweep import omega_list, sweep_omega
    from intrusim.scenarios import load_scenario
    from intrusim.scenarios.locomotor import write_body

    try:
        check_workers(workers)
        if csv is not None:
            check_writable(csv.parent, "--csv")  # before the compute, not after it
        body = load_scenario(scenario)
        kind, scn = with_model(model, body, rft_coefficients)
        res = sweep_omega(
            scn, kind, omega_list(omega_rpm), lam=lam, parallel=parallel and workers != 1,
            scheduler_address=scheduler_address, n_workers=workers,
        )  # fmt: skip
    except InputError as err:
        _fail(err)
    typer.echo(f"{scn.name}, {_model_name(model, kind)}, lambda = {lam if lam is not None else scn.force_model.lam:g}")
    typer.echo(res.table())
    if csv is not None:
        typer.echo(f"wrote {res.to_csv(csv)} and {write_body(csv.with_suffix('.body.json'), body, scn.external_fx)}")
    if res.errors:
        raise typer.Exit(1)


@app.command()
def reproduce(
    figure: str = typer.Argument(
        ..., help="fig3ab, fig3cd, fig4b, fig5ab, fig5c, fig5d, fig6a, fig6a-mpm, fig7bc, figs1 or figs3b."
    ),
    out: Path = typer.Option(Path("figures"), help="Output folder for the PNG and CSV."),
    quick: bool = typer.Option(False, help="Coarse, fast version."),
    parallel: bool = typer.Option(True, help="Run the omega sweeps on a Dask cluster."),
    mpm: bool = typer.Option(False, help="Add the MPM points to fig5ab, fig7bc, figs1 (long: runs MPM sweeps)."),
    runs: Path = typer.Option(None, help="Folder of MPM run folders (default runs/mpm or runs/mpm-quick)."),
    name: Optional[str] = typer.Option(
        None,
        help="File name stem instead of the figure's (e.g. fig7bc_band0: fig7bc_band0.png, fig7bc_band0_vs_mpm.csv).",
    ),
    settings: Optional[Path] = typer.Option(
        None, "--settings", help="MPM settings TOML file of the runs the figure draws (as `mpm sweep --settings`)."
    ),
    sets: list[str] = typer.Option(
        [],
        "--set",
        help="KEY=VALUE, repeatable: an MPM setting of the runs the figure draws (as `mpm sweep --set`, e.g. contact_band=0).",
    ),
    workers: Optional[int] = typer.Option(
        None,
        min=1,
        help="MPM runs at once, each in a worker process on cores / WORKERS threads (default: one per core, up to the runs to make; 1: one after another in this process).",
    ),
) -> None:
    """Reproduce one of the paper's figures (PNG + CSV of the plotted numbers).

    RFT/DRFT: fig4b, fig5ab, fig6a, fig7bc, figs1. MPM (runs the continuum solver, or reuses
    finished run folders under --runs): fig3ab, fig3cd, fig5c, fig5d, fig6a-mpm, figs3b, and --mpm on the others.
    The MPM runs are those of the quick or paper settings with --settings and --set applied; a
    run folder or sweep CSV under --runs recorded with other settings is refused. Each MPM run
    prints its progress (simulated time reached, ETA) every few seconds.
    """

    from intrusim.figures import FIGURES
    from intrusim.figures.mpm import applying_settings, check_figure_settings, running_workers
    from intrusim.scenarios.mpm_settings import check_keys, settings_items

    items = settings_items(settings, sets)
    check_keys(items)  # an unknown key is refused before any figure
    if figure not in FIGURES:
        _fail(InputError(f"unknown figure {figure!r}; choose one of {sorted(FIGURES)}"))
    if name is not None and (not name or Path(name).name != name):
        _fail(InputError(f"--name must be a plain file name stem, got {name!r}"))
    try:
        check_workers(workers)
        check_writable(out)
    except InputError as err:
        _fail(err)
    if workers is not None and workers > 1 and not parallel:
        _fail(InputError(f"--workers {workers} runs MPM runs at once: not with --no-parallel (or give --workers 1)"))
    if items:  # and a bad value, over the base settings of the figure's MPM cases
        check_figure_settings(figure, quick, items)
    with applying_settings(items), running_workers(workers):
        if name is None:
            paths = FIGURES[figure](out, quick=quick, parallel=parallel, runs=runs, mpm=mpm)
        else:
            paths = _renamed_figure(
                FIGURES[figure], figure.replace("-", "_"), name, out, quick=quick, parallel=parallel, runs=runs, mpm=mpm
            )
    for p in paths:
        typer.echo(str(p))


def _renamed_figure(make: Any, stem: str, name: str, out: Path, **kwargs: Any) -> list[Path]:
    """Run a figure function into a scratch folder under ``out``, then move its files to ``out``
    with the stem ``stem`` replaced by ``name`` (a failed figure leaves ``out`` as it was)."""
    import shutil
    import tempfile

    out.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory(dir=out, prefix=".reproduce-") as tmp:
        moved = []
        for p in make(Path(tmp), **kwargs):
            target = out / (name + p.name[len(stem) :] if p.name.startswith(stem) else p.name)
            shutil.move(str(p), target)
            moved.append(target)
    return moved


@app.command()
def status(
    figures: Path = typer.Option(
        Path("research/outputs/figures"),
        help="Folder of the figures' CSVs (NAME_vs_mpm.csv; the committed ones by default).",
    ),
    write: Optional[Path] = typer.Option(
        None, help="Markdown file whose status block (<!-- status table: begin/end -->) is replaced by the table."
    ),
) -> None:
    """The models against MPM, summed up from the figures' CSVs (fig5ab, fig7bc, figs1 with --mpm)."""
    from intrusim.figures.status import status_table, write_status

    if not figures.is_dir():
        _fail(InputError(f"--figures {figures} is not a folder"))
    if write is None:
        typer.echo("\n".join(status_table(figures)))
        return
    if not write.is_file():
        _fail(InputError(f"--write {write} is not a file"))
    try:
        write_status(write, figures)
    except ValueError as err:
        _fail(InputError(str(err)))
    typer.echo(f"wrote the status table of {write}")


@app.command()
def calibrate(
    scenario: str = typer.Argument(..., help=SCENARIO_HELP),
    mpm: Optional[Path] = typer.Option(
        None,
        help="MPM sweep CSV of the scenario, e.g. runs/mpm/grousered_wheel_mpm_sweep.csv. Without it the MPM runs are made (or their finished folders under --runs reused): --mpm-omegas, --quick, --runs, --settings, --set.",
    ),
    mpm_omegas: Optional[str] = typer.Option(
        None,
        help="Without --mpm: RPM list 'a,b,c' or range 'start:stop:step' of the MPM runs (default: a wheel's 10,20,30,45,60,90; a runner's 20,50,100,150,200,300).",
    ),
    quick: bool = typer.Option(
        False, help="Without --mpm: the coarse, short MPM runs (2 cm cells): minutes, not hours."
    ),
    preset: Optional[str] = typer.Option(
        None,
        help="Without --mpm: the MPM runs' base settings, paper (the default), quick (as --quick) or reference "
        "(the nonlocal law at a fifth of the body's thinnest feature, run until settled: hours a point; docs/mpm.md).",
    ),
    runs: Optional[Path] = typer.Option(
        None,
        help="Without --mpm: folder of the MPM run folders (default OUT/mpm-runs; finished runs there are reused).",
    ),
    settings: Optional[Path] = typer.Option(
        None, "--settings", help="Without --mpm: MPM settings TOML file of the runs (as `mpm sweep --settings`)."
    ),
    sets: list[str] = typer.Option(
        [], "--set", help="Without --mpm: KEY=VALUE, repeatable, an MPM setting of the runs (as `mpm sweep --set`)."
    ),
    params: str = typer.Option(
        "xi,psi",
        help="Parameters to fit, comma-separated: xi, psi (slope c), psi_offset, lam, bulldozing (k_b of a bulldozing resistance, not in the paper); 'none': fit nothing, compare the model as it is (its values measured, --fix).",
    ),
    fix: list[str] = typer.Option(
        [],
        help="NAME=VALUE, repeatable: a parameter (as --params) set to a measured value, not fitted, on the scenario and the --check scenarios.",
    ),
    structural: Optional[str] = typer.Option(
        None,
        help="Structural correction (default: the scenario's): wheel-rear-half, wheel-rear-half-effective, wheel-rear-half-circle or none; also for the --check scenarios that have one (a runner keeps none).",
    ),
    mpm_push: bool = typer.Option(
        True, help="Give DRFT the constant forward push of the MPM runs (4 N for the Table S1 wheel)."
    ),
    psi_from_dh: str = typer.Option(
        "none", help="Set psi from the MPM rear surface drop before fitting: none, linear or affine."
    ),
    check: list[str] = typer.Option(
        [], help="Transfer check NAME=CSV (a scenario and its MPM sweep), fitted values reused; repeatable."
    ),
    model: str = typer.Option("drft", help="Force model: drft (rft or drft-inertial ignore psi)."),
    settled_only: bool = typer.Option(
        False,
        "--settled-only",
        help="Fit only the MPM runs that settled (the settle test: v and sinkage each within 1 % over their last two revolutions; the CSV's settled column; older CSVs: the window's halves within 5 %).",
    ),
    starts: int = typer.Option(
        8, help="Local least-squares fits from the scenario's values and points filling the bounds; the best is kept."
    ),
    out: Path = typer.Option(Path("figures"), help="Output folder for the PNG, CSV and JSON."),
    name: Optional[str] = typer.Option(None, help="File name stem (default calibration_SCENARIO)."),
    rft_coefficients: Optional[Path] = typer.Option(
        None,
        help="RFT coefficient table (JSON/TOML, N/cm^3; e.g. measured on the MPM medium by examples/mpm_rft_map.py) in place of the generic one, used as it is (xi = 1).",
    ),
    leave_one_out: bool = typer.Option(
        False,
        "--leave-one-out",
        help="Also refit without each MPM omega in turn and predict it (cross-validation; N more fits).",
    ),
    workers: int = typer.Option(
        1,
        min=1,
        help="Processes at once, at most this machine's cores: the MPM runs made without --mpm (each on cores / workers threads), then the local fits (--starts) and the leave-one-out folds (a local Dask cluster when > 1).",
    ),
) -> None:
    """Calibrate DRFT on MPM steady states (v and sinkage per omega) and check the transfer to other scenarios.

    Writes NAME.png, NAME.csv, NAME_vs_mpm.csv, NAME.json (the fit's record) and NAME.model.json, the
    calibrated model, which `intrusim steady|sweep --model NAME.model.json` runs on any body. Without
    --mpm it first makes the scenario's MPM runs (resumable; a finished run is reused) and keeps their
    table as NAME_mpm.csv (their settings beside it, NAME_mpm.settings.json)."""
    from intrusim.analysis.calibration_job import CalibrationJob, run_calibration

    job = CalibrationJob(
        scenario=scenario, mpm=mpm, mpm_omegas=mpm_omegas, quick=quick, preset=preset, runs=runs, settings=settings, sets=list(sets),
        params=params, fix=list(fix), structural=structural, mpm_push=mpm_push, psi_from_dh=psi_from_dh,
        check=list(check), model=model, settled_only=settled_only, starts=starts, out=out, name=name,
        rft_coefficients=rft_coefficients, leave_one_out=leave_one_out, workers=workers,
    )  # fmt: skip
    try:
        paths = run_calibration(job, say=typer.echo, warn=lambda text: typer.echo(f"warning: {text}", err=True))
    except (InputError, ValueError) as err:
        _fail(err)
    for p in paths:
        typer.echo(str(p))


@app.command()
def demo(
    out: Path = typer.Option(Path("intrusim_demo"), help="Folder for demo.csv and demo.png."),
    mpm: bool = typer.Option(True, help="Add one quick MPM point (30 RPM, 2 cm cells)."),
) -> None:
    """The paper's wheel under RFT, the paper's DRFT, the recommended calibrated DRFT (10-90 RPM) and a
    quick MPM point: a table, each model's measured error, and a PNG."""
    from intrusim.demo import run_demo

    result = run_demo(out, mpm_omega_rpm=30.0 if mpm else None)
    typer.echo("\n".join([result.table(), *result.notes, str(result.csv_path), str(result.png_path)]))


def _register_mpm() -> None:
    from intrusim.cli_mpm import mpm_app

    app.add_typer(mpm_app, name="mpm")


_register_mpm()

if __name__ == "__main__":  # pragma: no cover
    app()
