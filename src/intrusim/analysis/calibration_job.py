"""``intrusim calibrate`` as a library call: a body's MPM references made (or read), DRFT fitted to
them, the transfer checks, the files written, and everything a user must know said on the way.

:func:`run_calibration` takes a :class:`CalibrationJob` (the command's options, validated before
any compute) and two callables, ``say`` for results and ``warn`` for what may make them wrong:

* every MPM run that failed, with its own reason (a body the box cannot hold, settings of another
  run in its folder, a guard that stopped it);
* MPM runs that did not settle (their averages are not steady states: ``settled_only``);
* cells coarser than a fifth of the body's thinnest feature (lug thickness or height);
* the fit's verdict against the 15 % target, parameters at a bound of their range and parameters
  the data do not identify (:meth:`~intrusim.analysis.calibration.CalibrationResult.std_errors`);
* the forward push DRFT is given (``mpm_push``) and that the model file carries it.

Every output goes under ``out``: the MPM run folders (``out/mpm-runs`` unless ``runs`` is given),
their table, the fit's PNG / CSV / JSON, the model file and the effective body (``NAME.body.json``).
``out`` is checked for writing before anything is computed.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable, Optional

import numpy as np

from intrusim._checks import InputError, check_workers, check_writable

Say = Callable[[str], None]


@dataclass
class CalibrationJob:
    """The options of ``intrusim calibrate`` (see its ``--help`` for each)."""

    scenario: str
    mpm: Optional[Path] = None
    mpm_omegas: Optional[str] = None
    quick: bool = False
    preset: Optional[str] = None
    runs: Optional[Path] = None
    settings: Optional[Path] = None
    sets: list[str] = field(default_factory=list)
    params: str = "xi,psi"
    fix: list[str] = field(default_factory=list)
    structural: Optional[str] = None
    mpm_push: bool = True
    psi_from_dh: str = "none"
    check: list[str] = field(default_factory=list)
    model: str = "drft"
    settled_only: bool = False
    starts: int = 8
    out: Path = Path("figures")
    name: Optional[str] = None
    rft_coefficients: Optional[Path] = None
    leave_one_out: bool = False
    workers: int = 1

    @property
    def stem(self) -> str:
        return self.name or f"calibration_{Path(self.scenario).stem.replace('-', '_')}"

    @property
    def fitted(self) -> list[str]:
        p = self.params.strip()
        return [] if p == "none" else [x.strip() for x in p.split(",") if x.strip()]


def fixed_values(items: list[str], fitted: list[str]) -> dict[str, float]:
    """``--fix NAME=VALUE`` items as {name: value}: each a known parameter, finite, given once and not fitted."""
    from intrusim.analysis.calibration import PARAMETERS

    out: dict[str, float] = {}
    for item in items:
        key, sep, text = item.partition("=")
        key = key.strip()
        if not sep or key not in PARAMETERS:
            raise InputError(f"--fix must be NAME=VALUE with NAME one of {', '.join(PARAMETERS)}, got {item!r}")
        if key in out or key in fitted:
            raise InputError(f"--fix {key}: {'given twice' if key in out else 'also in --params (fitted)'}")
        try:
            value = float(text)
        except ValueError:
            raise InputError(f"--fix {key}: {text.strip()!r} is not a number") from None
        if not math.isfinite(value):
            raise InputError(f"--fix {key}: must be finite, got {text.strip()!r}")
        out[key] = value
    return out


def pct(x: float, sign: str = "+") -> str:
    """A relative error as a percentage; a failed DRFT point (NaN, or an infinite maximum) as 'failed'."""
    return f"{x:{sign}.1%}" if math.isfinite(x) else "failed"


def comparison_table(c: Any) -> list[str]:
    """A calibration's per-omega table (an ``analysis.calibration.Comparison``), units in the header."""
    lines = [
        f"{'omega RPM':>9} | {'v MPM m/s':>9} | {'v DRFT m/s':>10} | {'dv':>6} | {'s MPM mm':>8} | {'s DRFT mm':>9} | {'ds':>6}"
    ]
    rows = zip(c.omega_rpm, c.velocity_ref, c.velocity_model, c.rel_error_velocity, c.sinkage_ref, c.sinkage_model,
               c.rel_error_sinkage)  # fmt: skip
    for w, v0, v1, dv, s0, s1, ds in rows:
        lines.append(
            f"{w:9.4g} | {v0:9.4f} | {v1:10.4f} | {pct(dv):>6} | {s0 * 1e3:8.2f} | {s1 * 1e3:9.2f} | {pct(ds):>6}"
        )
    lines.append(
        f"max |relative error|: velocity {pct(c.max_abs_rel_error_velocity, '')}, sinkage {pct(c.max_abs_rel_error_sinkage, '')}"
    )
    return lines


def unique_omegas(ref: Any, source: Any) -> Any:
    """``ref`` (a reference sweep) if each of its omegas appears once; else an InputError, before any fit."""
    w = [float(x) for x in ref.omega_rpm]
    twice = sorted({x for x in w if w.count(x) > 1})
    if twice:
        raise InputError(
            f"{source}: omega_rpm {', '.join(f'{x:g}' for x in twice)} appears more than once "
            "(one run per omega: gather them with `intrusim mpm collect`)"
        )
    return ref


def _failure_fix(error: str) -> str:
    """The fix that works for a failed MPM run's reason (the CSV's error column)."""
    if "holds MPM runs of other settings" in error or "holds a run of another configuration" in error:
        return "give another --runs folder (or --out), or remove that run folder"
    if "does not fit" in error or "cells must be square" in error:
        return "--set domain=[Lx, Lz] --set cell_size=H sets the box by hand"
    if "reached the wall" in error:
        return "a longer bed (--set length=...) or a shorter settle_time"
    return "`intrusim mpm steady --scenario ... --omega-rpm W --quick` runs it alone with its full diagnosis"


def make_references(job: CalibrationJob, scn: Any, csv: Path, say: Say, warn: Say) -> Path:
    """Make (or reuse) the MPM runs of ``scn`` at the job's omegas, write their table to ``csv``, and
    say each failed run's reason; InputError when none finished."""
    from intrusim.analysis.sweep import omega_list
    from intrusim.figures.mpm import MPM_RUNNER_RPM, MPM_WHEEL_RPM, mpm_sweep_table
    from intrusim.scenarios.mpm_locomotion import check_run
    from intrusim.scenarios.mpm_settings import case_settings, settings_items

    omegas = job.mpm_omegas
    w = omega_list(omegas) if omegas is not None else (MPM_RUNNER_RPM if scn.body == "runner" else MPM_WHEEL_RPM)
    if len(w) < 1:
        raise InputError(f"--mpm-omegas gives no angular velocity, got {omegas!r}")
    if job.fitted and len(w) < 2:
        raise InputError(f"--mpm-omegas: a fit needs at least 2 omegas, got {len(w)} ({omegas})")
    settings = case_settings(
        scn, job.quick, job.settings, job.sets, echo=warn, preset=job.preset
    )  # refused before any run; warns of coarse cells
    for omega in w:  # and a run that cannot be made (a box set by hand that cannot hold the body, too many steps)
        check_run(scn, settings, float(omega))
    runs = job.runs if job.runs is not None else job.out / "mpm-runs"
    res = mpm_sweep_table(
        scn, w, job.quick, runs, settings_items(job.settings, job.sets), csv, workers=job.workers, preset=job.preset
    )
    failed = [r for r in res.records if not r.get("ok")]
    for r in failed:
        err = str(r.get("error") or "unknown error").strip()
        warn(f"{scn.name} at {r['omega_rpm']:g} RPM failed: {err} (fix: {_failure_fix(err)})")
    if len(failed) == len(res.records):
        raise InputError(
            f"{csv}: no MPM run of {scn.name} finished (the reasons are above; each run's folder is under {runs})"
        )
    say(
        f"MPM references: {csv} ({len(res.records) - len(failed)} of {len(res.records)} runs finished; run folders under {runs})"
    )
    return csv


def _reference_warnings(job: CalibrationJob, scn: Any, ref: Any, csv: Path, made: bool, warn: Say) -> None:
    """Unsettled runs, and (for a given CSV with its settings record) cells too coarse for the body."""
    from intrusim.scenarios.mpm_locomotion import resolution_warning
    from intrusim.scenarios.mpm_settings import read_record

    loose = [r for r in ref.records if "settled" in r and not bool(r["settled"])]
    short = [r for r in loose if r.get("outcome") == "too short"]
    moving = [r for r in loose if r.get("outcome") != "too short"]
    if short:
        ws = ", ".join(f"{r['omega_rpm']:g}" for r in short)
        warn(
            f"{len(short)} of {len(ref.records)} MPM runs were too short to judge ({ws} RPM: the settle test needs two "
            "revolutions after the transient): their averages may not be steady states; lengthen them (--set t_max=...; "
            "with a treadmill and --set settle_tol=0.01 each stops once settled)"
            + ("" if job.settled_only else "; --settled-only would leave them out")
        )
    if moving and not job.settled_only:
        ws = ", ".join(f"{r['omega_rpm']:g} RPM" + (f" {r['outcome']}" if r.get("outcome") else "") for r in moving)
        warn(
            f"{len(moving)} of {len(ref.records)} MPM runs did not settle ({ws}); their averages are not steady "
            "states: --settled-only fits only the settled runs, or lengthen them (--set t_max=...; --set settle_tol=0.01 "
            "stops each once settled)"
        )
    if not made:
        record = read_record(csv) or {}
        for s in list(record.values())[:1]:
            domain, cells = s.get("domain"), s.get("cells")
            if domain and cells:
                note = resolution_warning(scn, float(domain[0]) / int(cells[0]))
                if note:
                    warn(note)


def _fit_warnings(res: Any, say: Say, warn: Say) -> None:
    """The verdict against the 15 % target; parameters at a bound or not identified by the data."""
    from intrusim.figures.calibration import TARGET

    c = res.comparison
    ev, es = c.max_abs_rel_error_velocity, c.max_abs_rel_error_sinkage
    ok = ev <= TARGET and es <= TARGET
    say(
        f"verdict: {'within' if ok else 'NOT within'} {TARGET:.0%} of the MPM at every omega "
        f"(velocity {pct(ev, '')}, sinkage {pct(es, '')})"
    )
    if not ok:
        warn(f"the fit misses the {TARGET:.0%} target: the model is not a good stand-in for the MPM on this body")
    errors = res.std_errors()
    shown = []
    for p in res.params:
        v, (lo, hi) = res.values[p], res.bounds[p]
        se = errors.get(p, math.nan)
        near = min(se, 0.02 * (hi - lo)) if math.isfinite(se) else 0.02 * (hi - lo)  # within its error, at most 2 %
        if min(v - lo, hi - v) <= max(near, 1e-3 * (hi - lo)):
            warn(
                f"{p} = {v:.4g} is at a bound of its range [{lo:g}, {hi:g}]: the data push it further; not a measured value"
            )
        scale = max(abs(v), 0.1 * (hi - lo))  # a value near 0 is judged against its range
        identified = math.isfinite(se) and se <= 0.5 * scale
        if not identified:
            spread = _flat_range(res, p)
            extra = f"; other starts reach within 5 % of the best cost at {p} = {spread}" if spread else ""
            how = "the cost is flat along it" if not math.isfinite(se) or se > hi - lo else f"standard error {se:.2g}"
            warn(f"{p} = {v:.4g} is not identified by the data ({how}){extra}")
        shown.append(f"{p} = {v:.4g} +- {2 * se:.2g}" if identified else f"{p} = {v:.4g} (not identified)")
    if shown:
        say("fitted values (+- 2 standard errors): " + ", ".join(shown))


def _flat_range(res: Any, p: str) -> str | None:
    """The range of ``p`` over the local fits within 5 % of the best cost ('a-b'), if wider than 10 % of its bounds."""
    fits = res.meta.get("local_fits") or []
    near = [f["values"][p] for f in fits if f["cost"] <= 1.05 * res.cost + 1e-12]
    lo, hi = res.bounds[p]
    if len(near) > 1 and max(near) - min(near) > 0.1 * (hi - lo):
        return f"{min(near):.3g}-{max(near):.3g}"
    return None


def _write_model_file(path: Path, res: Any, kind: str, mpm_push: bool, mpm: Path) -> Path:
    from intrusim.analysis.model_file import ModelFile, write_model

    c = res.comparison.summary()  # the errors as the fit's record has them (None where not finite)
    fit = {"params": res.values, "reference": str(mpm), "omega_rpm": c["omega_rpm"],
           **{k: c[k] for k in ("max_abs_rel_error_velocity", "max_abs_rel_error_sinkage")}}  # fmt: skip
    model = ModelFile(kind=kind, force_model=res.scenario.force_model, mpm_push=mpm_push,
                      calibrated_on=res.scenario.name, fit=fit)  # fmt: skip
    return write_model(path, model)


def run_calibration(job: CalibrationJob, say: Say = print, warn: Optional[Say] = None) -> list[Path]:
    """Calibrate DRFT on a body's MPM steady states and check the transfer to other bodies
    (``intrusim calibrate``); returns the files written. Bad input is an InputError (or
    ValueError) raised before any compute."""
    from intrusim.analysis.calibration import calibrate as fit
    from intrusim.analysis.calibration import check_reference, load_reference, with_mpm_push, with_parameters
    from intrusim.analysis.calibration import leave_one_out as cross_validate
    from intrusim.analysis.model_file import with_rft_table
    from intrusim.figures.calibration import Check, psi_from_surface_drop, write_calibration
    from intrusim.scenarios import load_scenario
    from intrusim.scenarios.locomotor import write_body

    warn = warn or (lambda text: say(f"warning: {text}"))
    check_workers(job.workers)
    names = job.fitted
    if not names and job.params.strip() != "none":
        raise InputError("--params names no parameter: give one or more, or 'none' to fit nothing")
    if not names and job.leave_one_out:
        raise InputError("--leave-one-out refits without each omega: nothing is fitted with --params none")
    fixed = fixed_values(job.fix, names)
    if job.psi_from_dh not in ("none", "linear", "affine"):
        raise InputError(f"--psi-from-dh must be none, linear or affine, got {job.psi_from_dh!r}")
    if job.psi_from_dh != "none" and {"psi", "psi_offset"} & (set(names) | set(fixed)):
        raise InputError("--psi-from-dh sets psi: do not fit psi or psi_offset, nor --fix them")
    if job.name is not None and (not job.name or Path(job.name).name != job.name):
        raise InputError(f"--name must be a plain file name stem, got {job.name!r}")
    if job.mpm is not None and (
        job.mpm_omegas is not None or job.quick or job.preset or job.runs is not None or job.settings or job.sets
    ):
        raise InputError(
            "--mpm-omegas, --quick, --preset, --runs, --settings and --set make the MPM runs: not with --mpm"
        )

    def prepared(name: str, check: bool = False) -> Any:
        """A scenario with this job's choices: the RFT table, the push, and ``structural`` (on a
        checked scenario only in place of a correction of its own: a runner keeps none)."""
        s = with_rft_table(load_scenario(name), job.rft_coefficients)
        if job.structural is not None and not (check and s.force_model.structural == "none"):
            s = s.validated_copy(force_model=s.force_model.validated_copy(structural=job.structural))
        s = with_parameters(s, fixed)
        return with_mpm_push(s) if job.mpm_push else s

    stem, out = job.stem, Path(job.out)
    start = prepared(job.scenario)
    checks_in = []
    for item in job.check:  # a bad check is refused before any compute
        label, sep, path = item.partition("=")
        if not sep:
            raise InputError(f"--check must be NAME=CSV, got {item!r}")
        if any(lb == label.strip() for lb, _ in checks_in):  # the comparisons are keyed by NAME: one would be lost
            raise InputError(
                f"--check {label.strip()} given twice: put its omegas in one CSV (research/steady_to_sweep.py takes several files)"
            )
        checks_in.append((label.strip(), path.strip()))
    check_writable(out)
    if job.runs is not None:
        check_writable(job.runs, "--runs")
    if job.mpm_push:
        say(
            f"DRFT is given the MPM runs' constant forward push, {start.external_fx:.3g} N on {start.name} (Table S1's 4 N "
            "scaled by mass_x / 23 kg); the model file records it (mpm_push), and `steady|sweep --model` applies it: "
            "--no-mpm-push leaves it out"
        )
    mpm, made = job.mpm, job.mpm is None
    if mpm is None:
        mpm = make_references(job, load_scenario(job.scenario), out / f"{stem}_mpm.csv", say, warn)
    ref = unique_omegas(check_reference(load_reference(mpm, start.name, settled_only=job.settled_only)), mpm)
    _reference_warnings(job, start, ref, Path(mpm), made, warn)
    psi_values: dict[str, float] = {}  # set from the calibrated scenario's rear drop, reused by the checks
    if job.psi_from_dh != "none":
        psi = psi_from_surface_drop(start, ref)
        if psi is None:
            raise InputError(f"{mpm}: fewer than 2 runs with a measured rear surface drop")
        linear = job.psi_from_dh == "linear"
        psi_values = {"psi": psi["linear_slope"] if linear else psi["affine_slope"],
                      "psi_offset": 0.0 if linear else psi["affine_offset"]}  # fmt: skip
        start = with_parameters(start, psi_values)
    checks = []
    for label, path in checks_in:
        s = with_parameters(prepared(label, check=True), psi_values)
        try:
            checks.append(Check(label, s, unique_omegas(check_reference(load_reference(path, s.name)), path)))
        except ValueError as err:
            raise InputError(f"--check {label}: {err}") from None
    parallel = job.workers > 1
    res = fit(start, ref, names, kind=job.model, starts=job.starts, parallel=parallel, n_workers=job.workers)
    say(
        f"{start.name}: {', '.join(f'{p} = {v:.4g}' for p, v in res.values.items())} ({res.nfev} evaluations; {res.message})"
    )
    for line in comparison_table(res.comparison):
        say(line)
    _fit_warnings(res, say, warn)
    loo = None
    if job.leave_one_out:
        say("leave-one-out: each omega predicted by a fit without it")
        loo = cross_validate(start, ref, names, kind=job.model, starts=job.starts, progress=say, parallel=parallel,
                             n_workers=job.workers)  # fmt: skip
        for line in comparison_table(loo.comparison):
            say(line)
    command = {k: (str(v) if isinstance(v, Path) else v) for k, v in vars(job).items()}
    meta: dict[str, Any] = {"command": {**command, "mpm": str(mpm), "params": names, "fixed": fixed,
                                        "structural": start.force_model.structural, "external_fx_N": start.external_fx}}  # fmt: skip
    if loo is not None:
        meta["leave_one_out"] = loo.summary()
    paths, check_cmps = write_calibration(out, stem, res, start, ref, checks, job.model, meta)
    paths.append(_write_model_file(out / f"{stem}.model.json", res, job.model, job.mpm_push, Path(mpm)))
    paths.append(
        write_body(out / f"{stem}.body.json", load_scenario(job.scenario), start.external_fx)
    )  # the body as run, beside the results
    for label, c in check_cmps.items():
        rows = ", ".join(
            f"{w:g} RPM v {pct(dv)} s {pct(ds)}"
            for w, dv, ds in zip(c.omega_rpm, c.rel_error_velocity, c.rel_error_sinkage)
        )
        say(f"check {label} ({c.name}, fitted values reused): {rows}; max |relative error| velocity "
            f"{pct(c.max_abs_rel_error_velocity, '')}, sinkage {pct(c.max_abs_rel_error_sinkage, '')}")  # fmt: skip
    if not np.isfinite(res.max_abs_rel_error):
        warn("a DRFT point of the fit failed (no steady state): see the CSV's error column")
    return paths
