"""What intrusim is for, on the default case: the paper's grousered wheel (Table S1).

:func:`run_demo` drives the wheel through dry poppy seeds at a few spin rates with quasistatic
RFT and Dynamic RFT (the paper's reduced-order models), adds one coarse point of the MPM continuum
solver, and writes the steady states as a table (CSV) and a figure (PNG): forward speed and
sinkage against omega, the comparison of the paper's Fig 5. ``intrusim demo`` calls it.

The MPM point uses :func:`~intrusim.scenarios.mpm_locomotion.quick_settings` (2 cm cells, 1.2 s):
a trend in seconds, not a converged result (docs/results.md has those).
"""

from __future__ import annotations

import csv
import math
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Sequence

from intrusim._checks import InputError
from intrusim.params import RPM

DEFAULT_OMEGA_RPM = (10.0, 30.0, 60.0, 90.0)
# SI, the unit in each name (docs/getting-started.md, "CSV files"); omega_rad_s < 0: rolling forward
FIELDS = ("model", "omega_rpm", "omega_rad_s", "velocity_m_s", "sinkage_m", "slip", "wall_time_s")


@dataclass
class DemoResult:
    """The demo's steady states (one row per model and omega, keys :data:`FIELDS`, SI) and the files written."""

    rows: list[dict[str, float | str]]
    csv_path: Path | None = None
    png_path: Path | None = None
    wall_time: float = 0.0
    notes: list[str] = field(default_factory=list)

    def table(self) -> str:
        """The rows as an aligned text table (speed in mm/s, sinkage in mm)."""
        lines = [f"{'model':>6} | {'omega RPM':>9} | {'v mm/s':>7} | {'sinkage mm':>10} | {'slip':>5} | {'wall s':>6}"]
        for r in self.rows:
            lines.append(
                f"{r['model']:>6} | {r['omega_rpm']:9.0f} | {1e3 * float(r['velocity_m_s']):7.1f} | "
                f"{1e3 * float(r['sinkage_m']):10.1f} | {float(r['slip']):5.2f} | {float(r['wall_time_s']):6.1f}"
            )
        return "\n".join(lines)


def run_demo(
    out_dir: str | Path | None = "intrusim_demo",
    omega_rpm: Sequence[float] = DEFAULT_OMEGA_RPM,
    *,
    mpm_omega_rpm: float | None = 30.0,
    mpm_t_max: float = 1.2,
    threads: int = 1,
) -> DemoResult:
    """Steady states of the Table S1 wheel under RFT, DRFT and (one point) MPM.

    Parameters
    ----------
    out_dir : folder for ``demo.csv`` and ``demo.png`` (created); None writes nothing.
    omega_rpm : spin rates of the RFT and DRFT sweeps, RPM > 0 (forward rolling).
    mpm_omega_rpm : spin rate of the quick MPM point; None skips MPM.
    mpm_t_max : s, simulated time of the MPM point (coarse: 2 cm cells).
    threads : CPU threads of the MPM solver.
    """
    from intrusim.analysis.steady import run_steady
    from intrusim.scenarios import grousered_wheel_scenario

    omegas = [float(w) for w in omega_rpm]
    if not omegas or any(not math.isfinite(w) or w <= 0 for w in omegas):
        raise InputError(f"omega_rpm must be a non-empty list of RPM > 0, got {list(omega_rpm)}")
    if mpm_omega_rpm is not None and (not math.isfinite(mpm_omega_rpm) or mpm_omega_rpm <= 0):
        raise InputError(f"mpm_omega_rpm must be > 0 (or None), got {mpm_omega_rpm}")
    t_start = time.perf_counter()
    scenario = grousered_wheel_scenario()
    rows: list[dict[str, float | str]] = []
    for kind in ("rft", "drft"):
        for w in omegas:
            t0 = time.perf_counter()
            st = run_steady(scenario, kind, w)
            rows.append(_row(kind, w, st.velocity, st.sinkage, st.slip, time.perf_counter() - t0))
    notes = []
    if mpm_omega_rpm is not None:
        from intrusim.scenarios.mpm_locomotion import quick_settings, run_mpm_steady

        settings = quick_settings("wheel").validated_copy(t_max=mpm_t_max, cpu_threads=threads)
        st = run_mpm_steady(scenario, settings, mpm_omega_rpm)
        rows.append(_row("mpm", mpm_omega_rpm, st.velocity, st.sinkage, st.slip, st.wall_time))
        notes.append(
            f"MPM: {settings.h * 1e3:.0f} mm cells, {mpm_t_max:g} s (coarse; docs/results.md for converged runs)"
        )
    result = DemoResult(rows, notes=notes)
    if out_dir is not None:
        out = Path(out_dir)
        out.mkdir(parents=True, exist_ok=True)
        result.csv_path = _write_csv(out / "demo.csv", rows)
        result.png_path = _plot(out / "demo.png", rows)
    result.wall_time = time.perf_counter() - t_start
    return result


def _row(model: str, omega_rpm: float, velocity: float, sinkage: float, slip: float, wall: float) -> dict:
    return {
        "model": model,
        "omega_rpm": omega_rpm,
        "omega_rad_s": -omega_rpm * RPM,  # the package's sign: counter-clockwise, < 0 rolling forward
        "velocity_m_s": float(velocity),
        "sinkage_m": float(sinkage),
        "slip": float(slip),
        "wall_time_s": float(wall),
    }


def _write_csv(path: Path, rows: list[dict]) -> Path:
    with path.open("w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=FIELDS)
        w.writeheader()
        w.writerows(rows)
    return path


def _plot(path: Path, rows: list[dict]) -> Path:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (ax_v, ax_s) = plt.subplots(1, 2, figsize=(9, 3.6), constrained_layout=True)
    style = {"rft": ("C0", "o-", "RFT"), "drft": ("C3", "s-", "DRFT"), "mpm": ("k", "*", "MPM (coarse)")}
    for model, (color, marker, label) in style.items():
        sel = [r for r in rows if r["model"] == model]
        if not sel:
            continue
        w = [r["omega_rpm"] for r in sel]
        ax_v.plot(
            w, [1e3 * r["velocity_m_s"] for r in sel], marker, color=color, label=label, ms=8 if model == "mpm" else 5
        )
        ax_s.plot(
            w, [1e3 * r["sinkage_m"] for r in sel], marker, color=color, label=label, ms=8 if model == "mpm" else 5
        )
    ax_v.set(xlabel="omega (RPM)", ylabel="forward speed (mm/s)", title="Table S1 wheel: speed")
    ax_s.set(xlabel="omega (RPM)", ylabel="sinkage (mm)", title="sinkage")
    ax_v.legend()
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return path
