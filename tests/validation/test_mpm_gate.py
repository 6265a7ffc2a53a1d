"""A static obstacle holds a granular column back until it is removed (a gate), then the column
collapses past it (issue: static rigid obstacles, gates removed at a set time)."""

import numpy as np

from intrusim.mpm.config import BedConfig, DomainConfig, MPMConfig, ObstacleConfig, Rectangle, TimeConfig
from intrusim.mpm.solver import Solver

GATE_X, OPEN_AT = 0.1, 0.15


def test_gate_holds_the_column_then_releases_it():
    cfg = MPMConfig(
        domain=DomainConfig(size=(0.4, 0.15), cells=(40, 15)),
        bed=BedConfig(rectangles=[Rectangle(x0=0.0, z0=0.0, x1=GATE_X, z1=0.1)]),
        obstacles=[
            ObstacleConfig(
                vertices=[(GATE_X, 0.0), (GATE_X + 0.01, 0.0), (GATE_X + 0.01, 0.14), (GATE_X, 0.14)],
                mu=0.0,
                removal_time=OPEN_AT,
            )
        ],
        time=TimeConfig(t_end=0.6),
    )
    solver = Solver(cfg)
    solver.run(t_end=OPEN_AT - 0.01)
    held = solver.particle_fields()
    # the gate acts on the grid, so points may reach up to about a cell into it, no further
    assert held["x"][:, 0].max() < GATE_X + solver.h
    assert np.linalg.norm(held["v"], axis=1).max() < 0.05
    solver.run(t_end=0.6)
    released = solver.particle_fields()
    assert released["x"][:, 0].max() > GATE_X + 0.05  # the front ran out past the gate (by > L0 / 2)
    drop = held["x"][:, 1].mean() - released["x"][:, 1].mean()
    assert drop > 0.005  # the centre of mass fell (the back corner stays: a failure wedge, mu = 0.56)
