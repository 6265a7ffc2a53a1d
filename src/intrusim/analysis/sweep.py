"""Sweeps of a locomotion scenario over omega, serial or on a Dask cluster.

Each point is an independent :func:`intrusim.analysis.steady.run_steady`. By default the points
run in parallel on a local Dask ``distributed`` cluster (processes, one worker per core); pass
``scheduler_address`` to use an existing cluster, or ``parallel=False`` for a plain loop (used by
the tests). A point that fails (bad input, integrator failure, no contact) becomes an error record;
every other point is still returned.

Progress: a bar of the points done; an MPM sweep (kind "mpm") prints instead each run's own
progress (:class:`RunProgress`: the simulated time reached, the speed, an ETA; one line every few
seconds a run) and a line as each run ends, on stderr, from whichever process runs it.
"""

from __future__ import annotations

import csv
import math
import os
import sys
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable, Sequence

import numpy as np

from intrusim._checks import InputError
from intrusim.analysis.steady import run_steady
from intrusim.errors import PROGRAMMING_ERRORS

TEXT_FIELDS = ("error", "retried", "outcome")  # the CSV columns read back as text
FIELDS = ("omega_rpm", "ok", "velocity", "sinkage", "slip", "velocity_std", "sinkage_std", "drift", "settled", "error")

# The CSV column of a record key, SI with the unit in its name (docs/getting-started.md, "CSV files"),
# and the factor from the record's value to the column's: the records keep |omega| (rad/s, forward
# rolling), the file omega_rad_s the package's sign (counter-clockwise: < 0 rolling forward).
# A key not named here (omega_rpm, ok, slip, drift, settled, steps, error, retried, a caller's own
# column) is written under its own name.
CSV_COLUMNS: dict[str, tuple[str, float]] = {
    "omega": ("omega_rad_s", -1.0),
    "velocity": ("velocity_m_s", 1.0),
    "sinkage": ("sinkage_m", 1.0),
    "velocity_std": ("velocity_std_m_s", 1.0),
    "sinkage_std": ("sinkage_std_m", 1.0),
    "velocity_z": ("velocity_z_m_s", 1.0),
    "surface_drop": ("surface_drop_m", 1.0),
    "surface_drop_std": ("surface_drop_std_m", 1.0),
    "wall_time": ("wall_time_s", 1.0),
    "window_start": ("window_start_s", 1.0),
    "window_end": ("window_end_s", 1.0),
    "sinkage_rate": ("sinkage_rate_m_s", 1.0),
    "acceleration": ("acceleration_m_s2", 1.0),
    "settle_window": ("settle_window_s", 1.0),
}
RECORD_KEYS: dict[str, tuple[str, float]] = {col: (key, f) for key, (col, f) in CSV_COLUMNS.items()}
# the standard columns of a sweep CSV, in order (then any other, by name)
CSV_FIELDS = ("omega_rpm", "omega_rad_s", "ok", "velocity_m_s", "sinkage_m", "slip", "velocity_std_m_s",
              "sinkage_std_m", "drift", "settled", "error")  # fmt: skip

MAX_POINTS = 10_000  # omegas of one sweep


def omega_list(text: str) -> list[float]:
    """'10,30,90' or 'start:stop:step' (inclusive stop) -> RPM list of finite numbers."""
    try:
        if ":" in text:
            a, b, c = (float(x) for x in text.split(":"))
            if not all(math.isfinite(x) for x in (a, b, c)) or c <= 0 or b < a:
                raise InputError(
                    f"omega range start:stop:step needs finite numbers, step > 0 and stop >= start, got {text!r}"
                )
            if (b - a) / c + 1 > MAX_POINTS:
                raise InputError(f"omega range {text!r} has {(b - a) / c + 1:.3g} points, more than {MAX_POINTS}")
            return [float(w) for w in np.arange(a, b + 0.5 * c, c)]
        out = [float(x) for x in text.split(",") if x.strip()]
    except ValueError as err:
        if isinstance(err, InputError):
            raise
        raise InputError(f"omega list must be 'a,b,c' or 'start:stop:step' (RPM), got {text!r}") from None
    if not all(math.isfinite(w) for w in out):
        raise InputError(f"omega list must hold finite numbers, got {text!r}")
    return out


PROGRESS_EVERY = 5.0  # s of wall time between two progress lines of one run


def _duration(seconds: float) -> str:
    if not math.isfinite(seconds):
        return "?"
    if seconds < 100.0:
        return f"{seconds:.0f} s"
    return f"{seconds / 60.0:.0f} min" if seconds < 6000.0 else f"{seconds / 3600.0:.1f} h"


class RunProgress:
    """One run's progress lines on stderr: the ``progress`` callable of
    :func:`~intrusim.scenarios.mpm_locomotion.run_mpm_steady` (it gets t, x, z, vx and wall, the
    run's wall time, at each chunk's end), e.g. ``grousered_wheel 30 RPM: t 0.45/1.20 s, v 0.120 m/s,
    wall 35 s, ETA 58 s``, the first report and then at most one line every ``every`` seconds.

    The ETA is the simulated time left at the rate since the first report (the solver's start-up
    and compile come before it), or at the mean rate at the first. Picklable: it travels with its
    point to a worker process, which prints it (a local cluster's workers write to this terminal).
    """

    def __init__(self, label: str, t_max: float, every: float = PROGRESS_EVERY) -> None:
        self.label, self.t_max, self.every = label, float(t_max), float(every)
        self._first: tuple[float, float] | None = None  # (t, wall) at the first report
        self._shown = -math.inf  # wall time of the last line

    def eta(self, t: float, wall: float) -> float:
        """Seconds of wall time left to ``t_max`` at simulated time ``t`` and wall time ``wall``."""
        t0, w0 = self._first or (t, wall)
        rate = (wall - w0) / (t - t0) if t > t0 else wall / t if t > 0.0 else math.nan
        return max(0.0, self.t_max - t) * rate

    def line(self, t: float, wall: float, vx: float) -> str:
        return (
            f"{self.label}: t {t:.2f}/{self.t_max:.2f} s, v {vx:.3f} m/s, wall {_duration(wall)}, "
            f"ETA {_duration(self.eta(t, wall))}"
        )

    def say(self, text: str) -> None:
        print(f"{self.label}: {text}", file=sys.stderr, flush=True)

    def __call__(self, d: dict[str, float]) -> None:
        t, wall = float(d["t"]), float(d["wall"])
        if self._first is None:
            self._first = (t, wall)
        elif wall - self._shown < self.every:
            return
        self._shown = wall
        print(self.line(t, wall, float(d.get("vx", math.nan))), file=sys.stderr, flush=True)


def run_progress(scenario: Any, kind: str, omega_rpm: float) -> RunProgress | None:
    """The :class:`RunProgress` of one point of an MPM case (kind "mpm", an
    :class:`~intrusim.scenarios.mpm_locomotion.MPMLocomotion`); None for other models (a point of
    theirs takes seconds)."""
    mpm = getattr(scenario, "mpm", None)
    if kind != "mpm" or mpm is None:
        return None
    name = getattr(getattr(scenario, "scenario", None), "name", scenario.name)
    return RunProgress(f"{name} {omega_rpm:g} RPM", mpm.t_max)


def sweep_point(
    scenario: Any, kind: str, omega_rpm: float, lam: float | None, progress: RunProgress | None = None
) -> dict[str, Any]:
    """One steady state as a flat record; failures of the point (bad input, a guard, no contact, a
    full disk) are caught and described; a programming error (:data:`~intrusim.errors.PROGRAMMING_ERRORS`)
    is raised, never turned into a data row. ``progress``: the run's progress lines (an MPM case)."""
    rec: dict[str, Any] = {"omega_rpm": omega_rpm, "ok": False, "error": ""}
    try:
        # a scenario may carry its own runner (MPMLocomotion: the continuum solver)
        runner = getattr(scenario, "run_steady", None)
        if progress is not None and kind == "mpm":
            st = scenario.run_steady(kind, omega_rpm, lam, progress=progress)
        elif runner is not None:
            st = runner(kind, omega_rpm, lam)
        else:
            st = run_steady(scenario, kind, omega_rpm, lam)
    except Exception as err:  # noqa: BLE001 - one bad point must not sink the sweep
        if isinstance(err, PROGRAMMING_ERRORS):
            raise
        rec["error"] = f"{type(err).__name__}: {err}"
        return rec
    return steady_record(omega_rpm, st)


def steady_record(omega_rpm: float, st: Any) -> dict[str, Any]:
    """A finished steady state (its ``summary()`` and ``settled``) as a flat sweep record; a point
    that needed a finer step (``meta["retried"]``, :func:`~intrusim.analysis.steady.run_steady`)
    says so in a ``retried`` column."""
    rec = {"omega_rpm": omega_rpm, "ok": True, "error": "", **st.summary(), "settled": bool(st.settled)}
    retried = getattr(st, "meta", {}).get("retried")
    return {**rec, "retried": retried} if retried else rec


@dataclass(frozen=True)
class SweepResult:
    """Records of an omega sweep, in the order of the requested omegas.

    ``records[i]`` has keys :data:`FIELDS` (SI: velocity m/s, sinkage m, slip 1); failed points
    have ok = False, NaN numbers and an ``error`` message. In a CSV (:meth:`to_csv`) each column
    names its unit: ``velocity_m_s``, ``sinkage_m``, ``omega_rad_s`` (< 0 rolling forward) ...
    """

    scenario: str
    kind: str
    lam: float | None
    records: list[dict[str, Any]]
    meta: dict[str, Any] = field(default_factory=dict)

    def column(self, name: str) -> np.ndarray:
        """The records' ``name`` (a record key, or its CSV column: ``velocity_m_s`` is ``velocity``),
        NaN where a point failed or has none."""
        key, factor = RECORD_KEYS.get(name, (name, 1.0))
        return factor * np.array([r.get(key, math.nan) if r["ok"] else math.nan for r in self.records], float)

    @property
    def omega_rpm(self) -> np.ndarray:
        return np.array([r["omega_rpm"] for r in self.records], float)

    @property
    def errors(self) -> list[dict[str, Any]]:
        return [r for r in self.records if not r["ok"]]

    def table(self) -> str:
        """A short fixed-width table (mm, m/s, RPM)."""
        lines = [f"{'omega RPM':>9} | {'v m/s':>8} | {'sinkage mm':>10} | {'slip':>6} | note"]
        for r in self.records:
            if r["ok"]:
                note = ", ".join(
                    n
                    for n, on in (("not settled", not r.get("settled", True)), ("finer step", bool(r.get("retried"))))
                    if on
                )
                lines.append(
                    f"{r['omega_rpm']:9.4g} | {r['velocity']:8.4f} | {r['sinkage'] * 1e3:10.2f} | {r['slip']:6.3f} | {note}"
                )
            else:
                lines.append(f"{r['omega_rpm']:9.4g} | {'-':>8} | {'-':>10} | {'-':>6} | ERROR {r['error']}")
        return "\n".join(lines)

    def to_csv(self, path: str | Path) -> Path:
        """Write the records: the standard :data:`CSV_FIELDS` first, then any model-specific ones (e.g.
        MPM's rear surface drop and wall time), each in SI with its unit in its name (:data:`CSV_COLUMNS`)."""
        import io

        from intrusim.mpm.io import atomic_write_bytes

        p = Path(path)
        rows = [_csv_row(r) for r in self.records]
        names = list(CSV_FIELDS) + sorted({k for r in rows for k in r} - set(CSV_FIELDS))
        buf = io.StringIO(newline="")
        w = csv.DictWriter(buf, fieldnames=names, extrasaction="ignore")
        w.writeheader()
        for r in rows:
            w.writerow({k: r.get(k, "") for k in names})
        p.parent.mkdir(parents=True, exist_ok=True)
        atomic_write_bytes(p, buf.getvalue().encode())  # a killed sweep leaves the old CSV or the new one
        return p

    @classmethod
    def from_csv(cls, path: str | Path, scenario: str = "", kind: str = "") -> "SweepResult":
        """Read records written by :meth:`to_csv` (e.g. ``runs/mpm/*_mpm_sweep.csv``), with the unit in
        each column's name or (files written before: ``velocity``, ``sinkage``, ``omega`` > 0 ...) without.

        The records have the keys they always had (``velocity`` m/s, ``sinkage`` m, ``omega`` = |omega|
        rad/s: :data:`CSV_COLUMNS`). ``ok`` and ``settled`` become booleans, ``error`` and ``retried`` stay
        text, every other column a float (an empty cell: NaN). Rows keep the file's order. Raises
        InputError if the file is missing or has no ``omega_rpm`` / ``ok`` column.
        """
        p = Path(path)
        if not p.is_file():
            raise InputError(f"sweep CSV not found: {p}")
        with p.open(newline="") as f:
            rows = list(csv.DictReader(f))
        if not rows or not {"omega_rpm", "ok"} <= set(rows[0]):
            raise InputError(f"{p}: not a sweep CSV (needs the columns omega_rpm and ok, and at least one row)")
        records = []
        for row in rows:
            rec: dict[str, Any] = {}
            for k, v in row.items():
                key, factor = RECORD_KEYS.get(k, (k, 1.0))
                if key in ("ok", "settled"):
                    rec[key] = v.strip().lower() in ("true", "1", "1.0")
                elif key in TEXT_FIELDS:
                    rec[key] = v
                else:
                    rec[key] = factor * float(v) if v.strip() else math.nan
            records.append(rec)
        return cls(scenario, kind, None, records, meta={"source": str(p)})


def _csv_row(rec: dict[str, Any]) -> dict[str, Any]:
    """A record under its CSV column names, in SI (:data:`CSV_COLUMNS`)."""
    out: dict[str, Any] = {}
    for k, v in rec.items():
        col, factor = CSV_COLUMNS.get(k, (k, 1.0))
        out[col] = factor * v if factor != 1.0 and isinstance(v, (int, float)) else v
    return out


def dask_map(
    fn: Callable[..., Any], args: Sequence[tuple], *, scheduler_address: str | None = None, n_workers: int | None = None,
    progress: bool = True, desc: str = "tasks", on_error: Callable[[int, Exception], Any] | None = None,
    on_done: Callable[[int, Any], None] | None = None,
) -> list[Any]:  # fmt: skip
    """``[fn(*a) for a in args]`` on a Dask cluster, in the order of ``args``.

    None for ``scheduler_address`` starts a LocalCluster of ``n_workers`` processes (default: one
    per core, one thread each) for this call. A task whose result cannot be had (an exception in
    ``fn``, a lost worker) raises, or becomes ``on_error(i, err)`` when that is given.
    ``on_done(i, result)`` is called as each task ends (in the order they end).
    """
    from dask.distributed import Client, LocalCluster, as_completed

    cluster = None
    if scheduler_address is None:
        cluster = LocalCluster(
            n_workers=n_workers or os.cpu_count() or 1, threads_per_worker=1, processes=True, dashboard_address=":0"
        )
        client = Client(cluster)
    else:
        client = Client(scheduler_address)
    try:
        futures = [client.submit(fn, *a, pure=False) for a in args]
        index = {f.key: i for i, f in enumerate(futures)}
        out: list[Any] = [None] * len(futures)
        bar = _bar(len(futures), progress, desc)
        for fut in as_completed(futures):
            i = index[fut.key]
            try:
                out[i] = fut.result()
            except Exception as err:  # noqa: BLE001 - worker lost, unpicklable result...
                if on_error is None:
                    raise
                out[i] = on_error(i, err)
            if on_done is not None:
                on_done(i, out[i])
            bar.update(1)
        bar.close()
        return out
    finally:
        client.close()
        if cluster is not None:
            cluster.close()


def _bar(total: int, enabled: bool, desc: str = "omega sweep") -> Any:
    from tqdm import tqdm

    return tqdm(total=total, disable=not enabled, desc=desc, leave=False)


def _error_record(omega_rpm: float, err: Exception) -> dict[str, Any]:
    """A point whose task failed on the cluster (a lost worker, a failure of the point) as an error
    record; a programming error is raised."""
    if isinstance(err, PROGRAMMING_ERRORS):
        raise err
    return {"omega_rpm": omega_rpm, "ok": False, "error": f"{type(err).__name__}: {err}"}


def _done_line(rec: dict[str, Any], done: int, total: int) -> str:
    """A finished point of an MPM sweep, as :class:`RunProgress` labels it has ended."""
    if not rec["ok"]:
        return f"FAILED ({done} of {total} done): {rec['error']}"
    wall = f", wall {_duration(rec['wall_time'])}" if "wall_time" in rec else ""
    return (
        f"done ({done} of {total}): v {rec['velocity']:.4f} m/s, sinkage {rec['sinkage'] * 1e3:.2f} mm, "
        f"slip {rec['slip']:.3f}{wall}{'' if rec.get('settled', True) else ', NOT settled'}"
    )


def sweep_omega(
    scenario: Any,
    kind: str,
    omega_rpm: Sequence[float],
    *,
    lam: float | None = None,
    parallel: bool = True,
    scheduler_address: str | None = None,
    n_workers: int | None = None,
    progress: bool = True,
) -> SweepResult:
    """Steady states of ``scenario`` with force model ``kind`` at each ``omega_rpm`` (RPM).

    Parameters
    ----------
    scenario : LocomotorScenario.
    kind : "rft", "drft-inertial" or "drft" (must be in ``scenario.supported_models``).
    omega_rpm : RPM; a non-positive or non-finite entry gives an error record for that point.
    lam : overrides the scenario's lambda.
    parallel : run on Dask (default) or in a plain loop.
    scheduler_address : address of an existing Dask scheduler (e.g. "tcp://host:8786");
        None starts a LocalCluster of ``n_workers`` processes (default: one per core).
    progress : show a tqdm bar of the points; for an MPM case (kind "mpm") each run's own progress
        lines instead (:class:`RunProgress`) and a line as each run ends, on stderr.
    """
    omegas = [float(w) for w in omega_rpm]
    if not omegas:
        raise InputError("omega_rpm is empty: give at least one angular velocity")
    if kind not in scenario.supported_models:
        raise InputError(f"scenario {scenario.name!r} supports {list(scenario.supported_models)}, got {kind!r}")
    reporters = [run_progress(scenario, kind, w) if progress else None for w in omegas]
    lines = any(r is not None for r in reporters)  # per-run lines, not a bar
    finished = [0]

    def done(i: int, rec: dict[str, Any]) -> None:
        finished[0] += 1
        if reporters[i] is not None:
            reporters[i].say(_done_line(rec, finished[0], len(omegas)))  # type: ignore[union-attr]

    if parallel:
        records = dask_map(
            sweep_point, [(scenario, kind, w, lam, r) for w, r in zip(omegas, reporters)],
            scheduler_address=scheduler_address, n_workers=n_workers, progress=progress and not lines,
            desc="omega sweep", on_error=lambda i, err: _error_record(omegas[i], err), on_done=done if lines else None,
        )  # fmt: skip
    else:
        bar = _bar(len(omegas), progress and not lines)
        records = []
        for i, (w, r) in enumerate(zip(omegas, reporters)):
            records.append(sweep_point(scenario, kind, w, lam, r))
            if lines:
                done(i, records[-1])
            bar.update(1)
        bar.close()
    return SweepResult(scenario.name, kind, lam, records, meta={"parallel": parallel})
