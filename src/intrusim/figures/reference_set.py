"""The MPM reference set a reduced-order model is calibrated and tested on, made by one command
(``intrusim mpm references``).

* omega sweeps of six bodies (:data:`SWEEPS`): the Table S1 wheel and the half-size wheel
  (9 omegas each), the Table S1 wheel with 10 and with 30 grousers and with grousers twice as
  tall (5 omegas each), and the four-flap runner (6 omegas);
* plate drag, Fig 6's 3 depths x 5 speeds (:func:`intrusim.figures.mpm_plates.drag_points`);
* the medium's RFT map alpha(beta, gamma) from MPM plates (:mod:`intrusim.mpm.rft_map`,
  6 orientations x 7 directions).

Every run is kept under the root folder (a finished one is reused, an interrupted locomotion run
resumes from its checkpoint), so the command can be stopped and run again. It writes, in the root,
``NAME_mpm.csv`` per sweep (the table ``intrusim calibrate --mpm`` reads, its runs' settings beside
it), ``plate_drag.csv``, ``alpha_map.csv`` (each column's unit in its name:
:func:`intrusim.mpm.rft_map.alpha_map_row`) and ``references.json`` (what was made, from what
settings, and which points failed). ``quick``: 2 cm cells for the bodies, 5 mm for the plates and
the map, and fewer omegas, speeds and directions: minutes, for a trial or a test.
"""

from __future__ import annotations

import json
import math
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Any, Callable, Sequence

from intrusim._checks import InputError
from intrusim.scenarios import LocomotorScenario

WHEEL_RPM = tuple(float(w) for w in range(10, 91, 10))
VARIANT_RPM = (10.0, 30.0, 50.0, 70.0, 90.0)
RUNNER_RPM = (20.0, 50.0, 100.0, 150.0, 200.0, 300.0)


@dataclass(frozen=True)
class ReferenceSweep:
    """One body's omega sweep of the set: ``omegas`` (RPM), ``quick_omegas`` for a quick set."""

    name: str  # a shipped scenario (intrusim.scenarios.LOCOMOTORS)
    omegas: tuple[float, ...]
    quick_omegas: tuple[float, ...]
    quick_extra_height: float = 0.0  # m added to the quick box's height (same cells), for a taller body

    def scenario(self) -> LocomotorScenario:
        from intrusim.scenarios import get_scenario

        return get_scenario(self.name)  # type: ignore[return-value]

    def settings_items(self, quick: bool) -> list[tuple[str, Any]]:
        """MPM settings over the body's quick or paper ones (``intrusim.figures.mpm.applying_settings``)."""
        if not (quick and self.quick_extra_height):
            return []
        from intrusim.scenarios.mpm_locomotion import quick_settings

        scn = self.scenario()
        base = quick_settings(scn.body, scn.mpm_scale)
        h = base.domain[1] / base.cells[1]
        n = base.cells[1] + math.ceil(self.quick_extra_height / h - 1e-9)
        return [("domain", (base.domain[0], n * h)), ("cells", (base.cells[0], n))]


SWEEPS: tuple[ReferenceSweep, ...] = (
    ReferenceSweep("wheel", WHEEL_RPM, (30.0, 90.0)),
    ReferenceSweep("small-wheel", WHEEL_RPM, (30.0, 90.0)),
    ReferenceSweep("wheel-10-grousers", VARIANT_RPM, (30.0, 90.0)),
    ReferenceSweep("wheel-30-grousers", VARIANT_RPM, (30.0, 90.0)),
    ReferenceSweep("wheel-tall-grousers", VARIANT_RPM, (30.0, 90.0), quick_extra_height=0.06),
    ReferenceSweep("runner", RUNNER_RPM, (60.0, 200.0)),
)
PLATES = ("plate-drag", "alpha-map")
NAMES: tuple[str, ...] = tuple(s.name for s in SWEEPS) + PLATES

MAP_BETAS_DEG = (-60.0, -30.0, 0.0, 30.0, 60.0, 90.0)
MAP_GAMMAS_DEG = (-90.0, -60.0, -30.0, 0.0, 30.0, 60.0, 90.0)
MAP_QUICK_DEG = ((0.0, 90.0), (90.0, 0.0))  # (beta, gamma): pushed down, a vertical plate pushed along -x


def selected(only: Sequence[str] | None) -> list[str]:
    """The parts of the set named in ``only`` (None: all), in the set's order; InputError naming
    an unknown one."""
    if only is None:
        return list(NAMES)
    unknown = [n for n in only if n not in NAMES]
    if unknown or not only:
        raise InputError(f"unknown reference(s) {unknown or list(only)}; choose among {', '.join(NAMES)}")
    return [n for n in NAMES if n in only]


def alpha_map_cases(quick: bool) -> list[Any]:
    """The plates of the RFT map with the MPM's default contact (5 mm cells and two directions when ``quick``)."""
    from intrusim.mpm.rft_map import PlateMapCase, map_cases

    if quick:
        return [PlateMapCase(beta=math.radians(b), gamma=math.radians(g), cell_size=0.005, plate_thickness=0.01)
                for b, g in MAP_QUICK_DEG]  # fmt: skip
    betas, gammas = [math.radians(b) for b in MAP_BETAS_DEG], [math.radians(g) for g in MAP_GAMMAS_DEG]
    return map_cases(betas, gammas)


def _alpha_case(kw: dict[str, Any], path: str) -> dict[str, Any]:
    """One plate of the map, cached in ``path`` (run in a worker process: one thread)."""
    from intrusim.mpm.io import cached_json
    from intrusim.mpm.rft_map import PlateMapCase, case_record, measure_alpha

    case = PlateMapCase(**kw)

    def run() -> dict[str, Any]:
        from intrusim.mpm.solver import Solver

        solver = Solver(case.config(cpu_threads=1))
        return {**case_record(case), **measure_alpha(solver.run(), case), "steps": solver.step_count}

    return cached_json(Path(path), run)


def _write_rows(path: Path, rows: list[dict[str, Any]]) -> Path:
    """``rows`` as a CSV file (the union of their keys as columns), whole or not at all."""
    import csv
    import io

    from intrusim.mpm.io import atomic_write_bytes

    text = io.StringIO()
    w = csv.DictWriter(text, fieldnames=list(dict.fromkeys(k for r in rows for k in r)))
    w.writeheader()
    w.writerows(rows)
    atomic_write_bytes(path, text.getvalue().encode())
    return path


def make_references(
    root: Path, quick: bool = False, only: Sequence[str] | None = None, workers: int | None = None,
    echo: Callable[[str], None] = print,
) -> dict[str, Any]:  # fmt: skip
    """Make (or reuse) every run of the set's parts ``only`` (None: all) under ``root`` and write
    their tables there (module docstring). Returns the index written to ``root/references.json``.
    ``workers``: MPM runs at once, for each sweep's omegas (:func:`intrusim.figures.mpm.mpm_sweep`;
    1: one after another in this process) and for the map's plates (None: one per core).

    A failed point is reported and left out of its table; the others are kept."""
    from intrusim.analysis.sweep import dask_map
    from intrusim.figures.mpm import mpm_sweep_table
    from intrusim.figures.mpm_plates import drag_points

    names = selected(only)
    root = Path(root)
    root.mkdir(parents=True, exist_ok=True)
    index: dict[str, Any] = {"quick": quick, "parts": {}}
    for sweep in SWEEPS:
        if sweep.name not in names:
            continue
        scn = sweep.scenario()
        omegas = sweep.quick_omegas if quick else sweep.omegas
        echo(f"{sweep.name} ({scn.name}): MPM at {', '.join(f'{w:g}' for w in omegas)} RPM")
        csv = root / f"{sweep.name}_mpm.csv"
        res = mpm_sweep_table(scn, omegas, quick, root, sweep.settings_items(quick), csv, workers=workers)
        failed = [float(r["omega_rpm"]) for r in res.records if not r["ok"]]
        index["parts"][sweep.name] = {"scenario": scn.name, "table": csv.name, "omega_rpm": list(omegas),
                                      "failed_omega_rpm": failed}  # fmt: skip
    if "plate-drag" in names:
        echo("plate-drag: Fig 6 drag, 3 depths x " + ("3" if quick else "5") + " speeds")
        pts = drag_points(quick, root / "plates", progress=True)
        index["parts"]["plate-drag"] = {"table": _write_rows(root / "plate_drag.csv", pts).name, "points": len(pts)}
    if "alpha-map" in names:
        from intrusim.mpm.rft_map import alpha_map_row

        cases = alpha_map_cases(quick)
        echo(f"alpha-map: {len(cases)} plates")
        folder = root / "alpha_map"
        args = [(asdict(c), str(folder / f"beta{math.degrees(c.beta):+.0f}_gamma{math.degrees(c.gamma):+.0f}.json"))
                for c in cases]  # fmt: skip
        errors: list[str] = []

        def failed(i: int, err: Exception) -> None:
            errors.append(f"beta {math.degrees(cases[i].beta):.0f} gamma {math.degrees(cases[i].gamma):.0f}: {err}")

        rows = dask_map(_alpha_case, args, n_workers=workers, desc="alpha map", on_error=failed)
        rows = [r for r in rows if r is not None]
        for e in errors:
            echo(f"alpha-map: FAILED {e}")
        table = _write_rows(root / "alpha_map.csv", [alpha_map_row(r) for r in rows])  # the units in the header
        index["parts"]["alpha-map"] = {"table": table.name, "plates": len(rows), "failed": errors}
    from intrusim.mpm.io import atomic_write_bytes

    path = root / "references.json"
    old = json.loads(path.read_text()) if path.is_file() else {}
    if old.get("quick") == quick:  # parts made before, by another --only, are kept in the index
        index["parts"] = {**old.get("parts", {}), **index["parts"]}
    atomic_write_bytes(path, (json.dumps(index, indent=1) + "\n").encode())
    return index
