"""DRFT calibrated on MPM runs (mission part 6): the free-surface law and the DRFT parameters.

Two fits:

* :func:`fit_psi_linear`, :func:`fit_psi_affine`: the free-surface law psi from the rear
  free-surface drop dh that MPM measures (paper Fig 5C): dh = r psi(x), x = r omega^2 / g, with
  psi(x) = c x (least squares through the origin; the paper: c = 1) or psi(x) = a + c x.
* :func:`calibrate`: chosen DRFT parameters of a locomotor scenario (:data:`PARAMETERS`: xi,
  the psi slope and offset, lambda) fitted to MPM steady states (velocity and sinkage at each
  omega) by bounded least squares on the relative errors (``scipy.optimize.least_squares``).

:func:`compare` evaluates a scenario against a reference without fitting (e.g. the small wheel
with the parameters calibrated on the large one: the transfer check of Fig S1).

A reference is a :class:`~intrusim.analysis.sweep.SweepResult` of MPM steady states
(:func:`load_reference` reads ``runs/mpm/*_mpm_sweep.csv``): columns ``velocity_m_s``,
``sinkage_m`` and, for psi, ``surface_drop_m``, at ``omega_rpm`` (RPM); a CSV written before the
units were in the names (``velocity``, ``sinkage``, ``surface_drop``) reads the same. The records
keep the short keys (``reference.column("velocity")``, m/s).

The DRFT steady state is a piecewise-smooth function of the parameters (elements switch on and
off as the body moves), so the Jacobian is taken by finite differences over a finite step
(``diff_step``, 2 % by default), not at machine precision.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, Callable, Mapping, Sequence

import numpy as np
from scipy.optimize import least_squares
from scipy.stats import qmc

from intrusim.analysis.sweep import SweepResult, dask_map, sweep_omega
from intrusim.params import GRAVITY
from intrusim.scenarios.base import ForceModelConfig
from intrusim.scenarios.locomotor import LocomotorScenario


@dataclass(frozen=True)
class Parameter:
    """A fittable DRFT parameter: the :class:`ForceModelConfig` field it sets and its default bounds."""

    field: str
    bounds: tuple[float, float]
    description: str
    start_when_off: float | None = None
    """Starting value of a fit when the scenario's value is 0 (the term is off): at 0 on the lower
    bound, the finite-difference Jacobian's step sees too small a change to leave it."""


PARAMETERS: dict[str, Parameter] = {
    "xi": Parameter("xi", (0.05, 5.0), "media scaling of the Li (2013) fit: the RFT stiffness K (paper 0.35)"),
    "psi": Parameter("psi_slope", (0.0, 5.0), "slope c of the free-surface law psi(x) = a + c x (paper 1)"),
    "psi_offset": Parameter("psi_offset", (-0.5, 0.5), "offset a of psi(x) = a + c x (paper 0)"),
    "lam": Parameter("lam", (0.0, 50.0), "lambda of the inertial correction (paper wheel 1)"),
    "zone_width": Parameter(
        "zone_width",
        (0.0, 1.5),
        "rad, the band across which the lowered rear surface rises (paper: 0, a sharp split)",
        0.2,
    ),
    "bulldozing": Parameter(
        "bulldozing", (0.0, 20.0), "k_b of the bulldozing resistance k_b K_p rho g W d^2 / 2 (paper: none, 0)", 1.0
    ),
}

FAILED_RESIDUAL = 10.0
"""Relative error given to a DRFT point that fails (integrator error, no contact): 1000 %."""


# --- the free-surface law from the measured rear drop (Fig 5C) ------------------------------------
def _psi_data(
    omega: Any, surface_drop: Any, radius: float, gravity: float, min_points: int
) -> tuple[np.ndarray, np.ndarray]:
    """(x, y) = (r omega^2 / g, dh / r), checked."""
    w = np.asarray(omega, float)
    dh = np.asarray(surface_drop, float)
    if w.ndim != 1 or w.shape != dh.shape:
        raise ValueError(f"omega and surface_drop must be 1-D arrays of equal length, got {w.shape} and {dh.shape}")
    if not (np.all(np.isfinite(w)) and np.all(np.isfinite(dh))):
        raise ValueError(
            "omega and surface_drop must be finite (drop the NaN points of runs without a measured drop first)"
        )
    if not (radius > 0.0 and gravity > 0.0 and math.isfinite(radius) and math.isfinite(gravity)):
        raise ValueError(f"radius and gravity must be finite and > 0, got {radius!r}, {gravity!r}")
    x = radius * w**2 / gravity
    if len(np.unique(x)) < min_points:
        raise ValueError(f"need at least {min_points} distinct |omega| to fit psi, got {len(np.unique(x))}")
    return x, dh / radius


def fit_psi_linear(omega: Any, surface_drop: Any, radius: float, gravity: float = GRAVITY) -> float:
    """Slope c of psi(x) = c x fitted to the rear surface drop: least squares of dh / r on x.

    Parameters
    ----------
    omega : (N,) angular velocities, rad/s (the sign does not matter).
    surface_drop : (N,) measured rear free-surface drop dh, m (Fig 5C).
    radius : wheel radius r, m (the nominal outer radius of the structural correction).
    gravity : g, m/s^2.

    Returns
    -------
    c, dimensionless (the paper's law: c = 1).
    """
    x, y = _psi_data(omega, surface_drop, radius, gravity, 1)
    return float(np.sum(x * y) / np.sum(x * x))


def fit_psi_affine(omega: Any, surface_drop: Any, radius: float, gravity: float = GRAVITY) -> tuple[float, float]:
    """(a, c) of psi(x) = a + c x fitted to the rear surface drop: least squares of dh / r on x.

    Parameters as :func:`fit_psi_linear` (needs two distinct omegas). dh = r a + c r x, so r a
    (m) is the drop extrapolated to omega = 0.
    """
    x, y = _psi_data(omega, surface_drop, radius, gravity, 2)
    (a, c), *_ = np.linalg.lstsq(np.column_stack([np.ones_like(x), x]), y, rcond=None)
    return float(a), float(c)


# --- the reference and the DRFT parameters ----------------------------------------------------
def load_reference(path: Any, scenario: str = "", settled_only: bool = False) -> SweepResult:
    """MPM steady states from a sweep CSV (:meth:`SweepResult.from_csv`: the columns with their unit
    in the name, ``velocity_m_s``, or as older files have them, ``velocity``): the finished (ok) rows,
    sorted by omega.

    settled_only: keep only the rows whose ``settled`` column is true (the settle test of
    :mod:`intrusim.analysis.settling`; in CSVs written before it, the window's halves within 5 %):
    a run still digging in has no steady state to fit.
    """
    res = SweepResult.from_csv(path)
    rows = sorted((r for r in res.records if r["ok"]), key=lambda r: r["omega_rpm"])
    if settled_only:  # a sweep CSV without the flag reads back as not settled
        rows = [r for r in rows if bool(r.get("settled", False))]
    if not rows:
        raise ValueError(f"{path}: no finished (ok{', settled' if settled_only else ''}) MPM run")
    return SweepResult(scenario, "mpm", None, rows, meta=res.meta)


def _reference_arrays(reference: SweepResult, min_omegas: int = 1) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(omega_rpm, velocity, sinkage) of a reference, checked for what relative errors need (a
    comparison: one omega or more; a fit asks for ``min_omegas`` = 2)."""
    w, v, s = reference.omega_rpm, reference.column("velocity"), reference.column("sinkage")
    if len(w) < min_omegas:
        raise ValueError(
            f"the reference needs at least {min_omegas} omega{'s' if min_omegas > 1 else ''}, got {len(w)}"
        )
    for name, a in (("omega_rpm", w), ("velocity", v), ("sinkage", s)):
        if not np.all(np.isfinite(a)):
            raise ValueError(f"the reference {name} has NaN or infinite values (failed runs?): {a}")
    if np.any(w <= 0.0):
        raise ValueError(f"reference omega_rpm must be > 0, got {w}")
    if np.any(v == 0.0) or np.any(s == 0.0):
        raise ValueError("relative errors need a non-zero reference velocity and sinkage at every omega")
    return w, v, s


def check_reference(reference: SweepResult) -> SweepResult:
    """``reference`` itself, once checked for a comparison (finite, omega > 0, non-zero v and
    sinkage; one omega or more): a ValueError says what is wrong, before any DRFT is run."""
    _reference_arrays(reference)
    return reference


def _check_names(params: Sequence[str]) -> tuple[str, ...]:
    names = tuple(params)
    unknown = [p for p in names if p not in PARAMETERS]
    if unknown:
        raise ValueError(f"unknown DRFT parameter(s) {unknown}; known: {sorted(PARAMETERS)}")
    if not names or len(set(names)) != len(names):
        raise ValueError(f"give one or more distinct parameters, got {list(names)}")
    return names


def parameter_values(scenario: LocomotorScenario, params: Sequence[str]) -> dict[str, float]:
    """The scenario's current values of ``params`` (names of :data:`PARAMETERS`)."""
    return {p: float(getattr(scenario.force_model, PARAMETERS[p].field)) for p in _check_names(params)}


def with_parameters(scenario: LocomotorScenario, values: Mapping[str, float]) -> LocomotorScenario:
    """A copy of ``scenario`` whose force model has ``values`` (names of :data:`PARAMETERS`), validated;
    ``scenario`` itself for no values."""
    if not values:
        return scenario
    names = _check_names(list(values))
    data = scenario.force_model.model_dump()
    data.update({PARAMETERS[p].field: float(values[p]) for p in names})
    return scenario.model_copy(update=dict(force_model=ForceModelConfig.model_validate(data)))


def with_mpm_push(scenario: LocomotorScenario) -> LocomotorScenario:
    """``scenario`` with the constant forward force of its MPM runs as ``external_fx``, N.

    The MPM wheel runs push the wheel forward (the paper's rig-friction compensation: 4 N for the
    Table S1 wheel, scaled by m_x for other wheels; runner 0), while the shipped RFT/DRFT
    scenarios use 0 N. DRFT calibrated on those runs should drive the same body under the same
    loads.
    """
    from intrusim.scenarios.mpm_locomotion import forward_force, paper_settings

    return scenario.model_copy(update=dict(external_fx=forward_force(scenario, paper_settings(scenario.body))))


def drft_steady_states(scenario: LocomotorScenario, omega_rpm: Sequence[float], kind: str = "drft") -> SweepResult:
    """Serial DRFT steady states at ``omega_rpm`` (a point whose integration fails is retried once
    with a finer step by :func:`~intrusim.analysis.steady.run_steady`).

    Points that still fail stay error records (NaN velocity and sinkage).
    """
    return sweep_omega(scenario, kind, omega_rpm, parallel=False, progress=False)


@dataclass(frozen=True)
class Comparison:
    """A model against a reference at the reference omegas (SI; relative errors (model - ref) / |ref|).

    Attributes
    ----------
    name : scenario name.
    omega_rpm : (N,) RPM.
    velocity_ref, sinkage_ref : (N,) reference (MPM) steady states, m/s and m.
    velocity_model, sinkage_model : (N,) model steady states (NaN where the model failed).
    """

    name: str
    omega_rpm: np.ndarray
    velocity_ref: np.ndarray
    sinkage_ref: np.ndarray
    velocity_model: np.ndarray
    sinkage_model: np.ndarray

    @property
    def rel_error_velocity(self) -> np.ndarray:
        return (self.velocity_model - self.velocity_ref) / np.abs(self.velocity_ref)

    @property
    def rel_error_sinkage(self) -> np.ndarray:
        return (self.sinkage_model - self.sinkage_ref) / np.abs(self.sinkage_ref)

    @property
    def max_abs_rel_error_velocity(self) -> float:
        """max |relative error| of the velocity (inf if a model point failed)."""
        return _max_abs(self.rel_error_velocity)

    @property
    def max_abs_rel_error_sinkage(self) -> float:
        return _max_abs(self.rel_error_sinkage)

    @property
    def max_abs_rel_error(self) -> float:
        return max(self.max_abs_rel_error_velocity, self.max_abs_rel_error_sinkage)

    def residuals(self) -> np.ndarray:
        """Relative errors of velocity then sinkage; a failed point counts :data:`FAILED_RESIDUAL`."""
        r = np.concatenate([self.rel_error_velocity, self.rel_error_sinkage])
        return np.where(np.isfinite(r), r, FAILED_RESIDUAL)

    def summary(self) -> dict[str, Any]:
        """JSON-ready: per-omega numbers and the largest relative errors."""
        return {
            "scenario": self.name, "omega_rpm": self.omega_rpm.tolist(),
            "velocity_ref_m_s": self.velocity_ref.tolist(), "velocity_model_m_s": _list(self.velocity_model),
            "sinkage_ref_m": self.sinkage_ref.tolist(), "sinkage_model_m": _list(self.sinkage_model),
            "rel_error_velocity": _list(self.rel_error_velocity), "rel_error_sinkage": _list(self.rel_error_sinkage),
            "max_abs_rel_error_velocity": _num(self.max_abs_rel_error_velocity),
            "max_abs_rel_error_sinkage": _num(self.max_abs_rel_error_sinkage),
        }  # fmt: skip


def _max_abs(a: np.ndarray) -> float:
    return float(np.max(np.abs(a))) if np.all(np.isfinite(a)) else math.inf


def _num(v: float) -> float | None:
    return float(v) if math.isfinite(v) else None


def _list(a: np.ndarray) -> list[float | None]:
    return [_num(float(v)) for v in a]


def compare(scenario: LocomotorScenario, reference: SweepResult, kind: str = "drft") -> Comparison:
    """DRFT (``kind``) steady states of ``scenario`` against ``reference`` at its omegas."""
    w, _, _ = _reference_arrays(reference)
    return comparison(scenario.name, reference, drft_steady_states(scenario, w, kind))


def comparison(name: str, reference: SweepResult, model: SweepResult) -> Comparison:
    """The ``model`` sweep against ``reference`` at the reference omegas (the model must have each of them)."""
    w, v, s = _reference_arrays(reference)
    at = [np.flatnonzero(model.omega_rpm == wi) for wi in w]
    missing = [float(wi) for wi, i in zip(w, at) if len(i) == 0]
    if missing:
        raise ValueError(f"the model sweep has no steady state at the reference omegas {missing} RPM")
    idx = [int(i[0]) for i in at]
    return Comparison(name, w, v, s, model.column("velocity")[idx], model.column("sinkage")[idx])


@dataclass(frozen=True)
class CalibrationResult:
    """Outcome of :func:`calibrate`.

    Attributes
    ----------
    scenario : the calibrated scenario (force model with the fitted values).
    params : names of the fitted parameters (:data:`PARAMETERS`).
    values, initial : fitted and starting values, by name.
    bounds : (low, high) of each fitted parameter.
    comparison : the calibrated model against the reference (per-omega relative errors).
    cost : 1/2 sum of the squared residuals at the fit.
    nfev : distinct parameter sets evaluated (each one DRFT steady state per reference omega),
        all local fits together.
    success, message : from scipy.optimize.least_squares.
    jacobian : d residuals / d parameters at the fit (finite differences over ``diff_step``), or None
        (nothing fitted); :meth:`std_errors` reads it.
    """

    scenario: LocomotorScenario
    params: tuple[str, ...]
    values: dict[str, float]
    initial: dict[str, float]
    bounds: dict[str, tuple[float, float]]
    comparison: Comparison
    cost: float
    nfev: int
    success: bool
    message: str
    meta: dict[str, Any] = field(default_factory=dict)
    jacobian: np.ndarray | None = field(default=None, repr=False)

    def std_errors(self) -> dict[str, float]:
        """Standard error of each fitted parameter from the Jacobian at the fit (the Gauss-Newton
        covariance s^2 (J^T J)^-1, s^2 the residuals' variance: 2 cost / (residuals - parameters));
        inf for a parameter the data do not identify (J^T J singular: a flat direction of the cost),
        and for every one when there are no more residuals than parameters."""
        if self.jacobian is None or not self.params:
            return {}
        jac = np.asarray(self.jacobian, float)
        if not np.all(np.isfinite(jac)):
            return dict.fromkeys(self.params, math.nan)
        m, n = jac.shape
        if m <= n:  # no degree of freedom left for the residuals' variance: nothing can be said
            return dict.fromkeys(self.params, math.inf)
        s2 = 2.0 * self.cost / (m - n)
        out = dict.fromkeys(self.params, math.inf)  # a parameter the residuals do not move: unidentified
        seen = np.flatnonzero(np.linalg.norm(jac, axis=0) > 0.0)
        if len(seen) == 0:
            return out
        sub = jac[:, seen]
        scale = np.linalg.norm(sub, axis=0)
        norm = (sub.T @ sub) / np.outer(scale, scale)  # unit diagonal: a flat direction is a tiny eigenvalue
        w, vec = np.linalg.eigh(norm)
        flat = np.zeros(len(seen), bool)
        for k in np.flatnonzero(w < 1e-10 * w.max()):
            flat |= np.abs(vec[:, k]) > 0.1  # the parameters taking part in a flat direction
        cov = np.linalg.pinv(norm, hermitian=True) / np.outer(scale, scale) * s2
        for i, col in enumerate(seen):
            out[self.params[col]] = math.inf if flat[i] else float(np.sqrt(max(cov[i, i], 0.0)))
        return out

    @property
    def max_abs_rel_error(self) -> float:
        """Largest |relative error| of velocity and sinkage over the reference omegas."""
        return self.comparison.max_abs_rel_error

    def summary(self) -> dict[str, Any]:
        """JSON-ready record of the fit."""
        fm = self.scenario.force_model
        return {
            "scenario": self.scenario.name, "params": list(self.params), "values": self.values,
            "initial": self.initial, "bounds": {k: list(b) for k, b in self.bounds.items()},
            "force_model": fm.model_dump(mode="json"), "external_fx_N": self.scenario.external_fx,
            "cost": self.cost, "nfev": self.nfev, "success": self.success, "message": self.message,
            "max_abs_rel_error": _num(self.max_abs_rel_error), "comparison": self.comparison.summary(),
            "std_errors": {k: _num(v) for k, v in self.std_errors().items()}, **self.meta,
        }  # fmt: skip


def calibrate(
    scenario: LocomotorScenario,
    reference: SweepResult,
    params: Sequence[str] = ("xi", "psi"),
    *,
    kind: str = "drft",
    initial: Mapping[str, float] | None = None,
    bounds: Mapping[str, tuple[float, float]] | None = None,
    diff_step: float = 0.02,
    max_nfev: int = 60,
    starts: int = 1,
    seed: int = 0,
    parallel: bool = False,
    n_workers: int | None = None,
    scheduler_address: str | None = None,
) -> CalibrationResult:
    """Fit DRFT parameters of ``scenario`` to MPM steady states by bounded least squares.

    Minimises sum over the reference omegas of ((v - v_MPM) / v_MPM)^2 + ((s - s_MPM) / s_MPM)^2,
    v the steady velocity and s the sinkage of the DRFT model, over ``params`` within ``bounds``
    (scipy.optimize.least_squares, trust-region reflective, finite-difference Jacobian).

    Parameters
    ----------
    scenario : LocomotorScenario; its other force-model settings (structural split, rho, the
        parameters not fitted) and its body (mass, external force) are kept.
    reference : MPM steady states (:func:`load_reference`), at least 2 omegas, finite.
    params : names from :data:`PARAMETERS`: "xi", "psi" (slope c), "psi_offset" (a), "lam"; none
        (empty): nothing is fitted, the result is the scenario's own model against the reference
        (a model whose parameters were all measured), with one reference omega or more.
    kind : DRFT force-model kind ("drft"; "rft" or "drft-inertial" ignore the psi parameters).
    initial : starting values (default: the scenario's, clipped into the bounds; a term the
        scenario has off (0) starts from its ``Parameter.start_when_off``, bulldozing from 1).
    bounds : (low, high) per parameter (default :data:`PARAMETERS` bounds).
    diff_step : relative finite-difference step of the Jacobian (the steady state is only
        piecewise smooth in the parameters: machine-precision steps see its jumps).
    max_nfev : most residual evaluations of one local fit.
    starts : local fits to run: from ``initial``, then from ``starts - 1`` points of a scrambled
        Halton sequence (``seed``) filling the bounds; the fit of least cost is returned (the
        cost has several local minima: the steady state jumps as elements switch on and off).
    seed : seed of the Halton sequence.
    parallel : run the local fits on a Dask cluster (:func:`intrusim.analysis.sweep.dask_map`:
        ``n_workers`` local processes, or the cluster at ``scheduler_address``); the same result.

    Raises
    ------
    ValueError for unknown or repeated parameter names, bad bounds or starting values, fewer
    than 2 reference omegas or fewer residuals (2 per omega) than parameters, NaN reference data.
    """
    if not tuple(params):  # nothing fitted: the scenario's model as it is (measured parameters)
        _reference_arrays(reference)
        cmp = compare(scenario, reference, kind)
        return CalibrationResult(
            scenario=scenario, params=(), values={}, initial={}, bounds={}, comparison=cmp,
            cost=0.5 * float(np.sum(cmp.residuals() ** 2)), nfev=1, success=True, message="nothing fitted",
        )  # fmt: skip
    names = _check_names(params)
    w, _, _ = _reference_arrays(reference, min_omegas=2)
    if 2 * len(w) < len(names):
        raise ValueError(
            f"{len(names)} parameters need at least {len(names)} residuals, got {2 * len(w)} (2 per omega)"
        )
    bnd = {p: tuple(float(b) for b in (bounds or {}).get(p, PARAMETERS[p].bounds)) for p in names}
    for p, (lo, hi) in bnd.items():
        if not (math.isfinite(lo) and math.isfinite(hi) and lo < hi):
            raise ValueError(f"bounds of {p} must be finite with low < high, got {(lo, hi)}")
    x0 = {p: (PARAMETERS[p].start_when_off if v == 0.0 and PARAMETERS[p].start_when_off is not None else v)
          for p, v in parameter_values(scenario, names).items()}  # fmt: skip
    x0 |= {p: float(v) for p, v in (initial or {}).items() if p in names}
    unknown = set(initial or {}) - set(names)
    if unknown:
        raise ValueError(f"initial values given for parameters that are not fitted: {sorted(unknown)}")
    if not all(math.isfinite(v) for v in x0.values()):
        raise ValueError(f"initial values must be finite, got {x0}")
    start = np.array([min(max(x0[p], bnd[p][0]), bnd[p][1]) for p in names])
    if starts < 1:
        raise ValueError(f"starts must be >= 1, got {starts!r}")
    lo, hi = np.array([bnd[p][0] for p in names]), np.array([bnd[p][1] for p in names])
    points = [start]
    if starts > 1:
        points += list(lo + (hi - lo) * qmc.Halton(len(names), seed=seed).random(starts - 1))
    tasks = [(scenario, reference, names, kind, x, lo, hi, diff_step, max_nfev) for x in points]
    if parallel:
        fits = dask_map(_local_fit, tasks, scheduler_address=scheduler_address, n_workers=n_workers, progress=False)
    else:
        fits = [_local_fit(*t) for t in tasks]
    fit = min(fits, key=lambda f: f.cost)
    values = dict(zip(names, (float(v) for v in fit.x)))
    local = [{"start": dict(zip(names, map(float, x))), "values": dict(zip(names, map(float, f.x))), "cost": float(f.cost)}
             for x, f in zip(points, fits)]  # fmt: skip
    return CalibrationResult(
        scenario=with_parameters(scenario, values), params=names, values=values,
        initial=dict(zip(names, (float(v) for v in start))), bounds=bnd, comparison=fit.comparison,
        cost=float(fit.cost), nfev=len(set().union(*(f.evaluated for f in fits))), success=bool(fit.success),
        message=str(fit.message), meta={"local_fits": local} if starts > 1 else {}, jacobian=fit.jacobian,
    )  # fmt: skip


@dataclass(frozen=True)
class _LocalFit:
    """One local least-squares fit of :func:`calibrate` (a task of its own: picklable)."""

    x: np.ndarray
    cost: float
    success: bool
    message: str
    comparison: Comparison  # at x
    evaluated: frozenset  # the parameter sets it evaluated
    jacobian: np.ndarray  # d residuals / d x at x


def _local_fit(
    scenario: LocomotorScenario, reference: SweepResult, names: tuple[str, ...], kind: str, x0: np.ndarray,
    lo: np.ndarray, hi: np.ndarray, diff_step: float, max_nfev: int,
) -> _LocalFit:  # fmt: skip
    """scipy's least_squares of the relative v and sinkage errors from ``x0``, each parameter set evaluated once."""
    cache: dict[tuple[float, ...], Comparison] = {}

    def evaluate(x: np.ndarray) -> Comparison:
        key = tuple(float(v) for v in x)
        if key not in cache:
            cache[key] = compare(with_parameters(scenario, dict(zip(names, key))), reference, kind)
        return cache[key]

    f = least_squares(
        lambda x: evaluate(x).residuals(), x0, bounds=(lo, hi), diff_step=diff_step, x_scale="jac", max_nfev=max_nfev
    )
    return _LocalFit(
        f.x, float(f.cost), bool(f.success), str(f.message), evaluate(f.x), frozenset(cache), np.asarray(f.jac)
    )


@dataclass(frozen=True)
class LeaveOneOut:
    """Cross-validation of a calibration: each reference omega predicted by a fit without it.

    Attributes
    ----------
    comparison : the held-out predictions against the reference (per-omega relative errors).
    values : the fitted values of each fold (fold i leaves out ``comparison.omega_rpm[i]``).
    """

    comparison: Comparison
    values: list[dict[str, float]]

    def summary(self) -> dict[str, Any]:
        return {"comparison": self.comparison.summary(), "fold_values": self.values}


def leave_one_out(
    scenario: LocomotorScenario,
    reference: SweepResult,
    params: Sequence[str] = ("xi", "psi"),
    *,
    kind: str = "drft",
    progress: Callable[[str], None] | None = None,
    parallel: bool = False,
    n_workers: int | None = None,
    scheduler_address: str | None = None,
    **fit_options: Any,
) -> LeaveOneOut:
    """Refit ``params`` without each reference omega in turn and predict that omega.

    A calibration's errors at the points it was fitted on say how well it fits; the errors of
    these held-out predictions say how well it predicts an omega it has not seen.
    ``fit_options`` go to :func:`calibrate` (starts, bounds, ...). Needs at least 3 omegas and
    2 (N - 1) >= the number of parameters. ``parallel``: the N folds run on a Dask cluster
    (:func:`intrusim.analysis.sweep.dask_map`: ``n_workers`` local processes, or the cluster at
    ``scheduler_address``); the same numbers as in series. ``progress`` gets one line per fold.
    """
    w, v, s = _reference_arrays(reference)
    if len(w) < 3:
        raise ValueError(f"leave-one-out needs at least 3 reference omegas, got {len(w)}")
    folds = [
        (scenario, SweepResult(reference.scenario, reference.kind, reference.lam,
                               [r for j, r in enumerate(reference.records) if j != i], meta=reference.meta),
         tuple(params), kind, float(w[i]), fit_options)
        for i in range(len(w))
    ]  # fmt: skip
    if parallel:  # the lines come when all folds are done (a progress bar meanwhile)
        results = dask_map(_fold, folds, scheduler_address=scheduler_address, n_workers=n_workers,
                           progress=progress is not None, desc="leave-one-out folds")  # fmt: skip
        for i, (values, _, _) in enumerate(results):
            _fold_line(progress, i, w, values)
    else:
        results = []
        for i, args in enumerate(folds):
            results.append(_fold(*args))
            _fold_line(progress, i, w, results[-1][0])
    v_pred = np.array([r[1] for r in results])
    s_pred = np.array([r[2] for r in results])
    return LeaveOneOut(Comparison(scenario.name, w, v, s, v_pred, s_pred), [r[0] for r in results])


def _fold(
    scenario: LocomotorScenario, rest: SweepResult, params: Sequence[str], kind: str, omega_rpm: float,
    fit_options: Mapping[str, Any],
) -> tuple[dict[str, float], float, float]:  # fmt: skip
    """One leave-one-out fold: fit on ``rest``, predict ``omega_rpm``; (values, v m/s, sinkage m)."""
    fit = calibrate(scenario, rest, params, kind=kind, **fit_options)
    held = drft_steady_states(fit.scenario, [omega_rpm], kind)
    return fit.values, float(held.column("velocity")[0]), float(held.column("sinkage")[0])


def _fold_line(progress: Callable[[str], None] | None, i: int, w: np.ndarray, values: Mapping[str, float]) -> None:
    if progress is not None:
        progress(
            f"fold {i + 1}/{len(w)}: without {w[i]:g} RPM, {', '.join(f'{p} = {x:.4g}' for p, x in values.items())}"
        )
