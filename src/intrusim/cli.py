"""Command-line interface: ``intrusim --help``."""

from __future__ import annotations

import numpy as np
import typer

from intrusim import __version__
from intrusim._checks import InputError
from intrusim.forces import make_force_model
from intrusim.geometry import grousered_wheel
from intrusim.kinematics import BodyState
from intrusim.params import table_s1

app = typer.Typer(help="intrusim: granular intrusion with MPM, RFT and Dynamic RFT.", no_args_is_help=True)

RPM = 2 * np.pi / 60  # rad/s per RPM


@app.callback()
def main() -> None:
    """Granular intrusion toolkit (Agarwal, Karsai, Goldman, Kamrin 2021)."""


@app.command()
def version() -> None:
    """Print the package version."""
    typer.echo(__version__)


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
        depths = [float(s) * 1e-3 for s in sinkage_mm.split(",") if s.strip()]
        wheel_cfg = table_s1()["grousered_wheel"]
        true_wheel = grousered_wheel()
        wheel = grousered_wheel(grouser_height_scale=1 / 3)  # grouser shadowing (paper, Methods)
        omega = omega_rpm * RPM
        v = (1 - slip) * wheel.radius * omega
        models = {k: make_force_model(k, wheel, lam=lam, structural="wheel-rear-half") for k in ("rft", "drft-inertial", "drft")}
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


if __name__ == "__main__":  # pragma: no cover
    app()
