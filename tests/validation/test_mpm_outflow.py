"""Open sides (BoundaryConfig kind "open"): points that leave through them are removed and their mass
is counted as outflow; the mass in the box plus the outflow stays the mass of the start."""

import pytest
from pydantic import ValidationError

from intrusim.mpm.config import (
    BedConfig,
    BoundaryConfig,
    DomainConfig,
    MPMConfig,
    OutputConfig,
    Rectangle,
    TimeConfig,
    WallConfig,
)
from intrusim.mpm.grid import PAD
from intrusim.mpm.solver import Solver


def _collapse(right: str = "open", t_end: float = 0.4) -> tuple[Solver, float, list[dict]]:
    """A column 0.08 m wide and 0.14 m high at the left of a 0.16 m box (10 mm cells) collapses; its right side is ``right``."""
    cfg = MPMConfig(
        domain=DomainConfig(size=(0.16, 0.16), cells=(16, 16)),
        bed=BedConfig(rectangles=[Rectangle(x0=0.0, z0=0.0, x1=0.08, z1=0.14)]),
        boundaries=BoundaryConfig(right=WallConfig(kind=right)),
        time=TimeConfig(t_end=t_end),
        output=OutputConfig(record_every=0.02, guard_every_steps=20),
    )
    solver = Solver(cfg)
    mass0 = float(solver.particle_fields()["mass"].sum())
    return solver, mass0, solver.run()


@pytest.fixture(scope="module")
def open_right():
    return _collapse()


def test_mass_in_the_box_plus_outflow_is_conserved(open_right):
    solver, mass0, rows = open_right
    assert rows[-1]["outflow_mass"] > 0.05 * mass0  # a good part of the column left through the right side
    assert solver.outflow["points"] > 0
    for r in rows:
        assert r["grain_mass"] + r["outflow_mass"] == pytest.approx(mass0, rel=1e-6)
    outflow = [r["outflow_mass"] for r in rows]
    assert all(b >= a for a, b in zip(outflow, outflow[1:]))
    assert solver.dropped["points"] == 0


def test_points_leave_only_through_the_open_side(open_right):
    solver, _, _ = open_right
    x = solver.particle_fields()["x"]
    lx = solver.cfg.domain.size[0]
    assert x[:, 0].min() > -solver.h and x[:, 1].min() > -solver.h  # walls hold on the left and below
    # between guards a leaving point keeps its whole stencil: it is not past the padding
    assert x[:, 0].max() < lx + (solver.grid.pad - 2) * solver.h
    assert solver.grid.pad > PAD


def test_a_wall_keeps_what_an_open_side_lets_out():
    solver, mass0, rows = _collapse("frictionless", t_end=0.2)
    assert "outflow_mass" not in rows[-1]
    assert rows[-1]["grain_mass"] == pytest.approx(mass0, rel=1e-6)
    assert solver.grid.pad == PAD


def test_an_open_top_and_an_unknown_kind():
    assert BoundaryConfig(top="open", floor=WallConfig(kind="open")).top == "open"
    with pytest.raises(ValidationError):
        WallConfig(kind="porous")
    with pytest.raises(ValidationError):
        BoundaryConfig(top="sticky")
