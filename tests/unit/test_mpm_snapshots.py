"""Particle snapshots open in ParaView as one time series, with the rigid bodies drawn at their pose."""

import re

import meshio
import numpy as np
import pytest

from intrusim.geometry import posed_polygon
from intrusim.mpm.config import (
    BedConfig,
    DomainConfig,
    IntruderConfig,
    MPMConfig,
    ObstacleConfig,
    OutputConfig,
    PrescribedMotion,
    Rectangle,
    TimeConfig,
)
from intrusim.mpm.solver import Solver

SQUARE = [(-0.02, -0.02), (0.02, -0.02), (0.02, 0.02), (-0.02, 0.02)]
GATE = [(0.2, 0.0), (0.21, 0.0), (0.21, 0.12), (0.2, 0.12)]


def _config(run_dir, t_end: float) -> MPMConfig:
    """A bed, a gate removed at 2 ms and a square driven sideways while it spins."""
    return MPMConfig(
        domain=DomainConfig(size=(0.3, 0.15), cells=(30, 15)),
        bed=BedConfig(rectangles=[Rectangle(x0=0.0, z0=0.0, x1=0.2, z1=0.08)]),
        obstacles=[ObstacleConfig(vertices=GATE, mu=0.2, removal_time=2e-3)],
        intruders=[
            IntruderConfig(vertices=SQUARE, x=0.1, z=0.1, mu_w=0.35, motion=PrescribedMotion(vx=0.5, omega=-20.0))
        ],
        time=TimeConfig(t_end=t_end),
        output=OutputConfig(directory=str(run_dir), record_every=1e-3, snapshot_every=1e-3),
    )


@pytest.fixture(scope="module")
def run(tmp_path_factory):
    run_dir = tmp_path_factory.mktemp("snap")
    solver = Solver(_config(run_dir, 3e-3))
    solver.run()
    return solver, run_dir / "snapshots"


def test_particle_snapshot_has_the_fields(tmp_path):
    solver = Solver(_config(tmp_path, 3e-3))
    for _ in range(5):
        solver.step()
    mesh = meshio.read(solver.write_snapshot())
    x = solver.particles.to_numpy()["x"]
    assert mesh.points.shape == (len(x), 3)
    np.testing.assert_array_equal(mesh.points[:, [0, 2]], x)
    assert not mesh.points[:, 1].any()  # the plane y = 0
    for field in ("velocity", "pressure", "density", "eps_p", "gdot_p"):
        assert len(mesh.point_data[field]) == len(x)
    np.testing.assert_array_equal(mesh.point_data["velocity"][:, [0, 2]], solver.particles.to_numpy()["v"])


def test_bodies_are_written_at_their_pose(run):
    solver, snap = run
    first, last = sorted(snap.glob("bodies_*.vtu"))[0], sorted(snap.glob("bodies_*.vtu"))[-1]
    t_snap = int(last.stem.split("_")[1]) * solver.dt
    start = meshio.read(first)
    assert np.concatenate(start.cell_data["body"]).tolist() == [0.0, -1.0]  # the square and the gate
    np.testing.assert_allclose(start.points[4:, [0, 2]], GATE)
    end = meshio.read(last)
    assert np.concatenate(end.cell_data["body"]).tolist() == [0.0]  # the gate is gone after 2 ms
    pose = {k: float(np.concatenate(end.cell_data[k])[0]) for k in ("x", "z", "theta", "vx", "omega")}
    assert pose["x"] == pytest.approx(0.1 + 0.5 * t_snap)
    assert pose["z"] == pytest.approx(0.1)
    assert pose["theta"] == pytest.approx(-20.0 * t_snap)
    np.testing.assert_allclose(
        end.points[:, [0, 2]], posed_polygon(np.array(SQUARE), pose["x"], pose["z"], pose["theta"]), atol=1e-12
    )
    assert (pose["vx"], pose["omega"]) == pytest.approx((0.5, -20.0))


def test_collection_lists_every_snapshot_at_its_time(run):
    solver, snap = run
    text = (snap / "snapshots.pvd").read_text()
    entries = re.findall(r'timestep="([^"]+)" part="(\d)" file="([^"]+)"', text)
    particles = [(float(t), f) for t, part, f in entries if part == "0"]
    bodies = [(float(t), f) for t, part, f in entries if part == "1"]
    assert [f for _, f in particles] == sorted(p.name for p in snap.glob("particles_*.vtu"))
    assert [f for _, f in bodies] == sorted(p.name for p in snap.glob("bodies_*.vtu"))
    assert len(particles) == 4  # t = 0, 1, 2, 3 ms
    np.testing.assert_allclose([t for t, _ in particles], [0.0, 1e-3, 2e-3, 3e-3], atol=0.6 * solver.dt)
    assert len(list(snap.glob("gdot_p_*.png"))) == 4
