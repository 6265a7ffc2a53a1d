"""DRFT's xi as a function of the grain length d / r, and its transfer to another wheel (an extension).

The nonlocal-law MPM wheel's steady state depends on d / r (research/notes/results_log.md, "grain length"): on the
resolved grid (2.5 mm cells) the large wheel with 12 mm grains and the half-size wheel with 6 mm
grains (both d / r 0.113) are one non-dimensional state. DRFT has no length, so a xi fitted on one
wheel carries to a wheel of another size in the same sand only as far as their d / r agree. This
script fits xi (``intrusim calibrate ... --params xi``, the MPM's forward push) on each ``--fit``
sweep (8 starts, as the CLI), fits the law xi = xi_ref (d / r / q_ref)^p through them
(:mod:`helpers.grain_length`), and checks each ``--check`` sweep with the law's xi at its
own d / r against DRFT without a length (the first fit's xi for every wheel)::

    python research/xi_grain_length.py \\
        --fit wheel research/outputs/mpm_nonlocal/grousered_wheel_mpm_sweep.csv 6e-3 \\
        --fit wheel research/outputs/mpm_nonlocal_d12/grousered_wheel_mpm_sweep.csv 12e-3 \\
        --check small-wheel research/outputs/mpm_nonlocal_fine_all/small_grousered_wheel_mpm_sweep.csv 6e-3 \\
        --check wheel research/outputs/mpm_nonlocal_blind_all/grousered_wheel_mpm_sweep.csv 6e-3 \\
        --out research/outputs/xi_grain_length                                                  # ~40 s

``--fit`` and ``--check`` take a scenario (``wheel``, ``small-wheel`` or a .toml), an MPM sweep CSV
(``research/steady_to_sweep.py``) and the run's grain diameter d (m); d / r uses the scenario's
radius. Writes OUT.csv (one row per check point: MPM, DRFT with the law, DRFT without a length),
OUT.json (the fits, the law, the checks' largest errors) and OUT.png.
"""

from __future__ import annotations

import argparse
import json
import math
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from helpers.grain_length import XiLengthLaw, d_over_r, fit_xi_length_law  # noqa: E402

from intrusim._checks import InputError  # noqa: E402
from intrusim.analysis.calibration import calibrate, compare, load_reference, with_mpm_push, with_parameters  # noqa: E402
from intrusim.mpm.io import write_csv  # noqa: E402
from intrusim.params import GRAVITY, RPM  # noqa: E402
from intrusim.scenarios import load_scenario  # noqa: E402

TARGET = 0.15  # the "within 15 %"
STARTS = 8  # local fits per calibration, as `intrusim calibrate` (its cost has several local minima)


def _set(spec: list[str], what: str) -> tuple[str, Path, float]:
    scenario, path, d = spec
    if not Path(path).is_file():
        raise InputError(f"{what}: no such sweep CSV: {path}")
    try:
        dv = float(d)
    except ValueError:
        raise InputError(f"{what}: the grain diameter must be a number (m), got {d!r}") from None
    if not (math.isfinite(dv) and 0.0 < dv < 0.1):
        raise InputError(f"{what}: the grain diameter must be in (0, 0.1) m, got {d!r}")
    return scenario, Path(path), dv


def fit_points(fits: list[tuple[str, Path, float]]) -> list[dict]:
    """xi calibrated on each sweep (the MPM's push), with its d / r and the fit's errors."""
    out = []
    for name, path, d in fits:
        sc = with_mpm_push(load_scenario(name))
        res = calibrate(sc, load_reference(path), ("xi",), starts=STARTS)
        c = res.comparison
        out.append({"scenario": sc.name, "sweep": str(path), "grain_diameter_m": d, "d_over_r": d_over_r(d, sc.radius),
                    "xi": res.values["xi"], "omega_rpm": c.omega_rpm.tolist(),
                    "max_abs_rel_error_velocity": c.max_abs_rel_error_velocity,
                    "max_abs_rel_error_sinkage": c.max_abs_rel_error_sinkage})  # fmt: skip
    return out


def check_rows(checks: list[tuple[str, Path, float]], law: XiLengthLaw, xi_no_length: float) -> list[dict]:
    """Each check sweep's points: MPM, DRFT with the law's xi at its d / r, DRFT with ``xi_no_length``."""
    rows = []
    for name, path, d in checks:
        sc = with_mpm_push(load_scenario(name))
        ref = load_reference(path)
        q = d_over_r(d, sc.radius)
        xi_law = law.xi(q)
        with_law = compare(with_parameters(sc, {"xi": xi_law}), ref)
        without = compare(with_parameters(sc, {"xi": xi_no_length}), ref)
        for i, w in enumerate(with_law.omega_rpm):
            rows.append({
                "scenario": sc.name, "sweep": str(path), "grain_diameter_m": d, "d_over_r": q,
                "omega_rpm": float(w), "omega_over_omega0": float(w * RPM * math.sqrt(sc.radius / GRAVITY)),
                "velocity_mpm": float(with_law.velocity_ref[i]), "sinkage_mpm": float(with_law.sinkage_ref[i]),
                "xi_law": xi_law, "velocity_law": float(with_law.velocity_model[i]), "sinkage_law": float(with_law.sinkage_model[i]),
                "dv_law": float(with_law.rel_error_velocity[i]), "ds_law": float(with_law.rel_error_sinkage[i]),
                "xi_no_length": xi_no_length, "velocity_no_length": float(without.velocity_model[i]),
                "sinkage_no_length": float(without.sinkage_model[i]),
                "dv_no_length": float(without.rel_error_velocity[i]), "ds_no_length": float(without.rel_error_sinkage[i]),
            })  # fmt: skip
    return rows


def within(rows: list[dict], which: str) -> tuple[int, int]:
    """(points with both |dv| and |ds| <= TARGET, points) for ``which`` = "law" or "no_length"."""
    ok = [abs(r[f"dv_{which}"]) <= TARGET and abs(r[f"ds_{which}"]) <= TARGET for r in rows]
    return sum(ok), len(ok)


def plot(result: dict, path: Path) -> None:
    fig, ax = plt.subplots(1, 3, figsize=(14, 4.2))
    law = XiLengthLaw(**result["law"])
    q = np.array([f["d_over_r"] for f in result["fits"]])
    qq = np.geomspace(q.min() / 1.4, q.max() * 1.4, 50)
    ax[0].loglog(qq, law.xi(qq), "k-", lw=1, label=f"xi = {law.xi_ref:.3g} (d/r / {law.q_ref:.3g})^{law.exponent:.2f}")
    ax[0].loglog(q, [f["xi"] for f in result["fits"]], "ko", label="xi fitted on the MPM wheel")
    for qc in sorted({r["d_over_r"] for r in result["checks"]}):
        ax[0].plot([qc], [law.xi(qc)], "s", mfc="none", ms=9, label=f"check at d/r {qc:.3f}")
    ax[0].set_xlabel("d / r")
    ax[0].set_ylabel("xi")
    ax[0].legend(fontsize=7)
    ax[0].set_title("DRFT media scaling vs grain length")
    for k, (key, name) in enumerate((("dv", "velocity"), ("ds", "sinkage")), start=1):
        for label in sorted({(r["scenario"], r["d_over_r"]) for r in result["checks"]}):
            rows = [r for r in result["checks"] if (r["scenario"], r["d_over_r"]) == label]
            x = [r["omega_over_omega0"] for r in rows]
            (line,) = ax[k].plot(
                x, [100 * r[f"{key}_law"] for r in rows], "o-", label=f"{label[0]}, d/r {label[1]:.3f}: law"
            )
            ax[k].plot(
                x,
                [100 * r[f"{key}_no_length"] for r in rows],
                "o--",
                mfc="none",
                color=line.get_color(),
                label="  no length",
            )
        ax[k].axhspan(-100 * TARGET, 100 * TARGET, color="0.9", zorder=0)
        ax[k].axhline(0.0, color="k", lw=0.5)
        ax[k].set_xlabel("omega / omega_0")
        ax[k].set_ylabel(f"DRFT {name} error against MPM (%)")
        ax[k].legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=130)
    plt.close(fig)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--fit", nargs=3, action="append", required=True, metavar=("SCENARIO", "CSV", "D"))
    ap.add_argument("--check", nargs=3, action="append", default=[], metavar=("SCENARIO", "CSV", "D"))
    ap.add_argument("--out", type=Path, required=True, help="output stem (OUT.csv, OUT.json, OUT.png)")
    a = ap.parse_args()
    try:
        fits = [_set(s, "--fit") for s in a.fit]
        checks = [_set(s, "--check") for s in a.check]
        if len({round(d_over_r(d, load_scenario(n).radius), 12) for n, _, d in fits}) < 2:
            raise InputError("--fit needs sweeps at two distinct d / r at least")
    except (InputError, ValueError) as e:
        ap.error(str(e))
    points = fit_points(fits)
    for p in points:
        print(f"fit {p['scenario']} d/r {p['d_over_r']:.4f}: xi {p['xi']:.4g} (max |dv| {100 * p['max_abs_rel_error_velocity']:.1f} %, "
              f"|ds| {100 * p['max_abs_rel_error_sinkage']:.1f} %)")  # fmt: skip
    law = fit_xi_length_law([p["d_over_r"] for p in points], [p["xi"] for p in points])
    print(f"law: xi = {law.xi_ref:.4g} (d/r / {law.q_ref:.4g})^{law.exponent:.3f}")
    rows = check_rows(checks, law, points[0]["xi"])
    for r in rows:
        print(f"check {r['scenario']} d/r {r['d_over_r']:.4f} {r['omega_rpm']:g} RPM: law (xi {r['xi_law']:.3g}) "
              f"v {100 * r['dv_law']:+.1f} % s {100 * r['ds_law']:+.1f} %; no length (xi {r['xi_no_length']:.3g}) "
              f"v {100 * r['dv_no_length']:+.1f} % s {100 * r['ds_no_length']:+.1f} %")  # fmt: skip
    result = {"fits": points, "law": law.summary(), "checks": rows,
              "within_15_percent": {"law": list(within(rows, "law")), "no_length": list(within(rows, "no_length"))}}  # fmt: skip
    a.out.parent.mkdir(parents=True, exist_ok=True)
    write_csv(a.out.with_suffix(".csv"), rows)
    a.out.with_suffix(".json").write_text(json.dumps(result, indent=1) + "\n")
    plot(result, a.out.with_suffix(".png"))
    n_law, n = within(rows, "law")
    n_none, _ = within(rows, "no_length")
    print(f"within 15 % in both v and sinkage: law {n_law} of {n}, no length {n_none} of {n}")
    print(f"wrote {a.out.with_suffix('.csv')}, .json, .png")


if __name__ == "__main__":
    main()
