"""Convergence of the MPM's answers in the time step and the cell size (not in CI).

Each named case is run at cells h, h/2 (h/4 with ``--levels 3``) and at each of them with dt and dt/2
(dt = C h sqrt(rho_c / E), C = 0.3 and 0.15; ``--dt-levels N``: dt/2 only at the N coarsest cells).
Every run's numbers are kept in ``runs/convergence/results.json`` (a run already there is not run
again), and ``--write docs/convergence.md`` rewrites that file's table from every result kept there:
each number, its change per dt halving and per h halving, against the targets (below).

Cases (``--cases``):

* ``collapse``: a 0.1 m square column of the Table S1 material (rho_c 638 kg/m^3, mu_s 0.56,
  E 1 MPa) on a sticky floor against a frictionless wall, 0.6 s (at rest by then): the runout
  (99th percentile of the points' x) and the x of the centre of mass. Base cells 10 mm.
* ``silo``: a flat-bottomed 2D silo 0.3 m wide, filled 0.2 m deep, its floor two static obstacles
  (0.02 m thick, grain friction 0.5) with a central slot of width D = 40, 60, 80 mm (8, 12, 16 cells
  at the base cells, 5 mm); the box's bottom is an open side (outflow), 0.04 m below the floor.
  The discharge rate W (kg/s per m) is the slope of the outflow mass from 0.12 to 0.35 s; the
  exponent b of W ~ D^b is fitted over the widths (target 1.5 +- 0.1).
* ``silo_wide``: the same slots in a silo 0.6 m wide filled 0.4 m deep (the slots 7-15 times
  narrower than the silo, where ``silo``'s are 4-7.5 times; Beverloo's law is for slots much
  narrower than the silo, and the deeper fill drains less of itself in the run).
* ``wheel30``, ``wheel90``: the Table S1 grousered wheel at 30 and 90 RPM
  (``scenarios.mpm_locomotion.run_mpm_steady``, 2 s; window from 0.65 s): v and sinkage.
  Base cells 10 mm (the paper's 5 mm is the second level).
* ``footing``: a rough rigid strip footing (``intrusim.mpm.footing.FootingCase``: B = 0.06 m, the
  Table S1 material, grain-footing friction 5) pushed 0.1 B into the bed at 0.05 m/s: N_gamma =
  q / (0.5 rho_c g B) over settlements s / B 0.02-0.04 and 0.04-0.08. Base cells 6 mm (10 across B).
* ``plate``: plate drag (Fig 6 set-up, ``mpm.plate.PlateDragCase``) at 3 speeds x 3 depths: K and
  lambda of F = K |z| + lambda rho A v^2. Base cells 5 mm (2.5 mm is Fig 6's).

``--flip S`` runs every case with a fixed FLIP share S per step (0: APIC, the former default)
instead of the default transfer, ``--pic-time T`` with ``transfer.pic_time = T`` (not the plate),
``--band B`` with the band contact of ``contact_band_cells = B`` and ``--contact surface`` with the
contact 'surface' (the former default) instead of the default contact 'nodes', each kept under its
own key, for comparison. ``--silo FLOOR WIDTH FILL`` runs the silo with another floor thickness,
width and fill depth (m; 0.02 0.3 0.2 by default), also kept under its own key.

    python benchmarks/convergence.py --cases collapse silo --levels 2 --threads 1 --write docs/convergence.md
"""

from __future__ import annotations

import argparse
import json
import math
import sys
import time
from functools import partial
from pathlib import Path

import numpy as np
from _doc_tables import markers, write_between

ROOT = Path(__file__).resolve().parents[1]
RESULTS = ROOT / "runs" / "convergence" / "results.json"
CFL = (0.3, 0.15)  # dt and dt/2
BAND: float | None = None  # contact_band_cells of the runs (--band); None: the config's default
CONTACT: str | None = None  # MPMConfig.contact of the runs (--contact nodes); None: the config's default


def contact_settings() -> dict:
    """The runs' contact settings (--band, --contact): {} for the default."""
    if BAND is not None:
        return {"contact": "band", "contact_band_cells": BAND}
    return {} if CONTACT is None else {"contact": CONTACT}


PIC_TIME: float | None = None  # transfer.pic_time of the runs (--pic-time); None: the config's default
FLUIDITY: float | None = (
    None  # grain diameter of the nonlocal fluidity (--fluidity; footing, wheels); None: the paper's law
)


def transfer(flip: float | None):
    from intrusim.mpm.config import TransferConfig

    return TransferConfig(flip=flip, **({} if PIC_TIME is None else {"pic_time": PIC_TIME}))


# targets: |change| per dt halving, per h halving between the two finest cells
DT_TARGET = 0.01
H_TARGET = {"plate": 0.05, "wheel30": 0.05, "wheel90": 0.05, "footing": 0.05}
SILO_WIDTHS = (0.04, 0.06, 0.08)  # m
SILO_BASE = (0.02, 0.3, 0.2)  # m: the floor's thickness, the silo's width, the fill's depth
SILO_WIDE = (0.02, 0.6, 0.4)  # the case silo_wide: slots 7-15 times narrower than the silo
SILO: tuple[float, float, float] = SILO_BASE  # of the runs (--silo FLOOR WIDTH FILL)
EXPONENT_TARGET = (1.5, 0.1)


def backend(threads: int) -> dict:
    return {"cpu_threads": threads}


# ---------------------------------------------------------------------------------------------- cases
def collapse(h: float, cfl: float, threads: int, flip: float | None) -> dict[str, float]:
    from intrusim.mpm.config import (
        BedConfig,
        DomainConfig,
        MaterialConfig,
        MPMConfig,
        OutputConfig,
        Rectangle,
        TimeConfig,
    )
    from intrusim.mpm.solver import Solver

    size = (0.5, 0.15)
    cfg = MPMConfig(
        domain=DomainConfig(size=size, cells=(round(size[0] / h), round(size[1] / h))),
        material=MaterialConfig(rho_c=638.0, mu_s=0.56, youngs_modulus=1e6),
        bed=BedConfig(rectangles=[Rectangle(x0=0.0, z0=0.0, x1=0.1, z1=0.1)]),
        time=TimeConfig(t_end=0.6, cfl=cfl),
        transfer=transfer(flip),
        output=OutputConfig(record_every=0.1),
        backend=backend(threads),
    )
    solver = Solver(cfg)
    rows = solver.run()
    d = solver.particle_fields()
    x, m = d["x"][:, 0], d["mass"]
    return {
        "runout_m": float(np.quantile(x, 0.99)),
        "centre_m": float((m * x).sum() / m.sum()),
        "final_ke_J_per_m": rows[-1]["kinetic_energy"],
        "steps": solver.step_count,
        "points": solver.particles.n,
    }


def silo_config(
    h: float, cfl: float, threads: int, flip: float | None, width: float, geometry: tuple[float, float, float]
):
    from intrusim.mpm.config import (
        BedConfig,
        BoundaryConfig,
        DomainConfig,
        MaterialConfig,
        MPMConfig,
        ObstacleConfig,
        OutputConfig,
        Rectangle,
        TimeConfig,
        WallConfig,
    )

    (thick, lx, fill), floor = geometry, 0.04
    lz = floor + fill + 0.06
    a, b = (lx - width) / 2, (lx + width) / 2
    slabs = [
        [(0.0, floor - thick), (a, floor - thick), (a, floor), (0.0, floor)],
        [(b, floor - thick), (lx, floor - thick), (lx, floor), (b, floor)],
    ]
    extra = contact_settings()  # the static obstacles' contact
    return MPMConfig(
        domain=DomainConfig(size=(lx, lz), cells=(round(lx / h), round(lz / h))),
        material=MaterialConfig(rho_c=638.0, mu_s=0.56, youngs_modulus=1e6),
        bed=BedConfig(rectangles=[Rectangle(x0=0.0, z0=floor, x1=lx, z1=floor + fill)]),
        boundaries=BoundaryConfig(floor=WallConfig(kind="open")),
        obstacles=[ObstacleConfig(vertices=s, mu=0.5) for s in slabs],
        time=TimeConfig(t_end=0.35, cfl=cfl, v_max_expected=2.0),
        transfer=transfer(flip),
        output=OutputConfig(record_every=0.01, guard_every_steps=20),
        backend=backend(threads),
        **extra,
    )


def silo(h: float, cfl: float, threads: int, flip: float | None, geometry=None) -> dict[str, float]:
    from intrusim.mpm.solver import Solver

    out: dict[str, float] = {}
    for width in SILO_WIDTHS:
        solver = Solver(silo_config(h, cfl, threads, flip, width, SILO if geometry is None else geometry))
        rows = solver.run()
        t = np.array([r["time"] for r in rows])
        m = np.array([r["outflow_mass"] for r in rows])
        sel = t >= 0.12  # the first grains reach the open bottom at ~0.09 s
        out[f"W_D{width * 1e3:.0f}mm_kg_per_s_m"] = float(np.polyfit(t[sel], m[sel], 1)[0])
        out["steps"] = solver.step_count
    out["exponent_b"] = silo_exponent(out)
    return out


def silo_exponent(values: dict[str, float]) -> float:
    rates = [values[f"W_D{w * 1e3:.0f}mm_kg_per_s_m"] for w in SILO_WIDTHS]
    if min(rates) <= 0:
        return float("nan")
    return float(np.polyfit(np.log(SILO_WIDTHS), np.log(rates), 1)[0])


def wheel(rpm: float):
    def run(h: float, cfl: float, threads: int, flip: float | None) -> dict[str, float]:
        from intrusim.scenarios.locomotor import grousered_wheel_scenario
        from intrusim.scenarios.mpm_locomotion import paper_settings, run_mpm_steady

        base = paper_settings("wheel")
        cells = tuple(round(length / h) for length in base.domain)
        settings = base.validated_copy(
            cells=cells,
            t_max=2.0,
            cpu_threads=threads,
            cfl=cfl,
            flip=flip,
            **contact_settings(),
            **({} if PIC_TIME is None else {"pic_time": PIC_TIME}),
            **({} if FLUIDITY is None else {"fluidity": {"grain_diameter": FLUIDITY}}),
        )
        st = run_mpm_steady(grousered_wheel_scenario(), settings, rpm)
        return {
            "v_m_per_s": st.velocity,
            "sinkage_m": st.sinkage,
            "slip": st.slip,
            "steps": st.steps,
            "v_std_m_per_s": st.velocity_std,
            "drift": st.drift,
        }

    return run


def plate(h: float, cfl: float, threads: int, flip: float | None) -> dict[str, float]:
    from intrusim.figures.mpm_plates import DRAG_DEPTHS, DRAG_SPEEDS_QUICK, PAPER_DRAG
    from intrusim.mpm.plate import PlateDragCase, fit_drag_law, steady_force
    from intrusim.mpm.solver import Solver

    depth, speed, force = [], [], []
    for d in DRAG_DEPTHS:
        for v in DRAG_SPEEDS_QUICK:
            case = PlateDragCase(
                depth=d,
                speed=v,
                travel=0.04,
                cells=(round(0.30 / h), round(0.15 / h)),
                cfl=cfl,
                flip=flip,
                **contact_settings(),
            )
            rows = Solver(case.config(**backend(threads))).run()
            depth.append(d)
            speed.append(v)
            force.append(-steady_force(rows, "fx"))
    K, lam = fit_drag_law(np.array(depth), np.array(speed), np.array(force), PAPER_DRAG["rho"], PAPER_DRAG["length"])
    return {"K_N_per_m": K, "lambda": lam}


FOOTING_WIDTH = 0.06  # m, B of intrusim.mpm.footing.FootingCase
FOOTING_WINDOWS = ((0.02, 0.04), (0.04, 0.08))  # settlement s / B


def footing(h: float, cfl: float, threads: int, flip: float | None) -> dict[str, float]:
    from intrusim.mpm.config import MPMConfig
    from intrusim.mpm.footing import FootingCase, n_gamma_at
    from intrusim.mpm.solver import Solver

    case = FootingCase(
        cells_across=round(FOOTING_WIDTH / h),
        width=FOOTING_WIDTH,
        cfl=cfl,
        **contact_settings(),
    )
    data = case.config(**backend(threads)).model_dump()
    if flip is not None or PIC_TIME is not None:
        data["transfer"] = transfer(flip).model_dump()
    if FLUIDITY is not None:
        data["material"]["fluidity"] = {"grain_diameter": FLUIDITY}
    cfg = MPMConfig.model_validate(data)  # validated as a file is
    solver = Solver(cfg)
    rows = solver.run()
    out = {f"N_gamma_sB_{a:g}_{b:g}": n_gamma_at(case, rows, (a, b)) for a, b in FOOTING_WINDOWS}
    return {**out, "steps": float(solver.step_count), "points": float(solver.particles.n)}


SILO_QUANTITIES = tuple(f"W_D{w * 1e3:.0f}mm_kg_per_s_m" for w in SILO_WIDTHS) + ("exponent_b",)
CASES = {  # name: (run, base cells h in m, the quantities of the table)
    "collapse": (collapse, 0.01, ("runout_m", "centre_m")),
    "silo": (silo, 0.005, SILO_QUANTITIES),
    "silo_wide": (partial(silo, geometry=SILO_WIDE), 0.005, SILO_QUANTITIES),
    "wheel30": (wheel(30.0), 0.01, ("v_m_per_s", "sinkage_m")),
    "wheel90": (wheel(90.0), 0.01, ("v_m_per_s", "sinkage_m")),
    "plate": (plate, 0.005, ("K_N_per_m", "lambda")),
    "footing": (footing, FOOTING_WIDTH / 10, tuple(f"N_gamma_sB_{a:g}_{b:g}" for a, b in FOOTING_WINDOWS)),
}


# ------------------------------------------------------------------------------------------ the runs
def key(case: str, h: float, cfl: float, flip: float | None) -> str:
    variant = ("default" if flip is None else f"flip={flip:g}") + ("" if BAND is None else f"|band={BAND:g}")
    variant += "" if CONTACT is None else f"|contact={CONTACT}"
    variant += "" if PIC_TIME is None else f"|pic_time={PIC_TIME:g}"
    variant += "" if FLUIDITY is None else f"|fluidity={FLUIDITY:g}"
    if case == "silo" and SILO != SILO_BASE:
        variant += "|silo={:g},{:g},{:g}".format(*SILO)
    return f"{case}|h={h * 1e3:g}mm|cfl={cfl:g}|{variant}"


def load() -> dict:
    return json.loads(RESULTS.read_text()) if RESULTS.exists() else {}


def run_cases(cases: list[str], levels: int, dt_levels: int, threads: int, flip: float | None) -> dict:
    results = load()
    for name in cases:
        run, h0, _ = CASES[name]
        for level in range(levels):
            h = h0 / 2**level
            for cfl in CFL[: 2 if level < dt_levels else 1]:
                k = key(name, h, cfl, flip)
                if k in results:
                    continue
                t0 = time.perf_counter()
                values = run(h, cfl, threads, flip)
                values["wall_s"] = time.perf_counter() - t0
                values["threads"] = threads
                print(k, json.dumps({a: round(b, 6) for a, b in values.items()}), flush=True)
                RESULTS.parent.mkdir(parents=True, exist_ok=True)
                results = {**load(), k: values}  # another process may have added runs meanwhile
                RESULTS.write_text(json.dumps(results, indent=1, sort_keys=True))
    return results


# ------------------------------------------------------------------------------------------ the table
def pct(a: float | None, b: float | None) -> str:
    if a is None or b is None or not (math.isfinite(a) and math.isfinite(b)) or a == 0:
        return "-"
    return f"{100 * (b / a - 1):+.2f} %"


def fmt(v: float | None) -> str:
    return "not run" if v is None else f"{v:.5g}"


def verdict(name: str, quantity: str, dt_change: float | None, h_change: float | None, value: float | None) -> str:
    parts = []
    if dt_change is not None:
        parts.append("dt: " + ("met" if abs(dt_change) < DT_TARGET else "NOT met"))
    if quantity == "exponent_b" and value is not None:
        b0, tol = EXPONENT_TARGET
        parts.append("b: " + ("met" if abs(value - b0) <= tol else "NOT met"))
    if name in H_TARGET and h_change is not None:
        parts.append("h: " + ("met" if abs(h_change) < H_TARGET[name] else "NOT met"))
    return ", ".join(parts) or "-"


def cell_sizes(results: dict, name: str, variant: str) -> list[float]:
    """The cell sizes (mm) at which case ``name`` has results of ``variant``, coarsest first."""
    hs = {float(k.split("|")[1][2:-2]) for k in results if k.startswith(name + "|") and k.split("|", 3)[3] == variant}
    return sorted(hs, reverse=True)


def table(results: dict, variant: str, every_case: bool = True) -> list[str]:
    """The rows of ``variant``'s runs; ``every_case``: a "not run" row for each case without any."""
    lines = [
        "| case | quantity | h (mm) | at dt | at dt/2 | per dt halving | per h halving (at dt) | target |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for name, (_, h0, quantities) in CASES.items():
        hs = cell_sizes(results, name, variant)
        if not hs and not every_case:
            continue
        if not hs:
            lines.append(f"| {name} | {', '.join(quantities)} | - | not run | not run | - | - | - |")
            continue
        for q in quantities:
            prev = None
            for h_mm in hs:
                a, b = (results.get(f"{name}|h={h_mm:g}mm|cfl={cfl:g}|{variant}", {}).get(q) for cfl in CFL)
                dt_change = None if a is None or b is None else b / a - 1
                h_change = None if a is None or prev is None else a / prev - 1
                lines.append(
                    f"| {name} | {q} | {h_mm:g} | {fmt(a)} | {fmt(b)} | {pct(a, b)} | {pct(prev, a)} | "
                    f"{verdict(name, q, dt_change, h_change, a)} |"
                )
                prev = a
    return lines


TITLES = {
    "default": "The defaults: FLIP with a PIC share per step exp(-dt / tau), the contact 'nodes' (the grid nodes "
    "inside the body projected, the points at its surface corrected)",
    "default|fluidity=0.003": "The defaults with the nonlocal granular fluidity, 3 mm grains, in place of the paper's law "
    "(`--fluidity 3e-3`)",
    "default|contact=surface": "The default transfer with the contact 'surface' (`--contact surface`, the former "
    "default: the points at the body's surface enforced on the grid by 8 projected Gauss-Seidel half steps)",
    "default|contact=surface|fluidity=0.003": "The contact 'surface' with the nonlocal granular fluidity, 3 mm grains, "
    "in place of the paper's law (`--contact surface --fluidity 3e-3`)",
    "default|band=1": "The default transfer with the 1-cell contact band (`--band 1`, the default contact before 'surface')",
    "default|contact=surface|grid_relax=0": "The contact 'surface' but its grid part with the plain impulse m_p dv per "
    "point and sweep (8 sweeps; a design tried, not kept)",
    "default|contact=surface|grid_relax=1": "The contact 'surface' but its grid part with full projected Gauss-Seidel "
    "steps, m_p dv / S_p (a design tried, not kept)",
    "flip=0|band=1": "APIC (`transfer.flip = 0`) with the 1-cell contact band: the former defaults",
    "flip=1|band=1": "FLIP (`transfer.flip = 1`) with the 1-cell contact band",
}


def write_doc(path: Path, results: dict) -> None:
    """Replace the generated tables of ``path`` (between the markers) with the current ones."""
    variants = sorted({k.split("|", 3)[3] for k in results}, key=lambda v: (v != "default", v))
    body: list[str] = []
    for v in variants:
        title = TITLES.get(
            v,
            f"`{v}` ("
            + ", ".join(
                "APIC"
                if p == "flip=0"
                else "contact band " + p[5:]
                if p.startswith("band=")
                else "the default transfer"
                if p == "default"
                else p
                for p in v.split("|")
            )
            + ")",
        )
        body += ["", f"{title}:", ""] + table(results, v, every_case=v == "default")
    body += [""]
    if not path.exists():
        begin, end = markers("convergence table")
        path.write_text(f"# Convergence\n\n{begin}\n{end}\n")
    write_between(path, "convergence table", body)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--cases", nargs="+", default=["collapse", "silo"], choices=sorted(CASES))
    ap.add_argument("--levels", type=int, default=2, help="cell sizes: h, h/2 (, h/4 with 3)")
    ap.add_argument(
        "--dt-levels", type=int, default=None, help="run dt/2 at this many of the coarsest cells (default all)"
    )
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument(
        "--flip", type=float, default=None, help="a fixed FLIP share per step (0: APIC) instead of the default"
    )
    ap.add_argument(
        "--band",
        type=float,
        default=None,
        help="the band contact with this contact_band_cells for every body and obstacle (default: the config's contact, 'nodes')",
    )
    ap.add_argument(
        "--contact",
        choices=["nodes", "surface"],
        default=None,
        help="the contact of every body and obstacle (default: the config's, 'nodes'); 'surface': the points at "
        "the body's surface enforced on the grid by sweeps (the former default)",
    )
    ap.add_argument(
        "--pic-time",
        type=float,
        default=None,
        help="transfer.pic_time of the default transfer (collapse, silo, wheels; default: the config's)",
    )
    ap.add_argument(
        "--fluidity",
        type=float,
        default=None,
        help="the nonlocal granular fluidity with this grain diameter (m) in place of the paper's law (footing, wheels)",
    )
    ap.add_argument(
        "--silo",
        type=float,
        nargs=3,
        default=list(SILO_BASE),
        metavar=("FLOOR", "WIDTH", "FILL"),
        help="the silo's floor thickness, width and fill depth, m (default 0.02 0.3 0.2)",
    )
    ap.add_argument("--write", type=Path, default=None, help="rewrite this markdown file's table (docs/convergence.md)")
    args = ap.parse_args()
    if (
        args.levels < 1
        or args.threads < 1
        or (args.flip is not None and not 0 <= args.flip <= 1)
        or (args.band is not None and args.band < 0)
    ):
        sys.exit("need --levels >= 1, --threads >= 1, 0 <= --flip <= 1 and --band >= 0")
    global BAND, PIC_TIME, FLUIDITY, CONTACT, SILO
    SILO = tuple(args.silo)  # type: ignore[assignment]
    thick, width, fill = SILO
    if not (0 < thick < 0.04 and width > 2 * max(SILO_WIDTHS) and fill > 0):
        sys.exit("--silo needs 0 < FLOOR < 0.04 (the gap below it), WIDTH > 2 x the widest slot and FILL > 0")
    BAND, PIC_TIME, FLUIDITY, CONTACT = args.band, args.pic_time, args.fluidity, args.contact
    if BAND is not None and CONTACT is not None:
        sys.exit("--band and --contact: one contact at a time")
    if FLUIDITY is not None and (not set(args.cases) <= {"footing", "wheel30", "wheel90"} or not FLUIDITY > 0):
        sys.exit("--fluidity D needs D > 0 and --cases among footing, wheel30, wheel90")
    results = run_cases(
        args.cases, args.levels, args.levels if args.dt_levels is None else args.dt_levels, args.threads, args.flip
    )
    variant = key("silo" if SILO != SILO_BASE else "", 0.0, 0.0, args.flip).split("|", 3)[3]
    print("\n".join(table(results, variant, every_case=SILO == SILO_BASE)))
    if args.write is not None:
        write_doc(args.write, results)


if __name__ == "__main__":
    main()
