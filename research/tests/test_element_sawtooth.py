"""``research/element_sawtooth.py``: the fine step is 1/16 of the default over 8 revolutions, and with
the paper's elements it runs the bulldozing wheel slower than the default step does (docs/locomotion.md)."""

import pytest


def test_the_fine_step_and_its_answer_at_the_papers_elements(load_example):
    mod = load_example("element_sawtooth")
    rows = {(r["elements"], r["step"]): r for r in mod.runs(10.0, 4.38, factors=(1,))}
    default, fine = rows[(1, "default")], rows[(1, "default / 16")]
    assert fine["dt_s"] == pytest.approx(default["dt_s"] / 16, rel=0.01)
    assert fine["state"].revolutions == 8
    assert fine["velocity"] < default["velocity"] * (1 - 4e-3)
