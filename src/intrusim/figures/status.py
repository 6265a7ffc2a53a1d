"""The model-against-MPM status table of docs/results.md, generated from the figures' CSVs.

``intrusim reproduce NAME --mpm`` writes ``NAME_vs_mpm.csv``: each model curve's relative difference
from the MPM curve of the same body at the MPM omegas. :func:`status_table` sums each curve up
(omegas, largest and median difference in v and in sinkage, how many omegas are within the
tolerance in both) and :func:`write_status` puts the table between the markers of a markdown file
(``intrusim status --write docs/results.md``), so the page's numbers are the CSVs' numbers.
"""

from __future__ import annotations

import csv
import math
from collections import defaultdict
from pathlib import Path

import numpy as np

#: the figures whose CSVs hold model-against-MPM differences, in the page's order
FIGURES_WITH_MPM = ("fig5ab", "fig7bc", "figs1")
BEGIN, END = "<!-- status table: begin -->", "<!-- status table: end -->"  # _doc_markers.markers("status table")
TOLERANCE = 0.15  # the paper's claim: DRFT within 15 % of MPM


def _number(text: str) -> float:
    try:
        return float(text)
    except ValueError:
        return math.nan


def curve_agreement(csv_path: Path, tolerance: float = TOLERANCE) -> list[dict]:
    """One summary per (curve, body) of a ``*_vs_mpm.csv``: omegas, largest and median |difference|
    in v and in sinkage, and how many omegas have both within ``tolerance`` (a missing model point
    counts as outside)."""
    groups: dict[tuple[str, str], list[tuple[float, float, float]]] = defaultdict(list)
    with open(csv_path, newline="") as f:
        for row in csv.DictReader(f):
            groups[(row["curve"], row["scenario"])].append(
                (_number(row["omega_rpm"]), _number(row["rel_diff_velocity"]), _number(row["rel_diff_sinkage"]))
            )
    out = []
    for (curve, body), points in groups.items():
        omegas = sorted(w for w, _, _ in points)
        dv = sorted(abs(v) for _, v, _ in points if math.isfinite(v))
        ds = sorted(abs(s) for _, _, s in points if math.isfinite(s))
        within = sum(
            math.isfinite(v) and math.isfinite(s) and abs(v) <= tolerance and abs(s) <= tolerance for _, v, s in points
        )
        out.append({
            "curve": curve,
            "body": body,
            "omegas": omegas,
            "v_max": dv[-1] if dv else math.nan,
            "v_median": _median(dv),
            "sinkage_max": ds[-1] if ds else math.nan,
            "sinkage_median": _median(ds),
            "within": within,
        })  # fmt: skip
    return out


def _median(xs: list[float]) -> float:
    return float(np.median(xs)) if xs else math.nan


def _pct(x: float) -> str:
    return "-" if not math.isfinite(x) else f"{100 * x:.0f} %"


def status_table(figures_dir: Path, tolerance: float = TOLERANCE) -> list[str]:
    """Markdown lines: one row per model curve of every figure in :data:`FIGURES_WITH_MPM` whose
    ``*_vs_mpm.csv`` is in ``figures_dir``."""
    lines = [
        f"| figure | model | body | omegas (RPM) | v: median / largest difference | sinkage: median / largest "
        f"| omegas within {100 * tolerance:g} % in both |",
        "|---|---|---|---|---|---|---|",
    ]
    for name in FIGURES_WITH_MPM:
        path = Path(figures_dir) / f"{name}_vs_mpm.csv"
        if not path.is_file():
            lines.append(f"| {name} | no `{path.name}` | | | | | |")
            continue
        for c in curve_agreement(path, tolerance):
            w = c["omegas"]
            lines.append(
                f"| {name} | {c['curve']} | {c['body']} | {w[0]:g}-{w[-1]:g} ({len(w)}) | "
                f"{_pct(c['v_median'])} / {_pct(c['v_max'])} | {_pct(c['sinkage_median'])} / {_pct(c['sinkage_max'])} | "
                f"{c['within']} of {len(w)} |"
            )
    return lines


def write_status(doc: Path, figures_dir: Path, tolerance: float = TOLERANCE) -> None:
    """Replace the lines between :data:`BEGIN` and :data:`END` in ``doc`` by :func:`status_table`
    (a doc without exactly one such pair is refused: :class:`intrusim._doc_markers.MarkerError`)."""
    from intrusim._doc_markers import replace_between

    text = Path(doc).read_text()
    Path(doc).write_text(replace_between(text, "status table", status_table(figures_dir, tolerance), where=str(doc)))
