"""DRFT calibrated on MPM: the figure (PNG), the per-omega comparison (CSV) and the fit (JSON).

``intrusim calibrate`` calls :func:`write_calibration`. The figure has the axes of the paper's
Fig 3 and S1 (v / sqrt(g l), sinkage / l against omega / omega_0, each wheel with its own l):
MPM points, DRFT before calibration (the paper's values) and DRFT with the calibrated ones,
for the calibrated scenario and for each transfer check (another scenario with the same
calibrated parameters and no refitting). Files, for ``name``:

* ``name.png`` and ``name.csv`` (every plotted point), written by :func:`intrusim.figures._output.write_curves`;
* ``name_vs_mpm.csv``: relative difference of each DRFT curve from MPM at the MPM omegas;
* with transfer checks, also one figure per body, ``name_LABEL.png`` (LABEL the check's name, a
  TOML file's stem, numbered where two would be the same; ``name_calibrated.png`` for the
  calibrated body), with its own CSVs as above: MPM, the paper's DRFT and the calibrated DRFT of
  that body alone;
* ``name.json``: the fitted values, the fit's per-omega errors, the errors before calibration
  (the paper's values unless the start was changed), the transfer checks, psi fitted to the
  measured rear surface drop, and the 15 % verdict.
"""

from __future__ import annotations

import json
import re
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Sequence

import numpy as np

from intrusim.analysis.calibration import (
    CalibrationResult,
    Comparison,
    comparison,
    drft_steady_states,
    fit_psi_affine,
    fit_psi_linear,
    with_parameters,
)
from intrusim.analysis.sweep import SweepResult
from intrusim.figures._output import write_curves
from intrusim.mpm.io import atomic_write_bytes
from intrusim.params import RPM
from intrusim.scenarios import LocomotorScenario

CURVE_RPM = np.arange(10.0, 90.1, 5.0)  # the DRFT curves (the MPM omegas are added)
TARGET = 0.15  # the mission's target: DRFT within 15 % of MPM at every omega


@dataclass(frozen=True)
class Check:
    """A transfer check: ``scenario`` (its own geometry, inertias, push and force model: a
    runner keeps its lambda and its structural correction) against its MPM ``reference``; the
    calibration's fitted values are put in, and nothing else."""

    label: str
    scenario: LocomotorScenario
    reference: SweepResult


def psi_from_surface_drop(scenario: LocomotorScenario, reference: SweepResult) -> dict[str, Any] | None:
    """psi fitted to the reference's measured rear drop (``surface_drop``), or None without one."""
    dh = reference.column("surface_drop")
    ok = np.isfinite(dh)
    if ok.sum() < 2:
        return None
    w = reference.omega_rpm[ok] * RPM
    a, c = fit_psi_affine(w, dh[ok], scenario.radius, scenario.gravity)
    return {"linear_slope": fit_psi_linear(w, dh[ok], scenario.radius, scenario.gravity), "affine_offset": a, "affine_slope": c,
            "points": int(ok.sum()), "radius_m": scenario.radius}  # fmt: skip


def _force_label(scenario: LocomotorScenario) -> str:
    fm = scenario.force_model
    bull = f", bulldozing k_b {fm.bulldozing:.3g}" if fm.bulldozing > 0.0 else ""
    return f"xi {fm.xi:.3g}, psi {fm.psi_offset:.3g} + {fm.psi_slope:.3g} x, lambda {fm.lam:.3g}{bull}"


def _verdict(cmp: Comparison) -> dict[str, bool]:
    return {
        "velocity_within_15pct": cmp.max_abs_rel_error_velocity <= TARGET,
        "sinkage_within_15pct": cmp.max_abs_rel_error_sinkage <= TARGET,
    }


def _curve(scenario: LocomotorScenario, reference: SweepResult, kind: str) -> SweepResult:
    rpm = np.union1d(CURVE_RPM, reference.omega_rpm)
    return drft_steady_states(scenario, rpm, kind)


def write_calibration(
    out: Path,
    name: str,
    result: CalibrationResult,
    start: LocomotorScenario,
    reference: SweepResult,
    checks: Sequence[Check] = (),
    kind: str = "drft",
    meta: dict[str, Any] | None = None,
) -> tuple[list[Path], dict[str, Comparison]]:
    """Write ``name``.png / .csv / _vs_mpm.csv / .json under ``out`` (see module docstring).

    Returns the paths written and, by label, each check's calibrated DRFT against its MPM.

    Parameters
    ----------
    result : the calibration of ``start`` on ``reference``.
    start : the scenario before calibration (with the shipped defaults: the paper's values).
    checks : transfer checks; each gets the calibrated values of ``result.params`` and nothing else.
    kind : DRFT force-model kind of the calibration.
    meta : extra JSON entries (the command line, the input files).
    """
    cases = [(start, with_parameters(start, result.values), reference, "")]
    for chk in checks:
        cases.append((chk.scenario, with_parameters(chk.scenario, result.values), chk.reference, f" ({chk.label})"))
    curves: list[tuple[str, LocomotorScenario, SweepResult]] = []
    per_body: list[tuple[str, list[tuple[str, LocomotorScenario, SweepResult]]]] = []
    report: dict[str, Any] = {"calibration": result.summary(), "verdict": _verdict(result.comparison), "checks": {}}
    check_cmps: dict[str, Comparison] = {}
    for i, (s0, s1, ref, tag) in enumerate(cases):
        after = _curve(s1, ref, kind)
        if result.params:
            before = _curve(s0, ref, kind)
            body = [(f"MPM{tag}", s0, ref), (f"DRFT before{tag}", s0, before), (f"DRFT calibrated{tag}", s1, after)]
        else:  # nothing fitted (--params none): the model as given, once
            before = after
            body = [(f"MPM{tag}", s0, ref), (f"DRFT, nothing fitted{tag}", s1, after)]
        curves += body
        label = "calibrated" if i == 0 else re.sub(r"[^A-Za-z0-9_-]+", "_", Path(checks[i - 1].label).stem)
        if any(label == used for used, _ in per_body):  # one file name per body
            label = f"{label}_{i}"
        per_body.append((label, body))
        entry = {
            "uncalibrated": comparison(s0.name, ref, before).summary(),
            "psi_from_surface_drop": psi_from_surface_drop(s0, ref),
        }
        if i == 0:
            report.update(entry)
        else:
            cal_cmp = check_cmps[checks[i - 1].label] = comparison(s1.name, ref, after)
            report["checks"][checks[i - 1].label] = {
                "calibrated": cal_cmp.summary(),
                "verdict": _verdict(cal_cmp),
                **entry,
            }
    report.update(meta or {})
    head = f"DRFT on MPM ({start.force_model.structural}, DRFT push {start.external_fx:g} N)"
    if result.params:
        title = f"{head}; before: {_force_label(start)};\ncalibrated: {_force_label(result.scenario)}"
    else:
        title = f"{head}, nothing fitted: {_force_label(start)}"
    paths = write_curves(out, name, curves, title)
    if checks:  # one figure per body as well
        for label, body in per_body:
            paths += write_curves(out, f"{name}_{label}", body, f"{body[0][1].name}: {title}")
    paths.append(out / f"{name}.json")
    atomic_write_bytes(paths[-1], json.dumps(report, indent=1).encode())
    return paths, check_cmps
