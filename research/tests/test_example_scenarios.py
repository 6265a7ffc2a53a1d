"""The scenario TOMLs in research/ load and say what their comments claim."""

from pathlib import Path

import pytest

from intrusim.analysis.steady import run_steady
from intrusim.scenarios import load_scenario

EXAMPLES = Path(__file__).resolve().parents[1]


def test_wheel_bulldozing_is_the_paper_drft_plus_the_fitted_term():
    sc = load_scenario(EXAMPLES / "wheel_bulldozing.toml")
    fm = sc.force_model
    assert (fm.structural, fm.lam, fm.xi, fm.psi_slope, fm.psi_offset) == ("wheel-rear-half", 1.0, 0.35, 1.0, 0.0)
    assert fm.bulldozing == 4.43 and sc.external_fx == 4.0
    st = run_steady(sc, "drft", 30.0)
    assert st.velocity == pytest.approx(0.160, rel=0.03)  # the settled MPM wheel: 0.150 m/s
    assert st.sinkage == pytest.approx(0.0484, abs=1e-3)  # MPM: 45.1 mm
