"""The paper's MPM figures (Fig 3A-D, 5C-D) and MPM overlays on the RFT/DRFT figures.

MPM points come from :class:`~intrusim.scenarios.mpm_locomotion.MPMLocomotion` sweeps whose run
folders live under ``runs`` (default ``runs/mpm``, or ``runs/mpm-quick`` with ``quick``): a point
whose folder holds ``result.json`` is reused, a missing one is computed (Dask sweep) and kept.
Full-resolution wheel sweeps take about an hour on 2 cores; ``quick`` uses 2 cm cells.
"""

from __future__ import annotations

import json
import sys
from contextlib import contextmanager
from pathlib import Path
from typing import Any, Iterator

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from intrusim._checks import InputError  # noqa: E402
from intrusim.analysis.sweep import SweepResult, sweep_omega  # noqa: E402
from intrusim.figures._output import save_figure, write_curves  # noqa: E402
from intrusim.geometry import posed_polygon  # noqa: E402
from intrusim.params import RPM  # noqa: E402
from intrusim.scenarios import LocomotorScenario  # noqa: E402
from intrusim.scenarios.mpm_locomotion import MPMLocomotion, recorded_differences  # noqa: E402
from intrusim.scenarios.mpm_settings import body_settings, read_record, settings_differences, write_record  # noqa: E402

# Full resolution costs ~5 min (90 RPM) to ~20 min (10 RPM) of one core per wheel point: 6 points
# span the linear range (10-30 RPM) and the plateau; a 10 RPM grid is `intrusim mpm sweep`.
MPM_WHEEL_RPM = np.array([10.0, 20.0, 30.0, 45.0, 60.0, 90.0])
MPM_WHEEL_RPM_QUICK = np.array([10.0, 30.0, 50.0, 70.0, 90.0])
MPM_WHEEL_SWEEP_RPM = np.arange(10.0, 91.0, 10.0)  # every 10 RPM: the wheel sweep of the reference set (wheel-load)
MPM_SMALL_WHEEL_RPM = np.array([30.0, 90.0])
MPM_RUNNER_RPM = np.array([20.0, 50.0, 100.0, 150.0, 200.0, 300.0])
MPM_RUNNER_RPM_QUICK = np.array([30.0, 60.0, 100.0, 150.0, 200.0, 300.0])


# (key, value) settings applied over the quick or paper settings of every MPM case of a figure
# (`intrusim reproduce --settings/--set`; :func:`applying_settings`)
_SETTINGS: list[tuple[str, Any]] = []
_PRESET: list[str | None] = [None]  # the base of the cases' settings (--preset; None: paper or quick)
# MPM runs at once of the figures' sweeps (`intrusim reproduce --workers`; :func:`running_workers`);
# None: one per core, up to the runs to make
_WORKERS: list[int | None] = [None]

# the scenarios of each figure's MPM cases (their base settings: base_settings of the body at the
# scenario's mpm_scale); a figure not named here draws none (its --set values are checked on the wheel's)
FIGURE_SCENARIOS: dict[str, tuple[str, ...]] = {
    "fig3ab": ("wheel",), "fig3cd": ("wheel",), "fig5c": ("wheel",), "fig5d": ("wheel",),
    "fig5ab": ("wheel",), "figs1": ("wheel", "small-wheel"), "fig7bc": ("runner",),
}  # fmt: skip


def check_figure_settings(figure: str, quick: bool, items: list[tuple[str, Any]]) -> None:
    """Refuse (InputError, naming the key and value) settings ``items`` that are not valid over the
    quick or paper settings of figure ``figure``'s MPM cases, before any of the figure is computed."""
    from intrusim.scenarios import get_scenario

    for name in FIGURE_SCENARIOS.get(figure, ("wheel",)):
        s = get_scenario(name)
        body_settings(s, quick, echo=False, items=items)  # type: ignore[arg-type]


@contextmanager
def applying_settings(items: list[tuple[str, Any]], preset: str | None = None) -> Iterator[None]:
    """Within this block the figures' MPM cases take ``items`` (key, value) over their base settings
    (:func:`intrusim.scenarios.mpm_settings.apply_settings`), the base being ``preset``'s
    (:func:`~intrusim.scenarios.mpm_locomotion.body_settings`; None: the paper's or the quick one)."""
    saved, saved_preset = list(_SETTINGS), _PRESET[0]
    _SETTINGS[:] = items
    _PRESET[0] = preset
    try:
        yield
    finally:
        _SETTINGS[:] = saved
        _PRESET[0] = saved_preset


@contextmanager
def running_workers(workers: int | None) -> Iterator[None]:
    """Within this block the figures' MPM sweeps make ``workers`` runs at once (:func:`mpm_sweep`;
    None: one per core, up to the runs to make)."""
    saved = _WORKERS[0]
    _WORKERS[0] = workers
    try:
        yield
    finally:
        _WORKERS[0] = saved


def run_count(workers: int | None, parallel: bool, missing: int) -> int:
    """How many MPM runs go at once: ``workers`` (None: one per core), at most the ``missing`` runs
    to make, 1 without ``parallel``. An InputError for ``workers`` < 1."""
    import os

    if workers is not None and (isinstance(workers, bool) or not isinstance(workers, int) or workers < 1):
        raise InputError(f"workers (MPM runs at once) must be an integer >= 1, got {workers!r}")
    if not parallel:
        return 1
    return max(1, min(missing, workers if workers is not None else os.cpu_count() or 1))


def runs_root(runs: Path | None, quick: bool) -> Path:
    if runs is not None:
        return Path(runs)
    return Path("runs") / ("mpm-quick" if quick else "mpm-reference" if _PRESET[0] == "reference" else "mpm")


def mpm_case(scenario: LocomotorScenario, quick: bool, runs: Path | None) -> MPMLocomotion:
    # the commands say what was grown once, before the runs
    settings = body_settings(scenario, quick, echo=False, preset=_PRESET[0], items=_SETTINGS)
    return MPMLocomotion(scenario=scenario, mpm=settings, out_root=str(runs_root(runs, quick)))


def _refuse(source: Any, diff: list[str]) -> None:
    shown = ", ".join(diff[:8]) + (f" and {len(diff) - 8} more" if len(diff) > 8 else "")
    raise InputError(
        f"{source} holds MPM runs of other settings than the figure's case (differs in {shown}); "
        "give reproduce the runs' settings (--settings, --set) or another --runs folder"
    )


def check_run_folder(case: MPMLocomotion, omega_rpm: float) -> None:
    """Refuse (InputError) the run folder of ``omega_rpm`` if its recorded settings
    (locomotion.json) differ from the case's (a shorter t_max is not a difference: the run is extended)."""
    run_dir = case.run_dir(omega_rpm)
    diff = recorded_differences(run_dir, case.mpm)
    if diff:
        _refuse(run_dir, diff)


def check_sweep_csv(case: MPMLocomotion, table: Path, omegas: np.ndarray) -> None:
    """Refuse (InputError) a sweep CSV whose runs were recorded (SCENARIO_mpm_sweep.settings.json,
    or the run folders beside it) with other settings than the case's; a CSV with no record is
    used with a warning."""
    recorded = read_record(table)
    if recorded is None:
        folders = [table.parent / f"{case.scenario.name}_{w:g}rpm" / "locomotion.json" for w in omegas]
        recorded = {w: json.loads(f.read_text()).get("settings") or {} for w, f in zip(omegas, folders) if f.is_file()}
    if not recorded:
        print(
            f"warning: {table} records no settings of its runs: not checked against the figure's case", file=sys.stderr
        )
        return
    diff = sorted({k for s in recorded.values() for k in settings_differences(s, case.mpm)})
    if diff:
        _refuse(table, diff)


def mpm_sweep(
    scenario: LocomotorScenario,
    rpm: np.ndarray,
    quick: bool,
    parallel: bool,
    runs: Path | None,
    workers: int | None = None,
) -> SweepResult:
    """MPM steady states at ``rpm``: the finished run folders under the runs root; if some are
    missing and the root holds ``SCENARIO_mpm_sweep.csv`` (as ``intrusim mpm sweep`` and
    ``research/mpm_contact_band.py sweep`` write it), that file's finished rows, whatever their
    omegas; otherwise the missing runs are run (and reused next time), each printing its progress.

    ``workers``: MPM runs at once (None: :func:`running_workers`' number, else one per core; at most
    the runs to make), each in a worker process on cores / workers threads; 1, or ``parallel``
    False, runs them one after another in this process."""
    import os

    from intrusim.analysis.calibration import load_reference

    wanted = workers if workers is not None else _WORKERS[0]
    run_count(wanted, parallel, 1)  # a bad number is refused before anything is looked at
    case = mpm_case(scenario, quick, runs)
    for w in rpm:  # a finished or interrupted run of other settings is refused, not reused or extended
        check_run_folder(case, w)
    missing = [w for w in rpm if not (case.run_dir(w) / "result.json").exists()]  # type: ignore[operator]
    table = runs_root(runs, quick) / f"{scenario.name}_mpm_sweep.csv"
    if missing and table.is_file():
        res = load_reference(table, scenario.name)
        check_sweep_csv(case, table, res.omega_rpm)
        print(
            f"{scenario.name}: MPM points from {table} ({len(res.records)} finished runs at "
            f"{', '.join(f'{w:g}' for w in res.omega_rpm)} RPM)",
            file=sys.stderr,
        )
        return res
    n = run_count(wanted, parallel, len(missing))
    if missing:
        print(
            f"{scenario.name}: {len(missing)} of {len(rpm)} MPM runs not finished under {case.out_root}; running them "
            f"({', '.join(f'{w:g}' for w in missing)} RPM; {n} at once; a run stopped midway resumes from its last "
            "checkpoint)",
            file=sys.stderr,
        )
    if n > 1:
        case = case.model_copy(
            update=dict(mpm=case.mpm.model_copy(update=dict(cpu_threads=max(1, (os.cpu_count() or 1) // n))))
        )
    return sweep_omega(case, "mpm", list(rpm), parallel=n > 1, n_workers=n, progress=True)


def mpm_sweep_table(
    scenario: LocomotorScenario,
    rpm: Any,
    quick: bool,
    runs: Path | None,
    items: list[tuple[str, Any]],
    csv: Path,
    workers: int | None = None,
    preset: str | None = None,
) -> SweepResult:
    """:func:`mpm_sweep` of ``scenario`` at ``rpm`` with the settings ``items`` over its quick or paper
    ones (or ``preset``'s), its table written to ``csv`` and the runs' settings beside it (``CSV.settings.json``, as
    ``intrusim mpm sweep`` writes them), for ``intrusim calibrate --mpm`` and the reference set.
    ``workers``: MPM runs at once (:func:`mpm_sweep`; 1: one after another in this process)."""
    rpm = np.asarray(rpm, float)
    with applying_settings(items, preset):
        res = mpm_sweep(scenario, rpm, quick, True, runs, workers)
        case = mpm_case(scenario, quick, runs)
    csv.parent.mkdir(parents=True, exist_ok=True)
    res.to_csv(csv)
    write_record(csv, scenario.name, {float(w): case.mpm for w in rpm})
    return res


def fig3ab(
    out: Path, quick: bool = False, parallel: bool = True, runs: Path | None = None, mpm: bool = True
) -> list[Path]:
    """Fig 3A-B: MPM wheel, steady velocity and sinkage vs omega (non-dimensional)."""
    from intrusim.scenarios import grousered_wheel_scenario

    s = grousered_wheel_scenario()
    res = mpm_sweep(s, MPM_WHEEL_RPM_QUICK if quick else MPM_WHEEL_RPM, quick, parallel, runs)
    return write_curves(out, "fig3ab", [("MPM", s, res)], "Fig 3A-B: grousered wheel, MPM (Table S1 set-up)")


def fig5c(
    out: Path, quick: bool = False, parallel: bool = True, runs: Path | None = None, mpm: bool = True
) -> list[Path]:
    """Fig 5C: rear free-surface drop dh from MPM vs omega, against dh = r (r omega^2 / g).

    Also fits psi(x) = a x (least squares through the origin; paper: a = 1) and the affine
    dh = dh0 + b r x (:mod:`intrusim.analysis.calibration`).
    """
    from intrusim.analysis.calibration import fit_psi_affine, fit_psi_linear
    from intrusim.scenarios import grousered_wheel_scenario

    s = grousered_wheel_scenario()
    res = mpm_sweep(s, MPM_WHEEL_RPM_QUICK if quick else MPM_WHEEL_RPM, quick, parallel, runs)
    w = res.omega_rpm * RPM
    r = s.radius
    x = r * w**2 / s.gravity
    dh = res.column("surface_drop")
    ok = np.isfinite(dh)
    a = fit_psi_linear(w[ok], dh[ok], r, s.gravity) if ok.any() else np.nan
    # affine fit dh = dh0 + b r x: MPM's rear contact sits below the surface even when slow
    a0, b = fit_psi_affine(w[ok], dh[ok], r, s.gravity) if ok.sum() > 1 else (np.nan, np.nan)
    dh0 = a0 * r
    fig, ax = plt.subplots(figsize=(4.8, 3.6))
    ax.plot(res.omega_rpm, dh * 1e3, "o", color="tab:red", label="MPM (highest loaded rear contact)")
    ww = np.linspace(0, res.omega_rpm.max(), 100)
    law = r * (r * (ww * RPM) ** 2 / s.gravity)
    ax.plot(ww, law * 1e3, ":", color="tab:blue", label=r"$\delta h = r\,(r\omega^2/g)$ (paper)")
    ax.plot(ww, a * law * 1e3, "-", lw=0.8, color="0.4", label=rf"fit $\psi = {a:.2f}\,x$")
    ax.plot(
        ww,
        (dh0 + b * law) * 1e3,
        "--",
        lw=0.8,
        color="0.6",
        label=rf"fit $\delta h = {dh0 * 1e3:.1f}$ mm ${'-' if b < 0 else '+'} {abs(b):.2f}\,r x$",
    )
    ax.set(xlabel=r"$\omega$ (RPM)", ylabel=r"$\delta h$ (mm)", title="Fig 5C: rear free-surface drop")
    ax.legend(fontsize=7)
    fig.tight_layout()
    rows = [{"omega_rpm": o, "r_omega2_over_g": xi, "dh_mpm_m": d, "dh_paper_law_m": r * xi, "fit_a": a,
             "affine_dh0_m": dh0, "affine_b": b}
            for o, xi, d in zip(res.omega_rpm, x, dh)]  # fmt: skip
    return save_figure(fig, out, "fig5c", rows)


def _snapshot_files(scenario: LocomotorScenario, rpm: float, quick: bool, runs: Path | None) -> list[Path]:
    """The saved particle snapshots of a run, oldest first (running it first if needed)."""
    case = mpm_case(scenario, quick, runs)
    check_run_folder(case, rpm)
    run_dir = case.run_dir(rpm)
    if run_dir is None or not (run_dir / "result.json").exists():
        case.run_steady("mpm", rpm)
    files = sorted(run_dir.glob("fields_*.npz"))  # type: ignore[union-attr]
    if not files:
        raise FileNotFoundError(f"{run_dir} has no fields_*.npz snapshot")
    return files


def _fields(scenario: LocomotorScenario, rpm: float, quick: bool, runs: Path | None) -> dict[str, np.ndarray]:
    """The last saved particle snapshot of a run (running it first if needed)."""
    return dict(np.load(_snapshot_files(scenario, rpm, quick, runs)[-1]))


def _field_panel(ax: Any, d: dict[str, np.ndarray], values: np.ndarray, norm: Any, cmap: str, half_width: float) -> Any:
    x0, z0 = float(d["body"][0]), float(d["body"][1])
    sel = np.abs(d["x"][:, 0] - x0) < half_width
    sc = ax.scatter(d["x"][sel, 0] - x0, d["x"][sel, 1], c=values[sel], s=2.0, cmap=cmap, norm=norm, linewidths=0)
    poly = posed_polygon(d["outline"], *(float(v) for v in d["body"][:3]))
    ax.fill(poly[:, 0] - x0, poly[:, 1], color="orange", alpha=0.8, ec="k", lw=0.5)
    ax.set_aspect("equal")
    ax.set_xlim(-half_width, half_width)
    ax.set_ylim(z0 - 0.25, z0 + 0.08)
    return sc


def fig3cd(
    out: Path, quick: bool = False, parallel: bool = True, runs: Path | None = None, mpm: bool = True
) -> list[Path]:
    """Fig 3C-D: grain velocity under the wheel at 30 and 60 RPM (MPM), and the profile below the centre.

    Arrows: grain velocity in the lab frame; colour: speed. The profile is the horizontal grain
    velocity along the vertical line through the wheel centre (particles within one cell of it).
    """
    from matplotlib.colors import Normalize

    from intrusim.scenarios import grousered_wheel_scenario

    s = grousered_wheel_scenario()
    h = mpm_case(s, quick, runs).mpm.h
    fig, axes = plt.subplots(1, 3, figsize=(13, 3.8), gridspec_kw={"width_ratios": [1, 1, 0.7]}, layout="constrained")
    rows: list[dict[str, Any]] = []
    for ax, rpm in zip(axes[:2], (30.0, 60.0)):
        d = _fields(s, rpm, quick, runs)
        speed = np.linalg.norm(d["v"], axis=1)
        sc = _field_panel(ax, d, speed, Normalize(0, 0.5), "viridis", 0.3)
        x0 = float(d["body"][0])
        q = np.abs(d["x"][:, 0] - x0) < 0.3
        q &= speed > 0.01
        step = max(1, int(q.sum() // 600))
        idx = np.flatnonzero(q)[::step]
        ax.quiver(d["x"][idx, 0] - x0, d["x"][idx, 1], d["v"][idx, 0], d["v"][idx, 1], scale=8, width=0.002)
        ax.set_title(f"{rpm:g} RPM, t = {float(d['t']):.2f} s", fontsize=9)
        ax.set_xlabel("x - x_wheel (m)")
        column = np.abs(d["x"][:, 0] - x0) < h
        below = column & (d["x"][:, 1] < float(d["body"][1]))
        order = np.argsort(-d["x"][below, 1])
        depth = float(d["body"][1]) - d["x"][below, 1][order]
        vx = d["v"][below, 0][order]
        axes[2].plot(vx, -depth, ".-", ms=3, label=f"{rpm:g} RPM")
        rows += [{"omega_rpm": rpm, "depth_below_centre_m": zd, "vx_m_s": v} for zd, v in zip(depth, vx)]
    fig.colorbar(sc, ax=axes[:2], label="grain speed (m/s)", fraction=0.02)
    axes[0].set_ylabel("z (m)")
    axes[2].axvline(0, color="0.6", lw=0.5)
    axes[2].set(xlabel="grain v_x below the centre (m/s)", ylabel="-(depth below centre) (m)", title="Fig 3D profile")
    axes[2].legend(fontsize=7)
    return save_figure(fig, out, "fig3cd", rows)


def fig5d(
    out: Path, quick: bool = False, parallel: bool = True, runs: Path | None = None, mpm: bool = True
) -> list[Path]:
    """Fig 5D: equivalent plastic strain rate under the wheel at 30 and 90 RPM (MPM)."""
    from matplotlib.colors import LogNorm

    from intrusim.scenarios import grousered_wheel_scenario

    s = grousered_wheel_scenario()
    fig, axes = plt.subplots(1, 2, figsize=(10, 3.8), layout="constrained")
    rows: list[dict[str, Any]] = []
    for ax, rpm in zip(axes, (30.0, 90.0)):
        d = _fields(s, rpm, quick, runs)
        g = np.clip(d["gdot_p"], 0.1, None)
        sc = _field_panel(ax, d, g, LogNorm(0.1, 100), "inferno", 0.3)
        ax.set_title(f"{rpm:g} RPM, t = {float(d['t']):.2f} s", fontsize=9)
        rows.append({"omega_rpm": rpm, "t_s": float(d["t"]), "max_gdot_p_per_s": float(d["gdot_p"].max()),
                     "sheared_area_m2_gdot_gt_1": float(np.sum(d["gdot_p"] > 1.0)) * (np.ptp(d["x"], axis=0).prod() / len(d["x"]))})  # fmt: skip
    fig.colorbar(sc, ax=axes, label="equivalent plastic strain rate (1/s)", fraction=0.02)
    return save_figure(fig, out, "fig5d", rows)


LOAD_FRACTION = 0.05  # the loaded arc's ends: 5 % of the wheel's load behind it, 5 % in front of it


def wheel_load(
    out: Path, quick: bool = False, parallel: bool = True, runs: Path | None = None, mpm: bool = True
) -> list[Path]:
    """Where the MPM wheel bears on the grains (not a paper figure; :mod:`intrusim.analysis.contact_load`).

    Left: the grains' pressure around the Table S1 wheel at 30 and 90 RPM (the last snapshot), the
    loaded arc's ends marked. Middle: the load around the rim by angle at each omega (the run's
    saved snapshots together). Right: psi_b = dh_b / r, the depth below the undisturbed surface
    where the wheel stops bearing on the grains behind, against x = r omega^2 / g, with its affine
    fit (the structural correction's psi measured; "circle" split), the paper's psi = x and Fig 5C's
    rear free-surface drop dh / r.
    """
    from matplotlib.colors import LogNorm

    from intrusim.analysis.calibration import fit_psi_affine
    from intrusim.analysis.contact_load import angular_load, bearing_drop, loaded_arc
    from intrusim.laws.drft import travel_sign
    from intrusim.scenarios import grousered_wheel_scenario

    s = grousered_wheel_scenario()
    rpm = MPM_WHEEL_RPM_QUICK if quick else MPM_WHEEL_SWEEP_RPM
    res = mpm_sweep(s, rpm, quick, parallel, runs)
    case = mpm_case(s, quick, runs)
    r, surface, shell = s.radius, case.mpm.bed_depth, 2.0 * case.mpm.h
    fig, axes = plt.subplots(
        1, 4, figsize=(16, 3.8), gridspec_kw={"width_ratios": [1, 1, 1.1, 1.1]}, layout="constrained"
    )
    rows: list[dict[str, Any]] = []
    cmap = plt.get_cmap("viridis")
    for k, w in enumerate(rpm):
        snaps = [dict(np.load(f)) for f in _snapshot_files(s, float(w), quick, runs)]
        total = None
        for d in snaps:
            b = d["body"]
            ang, load = angular_load(
                d["x"], d["pressure"], (float(b[0]), float(b[1])), travel_sign(b[5], b[3]), r, shell
            )
            total = load if total is None else total + load
        rear, front = loaded_arc(ang, total, LOAD_FRACTION)
        height = float(np.mean([d["body"][1] for d in snaps])) - surface
        dh_b = bearing_drop(rear, height, r)
        x = r * (w * RPM) ** 2 / s.gravity
        rows.append({"omega_rpm": float(w), "r_omega2_over_g": x, "snapshots": len(snaps), "rear_deg": np.degrees(rear),
                     "front_deg": np.degrees(front), "geometric_front_deg": np.degrees(np.arccos(min(1.0, height / r))),
                     "centre_height_m": height, "dh_b_m": dh_b, "psi_b": dh_b / r,
                     "dh_free_surface_m": float(res.column("surface_drop")[k])})  # fmt: skip
        axes[2].plot(
            np.degrees(ang), total / total.max(), color=cmap(k / max(1, len(rpm) - 1)), lw=1, label=f"{w:g} RPM"
        )
        for panel, shown in zip(axes[:2], (30.0, 90.0)):
            if w == shown:
                d = snaps[-1]
                sc = _field_panel(panel, d, np.clip(d["pressure"], 10.0, None), LogNorm(10, 1e4), "magma", 0.25)
                for a in (rear, front):
                    panel.plot(
                        [0, 1.3 * r * np.sin(a)], [d["body"][1], d["body"][1] - 1.3 * r * np.cos(a)], "c-", lw=1.2
                    )
                panel.axhline(surface, color="0.5", lw=0.6, ls=":")
                panel.set_title(
                    f"{w:g} RPM: loaded arc {np.degrees(rear):+.0f} to {np.degrees(front):+.0f} deg", fontsize=9
                )
                panel.set_xlabel("x - x_wheel (m)")
    if any(r_["omega_rpm"] == 30.0 for r_ in rows):
        fig.colorbar(sc, ax=axes[:2], label="grain pressure (Pa)", fraction=0.02)
    axes[0].set_ylabel("z (m)")
    axes[2].set(xlabel="angle from straight down, + forward (deg)", ylabel="load / its peak", xlim=(-90, 110),
                title=f"load by angle (arc: {LOAD_FRACTION:.0%} out each end)")  # fmt: skip
    axes[2].legend(fontsize=6, ncol=2)
    xs, psi = np.array([q["r_omega2_over_g"] for q in rows]), np.array([q["psi_b"] for q in rows])
    offset, slope = fit_psi_affine(rpm * RPM, psi * r, r, s.gravity)
    for q in rows:
        q["psi_b_fit_offset"], q["psi_b_fit_slope"] = float(offset), float(slope)
    xx = np.linspace(0.0, xs.max() * 1.05, 50)
    ax = axes[3]
    ax.plot(xs, psi, "o", color="tab:red", label=r"MPM: $\psi_b = \delta h_b / r$ (where the wheel stops bearing)")
    ax.plot(xx, offset + slope * xx, "-", color="tab:red", lw=0.8, label=rf"fit ${offset:.2f} + {slope:.2f}\,x$")
    ax.plot(xx, xx, ":", color="tab:blue", label=r"paper: $\psi = x$")
    ax.plot(
        xs,
        [q["dh_free_surface_m"] / r for q in rows],
        "s",
        mfc="none",
        color="0.4",
        label=r"Fig 5C: rear free surface $\delta h / r$",
    )
    ax.set(xlabel=r"$x = r\omega^2 / g$", ylabel=r"$\psi$", title="structural correction's depth")
    ax.legend(fontsize=6)
    return save_figure(fig, out, "wheel_load", rows)


def with_mpm(
    curves: list,
    scenario: LocomotorScenario,
    rpm: np.ndarray,
    quick: bool,
    parallel: bool,
    runs: Path | None,
    label: str = "MPM",
) -> list:
    """Append an MPM curve (computed or reused) to a list of RFT/DRFT curves."""
    return curves + [(label, scenario, mpm_sweep(scenario, rpm, quick, parallel, runs))]
