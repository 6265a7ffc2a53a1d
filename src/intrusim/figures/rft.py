"""Reproduce the paper's RFT / DRFT figures: PNG plus the CSV of the plotted numbers.

One function per figure, each ``fig(out_dir, quick=False, parallel=True) -> list[Path]``;
``intrusim reproduce NAME`` calls them. Axes are non-dimensional as in the paper (Fig 3):
v / sqrt(g l), sinkage / l, omega / omega_0 with omega_0 = sqrt(g / l) and l the outer diameter.
``quick`` uses a coarse omega grid and one averaging revolution.
"""

from __future__ import annotations

from pathlib import Path
from typing import Sequence

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from intrusim.analysis.plates import fit_static_plus_inertial  # noqa: E402
from intrusim.analysis.sweep import SweepResult, sweep_omega  # noqa: E402
from intrusim.figures._output import csv_rows, write_curves  # noqa: E402
from intrusim.figures.mpm import (  # noqa: E402
    MPM_RUNNER_RPM,
    MPM_RUNNER_RPM_QUICK,
    MPM_SMALL_WHEEL_RPM,
    MPM_WHEEL_RPM,
    MPM_WHEEL_RPM_QUICK,
    with_mpm,
)
from intrusim.scenarios import (  # noqa: E402
    LocomotorScenario,
    drag_force_table,
    four_flap_runner_scenario,
    grousered_wheel_scenario,
    plate_drag_scenario,
    small_wheel_scenario,
)

WHEEL_RPM = np.arange(10.0, 91.0, 10.0)  # Fig 4-5, S1: 10-90 RPM
WHEEL_RPM_QUICK = np.array([10.0, 30.0, 60.0, 90.0])
RUNNER_RPM = np.array([10, 25, 50, 75, 100, 125, 150, 200, 250, 300], float)  # Fig 7: 10-300 RPM
RUNNER_RPM_QUICK = np.array([10.0, 50.0, 100.0, 200.0, 300.0])


def _quick(s: LocomotorScenario, quick: bool) -> LocomotorScenario:
    if quick:
        s = s.model_copy(deep=True)
        s.run.average_revolutions = 1
    return s


def _curves(
    cases: Sequence[tuple[str, LocomotorScenario, str, float | None]], rpm: np.ndarray, parallel: bool
) -> list[tuple[str, LocomotorScenario, SweepResult]]:
    if not parallel:
        return [
            (label, s, sweep_omega(s, kind, rpm, lam=lam, parallel=False, progress=False))
            for label, s, kind, lam in cases
        ]
    from dask.distributed import LocalCluster

    with LocalCluster(
        threads_per_worker=1, processes=True, dashboard_address=":0"
    ) as cluster:  # one cluster per figure
        addr = cluster.scheduler_address
        return [
            (label, s, sweep_omega(s, kind, rpm, lam=lam, scheduler_address=addr, progress=False))
            for label, s, kind, lam in cases
        ]


def fig4b(
    out: Path, quick: bool = False, parallel: bool = True, runs: Path | None = None, mpm: bool = False
) -> list[Path]:
    """Fig 4B: wheel, RFT + inertial correction only, lambda in {0, 1, 25, 50, 100}."""
    s = _quick(grousered_wheel_scenario(), quick)
    lams = (0.0, 25.0, 100.0) if quick else (0.0, 1.0, 25.0, 50.0, 100.0)
    cases = [(f"lambda={lam:g}", s, "drft-inertial", lam) for lam in lams]
    rpm = WHEEL_RPM_QUICK if quick else WHEEL_RPM
    return write_curves(
        out, "fig4b", _curves(cases, rpm, parallel), "Fig 4B: wheel, RFT + lambda rho v_n^2 (no structural correction)"
    )


def fig5ab(
    out: Path, quick: bool = False, parallel: bool = True, runs: Path | None = None, mpm: bool = False
) -> list[Path]:
    """Fig 5A-B: wheel, RFT vs DRFT vs DRFT without the structural correction (lambda = 1); ``mpm``
    adds the MPM points (the paper compares with experiments, which are not available as data)."""
    s = _quick(grousered_wheel_scenario(), quick)
    fm = s.force_model.model_copy(update=dict(structural="wheel-rear-half-effective"))
    s_eff = s.model_copy(update=dict(force_model=fm))
    cases = [
        ("RFT", s, "rft", None), ("DRFT", s, "drft", None), ("DRFT, inertial only", s, "drft-inertial", None),
        ("DRFT, arc ends at lowered rear surface", s_eff, "drft", None),
    ]  # fmt: skip
    rpm = WHEEL_RPM_QUICK if quick else WHEEL_RPM
    curves = _curves(cases, rpm, parallel)
    if mpm:
        curves = with_mpm(curves, s, MPM_WHEEL_RPM_QUICK if quick else MPM_WHEEL_RPM, quick, parallel, runs)
    return write_curves(out, "fig5ab", curves, "Fig 5A-B: grousered wheel (Table S1)")


def fig7bc(
    out: Path, quick: bool = False, parallel: bool = True, runs: Path | None = None, mpm: bool = False
) -> list[Path]:
    """Fig 7B-C: four-flap runner, DRFT (inertial correction only), lambda in {0, 2, 4}; ``mpm`` adds MPM."""
    s = _quick(four_flap_runner_scenario(), quick)
    cases = [(f"DRFT lambda={lam:g}", s, "drft", lam) for lam in (0.0, 2.0, 4.0)]
    rpm = RUNNER_RPM_QUICK if quick else RUNNER_RPM
    curves = _curves(cases, rpm, parallel)
    if mpm:
        curves = with_mpm(curves, s, MPM_RUNNER_RPM_QUICK if quick else MPM_RUNNER_RPM, quick, parallel, runs)
    return write_curves(out, "fig7bc", curves, "Fig 7B-C: four-flap runner (Table S1, m = 10.5 kg, W = 1 m)")


def figs1(
    out: Path, quick: bool = False, parallel: bool = True, runs: Path | None = None, mpm: bool = False
) -> list[Path]:
    """Fig S1: DRFT for the Table S1 wheel and the half-size wheel (each with its own l); ``mpm`` adds MPM."""
    big, small = _quick(grousered_wheel_scenario(), quick), _quick(small_wheel_scenario(), quick)
    cases = [("wheel D=212 mm", big, "drft", None), ("small wheel D=106 mm", small, "drft", None)]
    rpm = WHEEL_RPM_QUICK if quick else WHEEL_RPM
    curves = _curves(cases, rpm, parallel)
    if mpm:
        curves = with_mpm(
            curves, big, MPM_WHEEL_RPM_QUICK if quick else MPM_WHEEL_RPM, quick, parallel, runs, "MPM wheel D=212 mm"
        )
        curves = with_mpm(
            curves,
            small,
            MPM_WHEEL_RPM_QUICK if quick else MPM_SMALL_WHEEL_RPM,
            quick,
            parallel,
            runs,
            "MPM small wheel D=106 mm",
        )
    return write_curves(out, "figs1", curves, "Fig S1: DRFT, two wheel sizes")


def fig6a(
    out: Path, quick: bool = False, parallel: bool = True, runs: Path | None = None, mpm: bool = False
) -> list[Path]:
    """Fig 6A: DRFT drag on a vertical plate vs speed at 20/30/40 mm; fit K|z| + lambda rho A v^2."""
    s = plate_drag_scenario()
    s = s.model_copy(update={"speeds": list(np.geomspace(0.04, 0.64, 5 if quick else 9))})
    force = drag_force_table(s, "drft")
    K, lam = fit_static_plus_inertial(np.array(s.depths), np.array(s.speeds), force, s.force_model.rho, s.area)
    out.mkdir(parents=True, exist_ok=True)
    fig, ax = plt.subplots(figsize=(4.8, 3.6))
    vv = np.linspace(0.0, max(s.speeds), 100)
    rows = []
    for i, d in enumerate(s.depths):
        (line,) = ax.plot(s.speeds, force[i], "o", label=f"DRFT |z| = {d * 1e3:.0f} mm")
        ax.plot(vv, K * d + lam * s.force_model.rho * s.area * vv**2, ":", color=line.get_color())
        if s.paper_K is not None and s.paper_lambda is not None:
            ax.plot(
                vv,
                s.paper_K * d + s.paper_lambda * s.force_model.rho * s.area * vv**2,
                "-",
                lw=0.6,
                color=line.get_color(),
            )
        for j, v in enumerate(s.speeds):
            rows.append({"depth_m": d, "speed_m_s": v, "force_N_per_m": force[i, j], "fit_K_N_per_m": K, "fit_lambda": lam,
                         "paper_K_N_per_m": s.paper_K, "paper_lambda": s.paper_lambda, "rho_kg_m3": s.force_model.rho,
                         "area_m2": s.area})  # fmt: skip
    ax.set(xlabel="drag speed v (m/s)", ylabel="drag force per metre width (N/m)",
           title=f"Fig 6A: fit K = {K:.0f} N/m, lambda = {lam:.2f} (paper MPM: 580, 1.1; thin lines)")  # fmt: skip
    ax.title.set_fontsize(7)
    ax.legend(fontsize=7)
    fig.tight_layout()
    png, csv_path = out / "fig6a.png", out / "fig6a.csv"
    fig.savefig(png, dpi=120)
    plt.close(fig)
    csv_rows(csv_path, rows)
    return [png, csv_path]
