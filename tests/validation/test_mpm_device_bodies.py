"""A coupled body's dynamics on the device (``BenchmarkSwitches.device_bodies``, the default) against the host's.

With the dynamics in a kernel at the end of the step, the pose never leaves the device between
steps (on a GPU the host would otherwise wait for the device every step to read the impulse
back). The host path is the reference: the same semi-implicit Euler in float64, so the two may
differ only in the last bit of the body's state (the kernel's arithmetic may fuse a multiply-add).
"""

import numpy as np
import pytest
import taichi as ti

from intrusim.mpm.backend import BenchmarkSwitches
from intrusim.mpm.config import (
    BedConfig,
    CoupledMotion,
    DomainConfig,
    IntruderConfig,
    MPMConfig,
    PrescribedMotion,
    Rectangle,
)
from intrusim.mpm.contact import node_box
from intrusim.mpm.solver import Solver
from intrusim.scenarios import grousered_wheel_scenario
from intrusim.scenarios.mpm_locomotion import mpm_config, quick_settings

BODY = ("x", "z", "theta", "vx", "vz", "omega")


def _wheel(device_bodies: bool, contact: str = "nodes") -> Solver:
    """The coarse wheel at 60 RPM (2,500 points, ramp 0.15 s)."""
    cfg = mpm_config(grousered_wheel_scenario(), quick_settings("wheel").validated_copy(contact=contact), 60.0, None)
    return Solver(cfg, switches=BenchmarkSwitches(device_bodies=device_bodies))


def _body(solver: Solver) -> np.ndarray:
    st = solver.intruders[0].state
    return np.array([getattr(st, n) for n in BODY], float)


@pytest.mark.parametrize("contact, rolled", [("nodes", 0.015), ("surface", 0.02)])
def test_device_dynamics_follow_the_host_dynamics(contact, rolled):
    host, device = _wheel(False, contact), _wheel(True, contact)
    assert device.intruders[0].on_device and not host.intruders[0].on_device
    start = _body(device)
    for _ in range(1500):  # spin-up, sinking and rolling
        host.step()
        device.step()
    bh, bd = _body(host), _body(device)
    # it rolled (measured 1.8 cm with the contact "nodes", over 2 cm with "surface") and sank 1 cm
    assert bd[0] - start[0] > rolled and start[1] - bd[1] > 0.01
    assert bd[5] == host.cfg.intruders[0].motion.omega  # driven omega after the ramp
    np.testing.assert_allclose(bd, bh, rtol=1e-12, atol=1e-12)  # measured: 7e-17 in vz
    xh, xd = host.particles.to_numpy(["x"])["x"], device.particles.to_numpy(["x"])["x"]
    assert np.max(np.abs(xd - xh)) < 1e-7  # m (measured: identical)
    np.testing.assert_allclose(
        device.intruders[0].contact.read_impulse(), host.intruders[0].contact.read_impulse(), rtol=1e-9, atol=1e-12
    )


def test_reading_the_state_does_not_disturb_the_run():
    # state reads the device's pose back; a state handed out is written back before the next step,
    # unchanged, so a run read every step is the run read never
    read, unread = _wheel(True), _wheel(True)
    for _ in range(300):
        read.step()
        _body(read)
        unread.step()
    np.testing.assert_array_equal(_body(read), _body(unread))
    np.testing.assert_array_equal(read.particles.to_numpy(["x"])["x"], unread.particles.to_numpy(["x"])["x"])


def test_a_state_changed_between_steps_reaches_the_device():
    runs = []
    for device_bodies in (False, True):
        s = _wheel(device_bodies)
        for _ in range(300):
            s.step()
        st = s.intruders[0].state
        st.vx, st.z = 0.5, st.z + 0.01  # as a driver that sets a body's state would
        for _ in range(50):
            s.step()
        runs.append(_body(s))
    host, device = runs
    np.testing.assert_allclose(device, host, rtol=1e-12, atol=1e-12)
    assert host[3] > 0.3  # the push is still felt after 50 steps


def _three_bodies() -> MPMConfig:
    """Two coupled squares (different masses, pushes and spins) and a prescribed one in one bed."""
    square = [(-0.02, -0.02), (0.02, -0.02), (0.02, 0.02), (-0.02, 0.02)]
    coupled = [
        CoupledMotion(omega=-20.0, ramp_time=1e-3, mass_x=0.5, mass_z=0.5, external_force=(0.2, -3.0)),
        CoupledMotion(omega=15.0, ramp_time=2e-3, mass_x=0.8, mass_z=0.3, external_force=(-0.1, 0.0), free_x=False),
    ]
    bodies = [IntruderConfig(vertices=square, x=x, z=0.1, mu_w=0.35, motion=m) for x, m in zip((0.07, 0.16), coupled)]
    bodies.append(IntruderConfig(vertices=square, x=0.24, z=0.1, mu_w=0.35, motion=PrescribedMotion(vz=-0.2)))
    return MPMConfig(
        domain=DomainConfig(size=(0.3, 0.15), cells=(30, 15)),
        bed=BedConfig(rectangles=[Rectangle(x0=0.0, z0=0.0, x1=0.3, z1=0.08)]),
        intruders=bodies,
        contact="surface",  # the motions below were measured with it; the wheel above has both contacts
    )


def test_each_of_several_bodies_keeps_its_own_dynamics():
    runs = []
    for device_bodies in (False, True):
        s = Solver(_three_bodies(), switches=BenchmarkSwitches(device_bodies=device_bodies))
        assert [b.on_device for b in s.intruders] == [device_bodies, device_bodies, False]  # prescribed: host
        for _ in range(int(round(0.02 / s.dt))):
            s.step()
        runs.append(np.array([[getattr(b.state, n) for n in BODY] for b in s.intruders]))
    host, device = runs
    # both coupled squares are thrown up by the grains they spin into (measured: 5.7 and 4.5 mm in
    # 0.02 s), the first also forward; the second is held in x
    assert host[0, 0] - 0.07 > 0.003 and host[0, 1] - 0.1 > 0.003 and host[1, 1] - 0.1 > 0.003
    assert host[1, 0] == 0.16 and host[1, 3] == 0.0
    np.testing.assert_allclose(device, host, rtol=1e-12, atol=1e-12)


def test_the_contact_kernel_box_is_the_disc_clipped_to_the_grid():
    nx, ny, pad, h, radius = 40, 30, 3, 0.01, 0.055
    centres = np.array([[0.1, 0.1], [0.0, 0.0], [-0.1, 0.05], [0.33, 0.24], [0.5, 0.5], [0.123456, 0.0987]])
    out = ti.ndarray(ti.i32, shape=(len(centres), 4))
    pts = ti.ndarray(ti.f64, shape=(len(centres), 2))
    pts.from_numpy(centres)

    @ti.kernel
    def boxes(pts: ti.types.ndarray(), out: ti.types.ndarray(), radius: ti.f64, h: ti.f64, pad: int, nx: int, ny: int):
        for k in range(pts.shape[0]):
            out[k, 0], out[k, 1], out[k, 2], out[k, 3] = node_box(pts[k, 0], pts[k, 1], radius, h, pad, nx, ny)

    boxes(pts, out, radius, h, pad, nx, ny)
    got = out.to_numpy()
    for (cx, cz), (i0, i1, j0, j1) in zip(centres, got):
        lo_i, hi_i = max(int(np.floor((cx - radius) / h)) + pad, 0), min(int(np.ceil((cx + radius) / h)) + pad + 1, nx)
        lo_j, hi_j = max(int(np.floor((cz - radius) / h)) + pad, 0), min(int(np.ceil((cz + radius) / h)) + pad + 1, ny)
        assert (i0, i1, j0, j1) == (lo_i, max(hi_i, lo_i), lo_j, max(hi_j, lo_j))
        nodes_x = (np.arange(nx) - pad) * h  # every node within the radius is in the box
        nodes_z = (np.arange(ny) - pad) * h
        near = (nodes_x[:, None] - cx) ** 2 + (nodes_z[None, :] - cz) ** 2 < radius**2
        inside = np.zeros_like(near)
        inside[i0:i1, j0:j1] = True
        assert not np.any(near & ~inside)
    i0, i1, j0, j1 = got[4]  # a disc off the grid: an empty box (an empty loop)
    assert i1 == i0 and j1 == j0


def test_a_restart_of_a_body_advanced_on_the_device_reproduces_the_run_bit_for_bit(
    tmp_path, run_killed_after_second_checkpoint
):
    # the checkpoint carries the device's pose and the impulse one step back; with exact sums (one
    # grid copy in 64-bit fixed point: the body's impulse too) the resumed run is the uninterrupted one
    def config(name):
        cfg = mpm_config(grousered_wheel_scenario(), quick_settings("wheel"), 60.0, None)
        cfg.backend.p2g_chunks = 1
        cfg.time.t_end = 0.09  # the wheel, half a cell above the bed, lands at ~0.05 s (contact at its surface)
        cfg.output.directory = str(tmp_path / name)
        cfg.output.record_every = 0.005
        cfg.output.checkpoint_every = 0.015
        return cfg

    full = Solver(config("full"))
    assert full.intruders[0].on_device and full.fixed_scale is not None
    full.run()
    ckpt_steps = run_killed_after_second_checkpoint(config("killed"))
    resumed = Solver.resume(tmp_path / "killed")
    assert resumed.step_count == 2 * ckpt_steps
    resumed.run()
    np.testing.assert_array_equal(_body(resumed), _body(full))
    assert _body(full)[0] > 0.161  # it rolled
    a, b = resumed.particles.to_numpy(["x", "v", "sigma"]), full.particles.to_numpy(["x", "v", "sigma"])
    for key in a:
        np.testing.assert_array_equal(a[key], b[key], err_msg=key)
    assert [r["fx"] for r in resumed.rows] == [r["fx"] for r in full.rows]
