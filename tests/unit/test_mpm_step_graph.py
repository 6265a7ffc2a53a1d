"""A step launched as one compiled Taichi graph gives the numbers of the kernel-by-kernel step."""

import numpy as np
import pytest

from intrusim.mpm.backend import BenchmarkSwitches
from intrusim.mpm.config import (
    BedConfig,
    CoupledMotion,
    DomainConfig,
    IntruderConfig,
    MPMConfig,
    ObstacleConfig,
    Rectangle,
)
from intrusim.mpm.solver import Solver
from intrusim.mpm.step_graph import Launch, StepGraph
from intrusim.mpm.transfer import p2g_args, p2g_kernel


def _config() -> MPMConfig:
    """A bed with a gate removed after a few steps and a coupled, spinning square pushed into it."""
    square = [(-0.02, -0.02), (0.02, -0.02), (0.02, 0.02), (-0.02, 0.02)]
    return MPMConfig(
        domain=DomainConfig(size=(0.3, 0.15), cells=(30, 15)),
        bed=BedConfig(rectangles=[Rectangle(x0=0.0, z0=0.0, x1=0.2, z1=0.08)]),
        obstacles=[
            ObstacleConfig(vertices=[(0.2, 0.0), (0.21, 0.0), (0.21, 0.12), (0.2, 0.12)], mu=0.2, removal_time=4e-4)
        ],
        intruders=[
            IntruderConfig(
                vertices=square,
                x=0.1,
                z=0.1,
                mu_w=0.35,
                motion=CoupledMotion(omega=-20.0, ramp_time=1e-3, mass_x=0.5, mass_z=0.5, external_force=(0.2, -3.0)),
            )
        ],
    )


def test_graph_step_equals_direct_calls():
    runs = []
    for step_graph in (True, False):
        s = Solver(_config(), switches=BenchmarkSwitches(step_graph=step_graph))
        n = int(round(1e-3 / s.dt))  # past the gate's removal: the graph is rebuilt without it
        for _ in range(n):
            s.step()
        if step_graph:
            assert len(s._graphs) == 2  # with the gate, then without it
        runs.append((s.particles.to_numpy(), s.intruders[0].state.as_dict(), s.intruders[0].contact.read_impulse()))
    (pa, ba, ia), (pb, bb, ib) = runs
    assert np.abs(ia).max() > 0  # the body touched the grains
    for name in pa:
        np.testing.assert_array_equal(pa[name], pb[name], err_msg=name)
    assert ba == bb
    np.testing.assert_array_equal(ia, ib)


def test_graph_refuses_a_wrong_argument_count():
    s = Solver(_config())
    args = p2g_args(s.particles, s.grid, s.dt)
    with pytest.raises(TypeError, match="arguments"):
        StepGraph([Launch(p2g_kernel(True), args[:-1])], {})
