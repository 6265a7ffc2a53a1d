"""``research/blind_table.py``: the blind table's cells, bold where both v and sinkage are within 10 %,
the within-10 % counts per model, the leave-one-out columns on the calibration wheel, the marker block."""

import json

import pytest


def _cmp(ev, es, w=(30.0, 90.0)):
    return {"omega_rpm": list(w), "velocity_ref_m_s": [0.15, 0.2], "sinkage_ref_m": [0.05, 0.09],
            "rel_error_velocity": list(ev), "rel_error_sinkage": list(es)}  # fmt: skip


def _write(folder, stem, ev, es, loo=False):
    checks = {b: {"calibrated": _cmp(ev, es)} for b in ("small-wheel", "wheel-10-grousers", "wheel-30-grousers",
                                                         "wheel-tall-grousers", "runner")}  # fmt: skip
    report = {"calibration": {"comparison": _cmp(ev, es), "values": {"xi": 0.5}}, "checks": checks}
    if loo:
        report["leave_one_out"] = {"comparison": _cmp((0.2, 0.01), (0.0, 0.0))}
    (folder / f"{stem}.json").write_text(json.dumps(report))


def test_cells_counts_and_marker_block(load_example, tmp_path):
    mod = load_example("blind_table")
    _write(tmp_path, "blind_paper", (0.5, -0.3), (0.0, 0.0))
    _write(tmp_path, "blind", (0.05, 0.02), (-0.09, 0.3), loo=True)
    _write(tmp_path, "blind_xi", (0.05, None), (0.05, 0.05), loo=True)
    _write(tmp_path, "blind_measured", (0.1, 0.1), (0.1, 0.1))
    lines, summary = mod.table(tmp_path)
    assert lines[2].startswith(
        "| Table S1 wheel (calibrated on) | 30 | 0.150 | 50.0 | +50 / +0.0 | **+5.0** / **-9.0** |"
    )
    assert "| +2.0 / +30 |" in lines[3] and "failed / +5.0" in lines[3]  # one out of 10 %, a failed point
    assert lines[2].endswith("| +20 / +0.0 | +20 / +0.0 |")  # leave-one-out on the calibration wheel only
    assert lines[4].endswith("|  |  |")
    within = summary["within_10pct"]
    assert within["fitted"] == {"points": 12, "within": 6} and within["measured"]["within"] == 12
    assert within["xi"]["within"] == 6 and within["paper"]["within"] == 0
    doc = tmp_path / "r.md"
    doc.write_text("a\n<!-- blind_table: begin -->\nold\n<!-- blind_table: end -->\nb\n")
    from intrusim._doc_markers import replace_between

    text = replace_between(doc.read_text(), "blind_table", lines, "r.md")
    assert "old" not in text and text.count("| Table S1 wheel") == 1
    with pytest.raises(ValueError):
        replace_between("no markers", "blind_table", lines)
