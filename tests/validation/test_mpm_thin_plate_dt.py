"""A plate thinner than a cell, dragged fast, carries the same drag at any time step (issue 52).

The Fig 6 plate (16 mm x 4 mm, 0.8 cells thick at 5 mm cells) is dragged 3 cm deep at 0.64 m/s, the
fastest speed of the drag law's fit, with the default contact ("nodes"); its drag is the mean over the
second half of 4 cm of travel. Each halving of dt (C 0.3, 0.15, 0.075) moves it by less than 1 %.
Before the contact points' affine velocity was set to the body's rigid gradient, it fell 1.8, 2.1
and 4.3 % per halving (C 0.3 to 0.0375): the grid's velocity gradient kept on a corrected point put
into the nodes inside the plate, each step, a momentum their projection took out again.

A corrected point's affine velocity is the body's rigid gradient [[0, -omega], [omega, 0]]: checked
on a square turning as it is pushed into a bed.
"""

import numpy as np
import pytest

from intrusim.mpm.config import (
    BedConfig,
    DomainConfig,
    IntruderConfig,
    MaterialConfig,
    MPMConfig,
    OutputConfig,
    PrescribedMotion,
    Rectangle,
    TimeConfig,
)
from intrusim.mpm.plate import PlateDragCase, steady_force
from intrusim.mpm.solver import Solver

H = 0.005  # m


def drag(cfl: float) -> float:
    case = PlateDragCase(depth=0.03, speed=0.64, travel=0.04, cells=(60, 30), cfl=cfl)
    rows = Solver(case.config(cpu_threads=1)).run()
    return -steady_force(rows, "fx")


@pytest.fixture(scope="module")
def drags():
    return {cfl: drag(cfl) for cfl in (0.3, 0.15, 0.075)}


def test_a_fast_sub_cell_plate_drag_does_not_move_with_dt(drags):
    assert drags[0.3] > 20.0  # N/m: the bed resists (K |z| alone is about 30 N/m here)
    for coarse, fine in ((0.3, 0.15), (0.15, 0.075)):
        change = drags[fine] / drags[coarse] - 1.0
        assert abs(change) < 0.01, (coarse, fine, drags)


def test_a_corrected_contact_point_takes_the_bodys_rigid_velocity_gradient():
    omega = 3.0  # rad/s
    cfg = MPMConfig(
        domain=DomainConfig(size=(0.2, 0.15), cells=(40, 30)),
        material=MaterialConfig(rho_c=638.0, mu_s=0.56, youngs_modulus=1e6),
        bed=BedConfig(rectangles=[Rectangle(x0=0.0, z0=0.0, x1=0.2, z1=0.08)]),
        intruders=[
            IntruderConfig(
                vertices=[(-0.02, -0.02), (0.02, -0.02), (0.02, 0.02), (-0.02, 0.02)],
                x=0.1,
                z=0.1,
                mu_w=0.4,
                motion=PrescribedMotion(vz=-0.2, omega=omega, ramp_time=0.0),
            )
        ],
        time=TimeConfig(t_end=0.05, cfl=0.3),
        output=OutputConfig(record_every=0.05),
        backend=dict(cpu_threads=1),
    )
    solver = Solver(cfg)
    rows = solver.run()
    d = solver.particles.to_numpy(["x", "C"])
    C = d["C"].reshape(-1, 2, 2)
    rigid = np.array([[0.0, -omega], [omega, 0.0]])
    corrected = np.all(C == rigid, axis=(1, 2))
    assert corrected.sum() >= 5  # the square is in the bed (its bottom 1 cm below the top at the end)
    # every one lies at the square's surface (within the contact gap, half a point spacing)
    body = np.array([rows[-1]["x"], rows[-1]["z"]])
    theta = rows[-1]["theta"]
    c, s = np.cos(theta), np.sin(theta)
    r = d["x"][corrected] - body
    local = np.stack([c * r[:, 0] + s * r[:, 1], -s * r[:, 0] + c * r[:, 1]], axis=1)
    outside = np.max(np.abs(local), axis=1) - 0.02  # distance outside the square along its axes
    assert np.all(outside > -1e-6) and np.all(outside < 0.5 * H / 2 + 1e-6), outside  # 1 um: single precision
