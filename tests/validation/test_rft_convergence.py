"""Discretisation convergence of the wheel's RFT/DRFT force (issue: < 1% from the paper's mesh to 4x finer)."""

import numpy as np
import pytest

from intrusim import geometry as g
from intrusim.forces import make_force_model
from intrusim.kinematics import BodyState

STATES = [
    BodyState(0, 0.085, 0.1, 0.25, 0.0, -2 * np.pi),  # 60 RPM, 20% slip
    BodyState(0, 0.09, 0.3, 0.2, -0.01, -np.pi),  # 30 RPM
    BodyState(0, 0.08, 0.0, 0.5, 0.0, -3 * np.pi),  # 90 RPM, deep
]


@pytest.mark.parametrize("kind", ["rft", "drft"])
@pytest.mark.parametrize("state", STATES)
def test_paper_mesh_within_one_percent_of_4x_finer(kind, state):
    def force(k):
        w = g.grousered_wheel(grouser_height_scale=1 / 3, rim_elements_per_segment=14 * k, lug_elements_per_face=8 * k)
        return make_force_model(kind, w, structural="wheel-rear-half").wrench(state).as_array()[:2]

    coarse, fine = force(1), force(4)
    assert np.linalg.norm(coarse - fine) / np.linalg.norm(fine) < 0.01
