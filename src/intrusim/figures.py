"""Reproduce the paper's RFT / DRFT figures: PNG plus the CSV of the plotted numbers.

One function per figure, each ``fig(out_dir, quick=False, parallel=True) -> list[Path]``;
``intrusim reproduce NAME`` calls them. Axes are non-dimensional as in the paper (Fig 3):
v / sqrt(g l), sinkage / l, omega / omega_0 with omega_0 = sqrt(g / l) and l the outer diameter.
``quick`` uses a coarse omega grid and one averaging revolution.
"""

from __future__ import annotations

import csv
from pathlib import Path
from typing import Any, Callable, Sequence

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from intrusim.analysis.plates import fit_static_plus_inertial  # noqa: E402
from intrusim.analysis.sweep import SweepResult, sweep_omega  # noqa: E402
from intrusim.figures_mpm import (  # noqa: E402
    MPM_FIGURES,
    MPM_RUNNER_RPM,
    MPM_RUNNER_RPM_QUICK,
    MPM_SMALL_WHEEL_RPM,
    MPM_WHEEL_RPM,
    MPM_WHEEL_RPM_QUICK,
    with_mpm,
)
from intrusim.params import RPM  # noqa: E402
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
        return [(label, s, sweep_omega(s, kind, rpm, lam=lam, parallel=False, progress=False)) for label, s, kind, lam in cases]
    from dask.distributed import LocalCluster

    with LocalCluster(threads_per_worker=1, processes=True, dashboard_address=":0") as cluster:  # one cluster per figure
        addr = cluster.scheduler_address
        return [(label, s, sweep_omega(s, kind, rpm, lam=lam, scheduler_address=addr, progress=False)) for label, s, kind, lam in cases]


def _write(
    out: Path, name: str, curves: list[tuple[str, LocomotorScenario, SweepResult]], title: str
) -> list[Path]:
    out.mkdir(parents=True, exist_ok=True)
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(9, 3.6))
    rows: list[dict[str, Any]] = []
    n_mpm = 0
    for label, s, res in curves:
        w = res.omega_rpm * RPM / s.omega_0
        v = res.column("velocity") / s.velocity_scale
        h = res.column("sinkage") / s.length_scale
        style: dict[str, Any] = dict(marker="o", ms=3)
        if label.startswith("MPM"):  # dashed, open markers: black circles, then grey squares, black triangles, grey diamonds
            style = dict(color=("k", "0.5")[n_mpm % 2], ls="--", marker="os^D"[n_mpm % 4], ms=5, mfc="w")
            n_mpm += 1
        a1.plot(w, v, label=label, **style)
        a2.plot(w, h, label=label, **style)
        for r, wi, vi, hi in zip(res.records, w, v, h):
            rows.append({
                "curve": label, "scenario": s.name, "model": res.kind, "lambda": res.lam if res.lam is not None else s.force_model.lam,
                "omega_rpm": r["omega_rpm"], "omega_over_omega0": wi, "v_over_sqrt_gl": vi, "sinkage_over_l": hi,
                "velocity_m_s": r.get("velocity", np.nan), "sinkage_m": r.get("sinkage", np.nan), "slip": r.get("slip", np.nan),
                "length_scale_m": s.length_scale, "error": r.get("error", ""),
            })  # fmt: skip
    a1.set(xlabel=r"$\omega/\omega_0$", ylabel=r"$v/\sqrt{g\ell}$")
    a2.set(xlabel=r"$\omega/\omega_0$", ylabel=r"sinkage$/\ell$")
    a1.legend(fontsize=7)
    fig.suptitle(title, fontsize=9)
    fig.tight_layout()
    png, csv_path = out / f"{name}.png", out / f"{name}.csv"
    fig.savefig(png, dpi=120)
    plt.close(fig)
    _csv(csv_path, rows)
    paths = [png, csv_path]
    agreement = _agreement_rows(curves)
    if agreement:
        paths.append(out / f"{name}_vs_mpm.csv")
        _csv(paths[-1], agreement)
    return paths


def _agreement_rows(curves: list[tuple[str, LocomotorScenario, SweepResult]]) -> list[dict[str, Any]]:
    """Relative difference of every model curve from the MPM curve of the same scenario, at the MPM omegas."""
    from intrusim.analysis.compare import relative_difference

    rows: list[dict[str, Any]] = []
    refs = [(s.name, res) for label, s, res in curves if label.startswith("MPM")]
    for name, ref in refs:
        for label, s, res in curves:
            if label.startswith("MPM") or s.name != name:
                continue
            dv = relative_difference(res.omega_rpm, res.column("velocity"), ref.omega_rpm, ref.column("velocity"))
            ds = relative_difference(res.omega_rpm, res.column("sinkage"), ref.omega_rpm, ref.column("sinkage"))
            for w, v_ref, s_ref, e_v, e_s in zip(ref.omega_rpm, ref.column("velocity"), ref.column("sinkage"), dv, ds):
                rows.append({"curve": label, "scenario": name, "omega_rpm": w, "omega_over_omega0": w * RPM / s.omega_0,
                             "velocity_mpm_m_s": v_ref, "sinkage_mpm_m": s_ref,
                             "rel_diff_velocity": e_v, "rel_diff_sinkage": e_s})  # fmt: skip
    return rows


def _csv(path: Path, rows: list[dict[str, Any]]) -> None:
    with path.open("w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)


def fig4b(out: Path, quick: bool = False, parallel: bool = True, runs: Path | None = None, mpm: bool = False) -> list[Path]:
    """Fig 4B: wheel, RFT + inertial correction only, lambda in {0, 1, 25, 50, 100}."""
    s = _quick(grousered_wheel_scenario(), quick)
    lams = (0.0, 25.0, 100.0) if quick else (0.0, 1.0, 25.0, 50.0, 100.0)
    cases = [(f"lambda={lam:g}", s, "drft-inertial", lam) for lam in lams]
    rpm = WHEEL_RPM_QUICK if quick else WHEEL_RPM
    return _write(out, "fig4b", _curves(cases, rpm, parallel), "Fig 4B: wheel, RFT + lambda rho v_n^2 (no structural correction)")


def fig5ab(out: Path, quick: bool = False, parallel: bool = True, runs: Path | None = None, mpm: bool = False) -> list[Path]:
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
    return _write(out, "fig5ab", curves, "Fig 5A-B: grousered wheel (Table S1)")


def fig7bc(out: Path, quick: bool = False, parallel: bool = True, runs: Path | None = None, mpm: bool = False) -> list[Path]:
    """Fig 7B-C: four-flap runner, DRFT (inertial correction only), lambda in {0, 2, 4}; ``mpm`` adds MPM."""
    s = _quick(four_flap_runner_scenario(), quick)
    cases = [(f"DRFT lambda={lam:g}", s, "drft", lam) for lam in (0.0, 2.0, 4.0)]
    rpm = RUNNER_RPM_QUICK if quick else RUNNER_RPM
    curves = _curves(cases, rpm, parallel)
    if mpm:
        curves = with_mpm(curves, s, MPM_RUNNER_RPM_QUICK if quick else MPM_RUNNER_RPM, quick, parallel, runs)
    return _write(out, "fig7bc", curves, "Fig 7B-C: four-flap runner (Table S1, m = 10.5 kg, W = 1 m)")


def figs1(out: Path, quick: bool = False, parallel: bool = True, runs: Path | None = None, mpm: bool = False) -> list[Path]:
    """Fig S1: DRFT for the Table S1 wheel and the half-size wheel (each with its own l); ``mpm`` adds MPM."""
    big, small = _quick(grousered_wheel_scenario(), quick), _quick(small_wheel_scenario(), quick)
    cases = [("wheel D=212 mm", big, "drft", None), ("small wheel D=106 mm", small, "drft", None)]
    rpm = WHEEL_RPM_QUICK if quick else WHEEL_RPM
    curves = _curves(cases, rpm, parallel)
    if mpm:
        curves = with_mpm(curves, big, MPM_WHEEL_RPM_QUICK if quick else MPM_WHEEL_RPM, quick, parallel, runs, "MPM wheel D=212 mm")
        curves = with_mpm(curves, small, MPM_WHEEL_RPM_QUICK if quick else MPM_SMALL_WHEEL_RPM, quick, parallel, runs, "MPM small wheel D=106 mm")
    return _write(out, "figs1", curves, "Fig S1: DRFT, two wheel sizes")


def fig6a(out: Path, quick: bool = False, parallel: bool = True, runs: Path | None = None, mpm: bool = False) -> list[Path]:
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
            ax.plot(vv, s.paper_K * d + s.paper_lambda * s.force_model.rho * s.area * vv**2, "-", lw=0.6, color=line.get_color())
        for j, v in enumerate(s.speeds):
            rows.append({"depth_m": d, "speed_m_s": v, "force_N_per_m": force[i, j], "fit_K_N_per_m": K, "fit_lambda": lam,
                         "paper_K_N_per_m": s.paper_K, "paper_lambda": s.paper_lambda, "rho": s.force_model.rho,
                         "area_m2": s.area})  # fmt: skip
    ax.set(xlabel="drag speed v (m/s)", ylabel="drag force per metre width (N/m)",
           title=f"Fig 6A: fit K = {K:.0f} N/m, lambda = {lam:.2f} (paper MPM: 580, 1.1; thin lines)")  # fmt: skip
    ax.title.set_fontsize(7)
    ax.legend(fontsize=7)
    fig.tight_layout()
    png, csv_path = out / "fig6a.png", out / "fig6a.csv"
    fig.savefig(png, dpi=120)
    plt.close(fig)
    _csv(csv_path, rows)
    return [png, csv_path]


FIGURES: dict[str, Callable[..., list[Path]]] = {
    "fig4b": fig4b, "fig5ab": fig5ab, "fig7bc": fig7bc, "figs1": figs1, "fig6a": fig6a, **MPM_FIGURES,
}  # fmt: skip
