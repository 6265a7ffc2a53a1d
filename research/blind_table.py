"""The blind-prediction table of docs/results.md and one figure per body, from four `intrusim calibrate` runs.

Each run compares a DRFT model with the MPM references of the Table S1 wheel and of the --check
bodies, and writes NAME.json and NAME.csv (``--out``). The table puts them side by side:

* ``paper``: the paper's DRFT (xi 0.35, psi = x, lambda 1, the submerged rear-half split), nothing
  fitted (``--params none --structural wheel-rear-half``);
* ``fitted``: xi, psi's slope and offset and the zone band's width fitted to the Table S1 wheel
  (circle split), lambda from plate drag (``--fix lam=2.6``);
* ``xi``: only xi fitted; psi from where the MPM wheel stops bearing on the grains (figure
  ``wheel-load``) and lambda from plate drag (``--fix``);
* ``measured``: nothing fitted; the medium's RFT map from MPM plates as well (``--rft-coefficients``).

The four runs (from the reference set, ``intrusim mpm references``; about 15 min on 2 cores):

    R=runs/references; CHECKS="--check small-wheel=$R/small-wheel_mpm.csv --check wheel-10-grousers=$R/wheel-10-grousers_mpm.csv \\
        --check wheel-30-grousers=$R/wheel-30-grousers_mpm.csv --check wheel-tall-grousers=$R/wheel-tall-grousers_mpm.csv \\
        --check runner=$R/runner_mpm.csv"
    intrusim calibrate wheel --mpm $R/wheel_mpm.csv --params none --structural wheel-rear-half --name blind_paper $CHECKS --out research/outputs/figures
    intrusim calibrate wheel --mpm $R/wheel_mpm.csv --params xi,psi,psi_offset,zone_width --fix lam=2.6 \\
        --structural wheel-rear-half-circle --starts 8 --leave-one-out --name blind $CHECKS --out research/outputs/figures
    intrusim calibrate wheel --mpm $R/wheel_mpm.csv --params xi --fix lam=2.6 --fix psi=0.727 --fix psi_offset=0.431 \\
        --structural wheel-rear-half-circle --starts 4 --leave-one-out --name blind_xi $CHECKS --out research/outputs/figures
    intrusim calibrate wheel --mpm $R/wheel_mpm.csv --params none --fix lam=2.6 --fix psi=0.727 --fix psi_offset=0.431 \\
        --rft-coefficients docs/figures/rft_map_reference.json --structural wheel-rear-half-circle \\
        --name blind_measured $CHECKS --out research/outputs/figures

    python research/blind_table.py research/outputs/figures --png docs/figures --write docs/results.md
"""

from __future__ import annotations

import argparse
import csv
import json
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "src"))
from intrusim._doc_markers import replace_between  # noqa: E402

RUNS = (("paper", "blind_paper", "paper's DRFT"), ("fitted", "blind", "4 fitted"), ("xi", "blind_xi", "xi fitted"),
        ("measured", "blind_measured", "nothing fitted"))  # fmt: skip
BODIES = (
    ("", "Table S1 wheel (calibrated on)"),
    ("small-wheel", "half-size wheel (its similar set-up)"),
    ("wheel-10-grousers", "10 grousers"),
    ("wheel-30-grousers", "30 grousers"),
    ("wheel-tall-grousers", "grousers twice as tall"),
    ("runner", "four-flap runner (no zone)"),
)
TARGET = 0.10


def comparison(report: dict, body: str) -> dict:
    return report["calibration"]["comparison"] if body == "" else report["checks"][body]["calibrated"]


def pct(e: float | None, bold: bool = False) -> str:
    if e is None:
        return "failed"
    s = f"{100 * e:+.0f}" if abs(e) >= 0.095 else f"{100 * e:+.1f}"
    return f"**{s}**" if bold else s


def cell(cmp: dict, i: int) -> str:
    ev, es = cmp["rel_error_velocity"][i], cmp["rel_error_sinkage"][i]
    both = ev is not None and es is not None and abs(ev) <= TARGET and abs(es) <= TARGET
    return f"{pct(ev, both)} / {pct(es, both)}"


def table(folder: Path) -> tuple[list[str], dict]:
    reports = {key: json.loads((folder / f"{stem}.json").read_text()) for key, stem, _ in RUNS}
    loo = {key: reports[key].get("leave_one_out", {}).get("comparison") for key, _, _ in RUNS}
    head = "| body | RPM | MPM v (m/s) | MPM sinkage (mm) | " + " | ".join(label for _, _, label in RUNS)
    head += " | leave-one-out: 4 fitted | leave-one-out: xi fitted |"
    lines = [head, "|" + "---|" * (4 + len(RUNS) + 2)]
    misses: dict[str, dict[str, int]] = {key: {"points": 0, "within": 0} for key, _, _ in RUNS}
    for body, label in BODIES:
        cmps = {key: comparison(reports[key], body) for key, _, _ in RUNS}
        ref = cmps["fitted"]
        for i, w in enumerate(ref["omega_rpm"]):
            row = [
                label if i == 0 else "",
                f"{w:g}",
                f"{ref['velocity_ref_m_s'][i]:.3f}",
                f"{1e3 * ref['sinkage_ref_m'][i]:.1f}",
            ]
            for key, _, _ in RUNS:
                c = cmps[key]
                row.append(cell(c, i))
                ev, es = c["rel_error_velocity"][i], c["rel_error_sinkage"][i]
                misses[key]["points"] += 1
                misses[key]["within"] += int(
                    ev is not None and es is not None and abs(ev) <= TARGET and abs(es) <= TARGET
                )
            for key in ("fitted", "xi"):
                row.append(cell(loo[key], i) if body == "" and loo[key] is not None else "")
            lines.append("| " + " | ".join(row) + " |")
    fits = {key: reports[key]["calibration"]["values"] for key, _, _ in RUNS}
    return lines, {"within_10pct": misses, "fitted_values": fits}


def figures(folder: Path, out: Path) -> list[Path]:
    """One figure per body: MPM, the paper's DRFT and the three calibrations (v and sinkage against omega)."""
    rows = {key: list(csv.DictReader((folder / f"{stem}.csv").open())) for key, stem, _ in RUNS}
    paths = []
    for body, label in BODIES:
        tag = f" ({body})" if body else ""
        fig, (av, az) = plt.subplots(1, 2, figsize=(9, 3.4), layout="constrained")
        mpm = [r for r in rows["fitted"] if r["curve"] == f"MPM{tag}"]
        for key, _, name in RUNS:
            curve = "DRFT, nothing fitted" if key in ("paper", "measured") else "DRFT calibrated"
            pts = [r for r in rows[key] if r["curve"] == f"{curve}{tag}" and r["velocity_m_s"] not in ("", "nan")]
            w = [float(r["omega_rpm"]) for r in pts]
            av.plot(w, [float(r["velocity_m_s"]) for r in pts], "-", lw=1, label=name)
            az.plot(w, [1e3 * float(r["sinkage_m"]) for r in pts], "-", lw=1)
        w = [float(r["omega_rpm"]) for r in mpm]
        av.plot(w, [float(r["velocity_m_s"]) for r in mpm], "ko", label="MPM")
        az.plot(w, [1e3 * float(r["sinkage_m"]) for r in mpm], "ko")
        av.set(xlabel="omega (RPM)", ylabel="v (m/s)", title=label)
        az.set(xlabel="omega (RPM)", ylabel="sinkage (mm)")
        av.legend(fontsize=7)
        path = out / f"blind_table_{body or 'wheel'}.png"
        fig.savefig(path, dpi=110)
        plt.close(fig)
        paths.append(path)
    return paths


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("folder", type=Path, help="the folder of the four runs' NAME.json and NAME.csv")
    ap.add_argument("--write", type=Path, default=None, help="markdown file whose blind_table block is replaced")
    ap.add_argument("--png", type=Path, default=None, help="folder of the per-body figures (default: the runs' folder)")
    a = ap.parse_args()
    lines, summary = table(a.folder)
    print("\n".join(lines))
    print(json.dumps(summary, indent=1))
    if a.png is not None:
        a.png.mkdir(parents=True, exist_ok=True)
    for p in figures(a.folder, a.png or a.folder):
        print(p)
    if a.write is not None:
        a.write.write_text(replace_between(a.write.read_text(), "blind_table", ["", *lines, ""], str(a.write)))
        print(f"wrote the table into {a.write}")


if __name__ == "__main__":
    main()
