"""What every figure writes: its PNG and the CSV of the plotted numbers (and, beside MPM curves,
the relative differences of the model curves from them)."""

from __future__ import annotations

import csv
from pathlib import Path
from typing import Any

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from intrusim.analysis.sweep import SweepResult  # noqa: E402
from intrusim.params import RPM  # noqa: E402
from intrusim.scenarios import LocomotorScenario  # noqa: E402


def write_curves(
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
        if label.startswith(
            "MPM"
        ):  # dashed, open markers: black circles, then grey squares, black triangles, grey diamonds
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
    csv_rows(csv_path, rows)
    paths = [png, csv_path]
    agreement = agreement_rows(curves)
    if agreement:
        paths.append(out / f"{name}_vs_mpm.csv")
        csv_rows(paths[-1], agreement)
    return paths


def agreement_rows(curves: list[tuple[str, LocomotorScenario, SweepResult]]) -> list[dict[str, Any]]:
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


def csv_rows(path: Path, rows: list[dict[str, Any]]) -> None:
    with path.open("w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)


def save_figure(fig: Any, out: Path, name: str, rows: list[dict[str, Any]]) -> list[Path]:
    out.mkdir(parents=True, exist_ok=True)
    png, csv_path = out / f"{name}.png", out / f"{name}.csv"
    fig.savefig(png, dpi=120)
    plt.close(fig)
    csv_rows(csv_path, rows)
    return [png, csv_path]
