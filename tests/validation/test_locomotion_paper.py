"""The paper's locomotion claims, as assertions on computed curves (Fig 4B, 5A-B, 7B-C, S2).

Results that do not come out of the model are reported in docs/locomotion.md, not weakened here.
"""

import numpy as np
import pytest

from intrusim.analysis.plates import fit_static_plus_inertial
from intrusim.analysis.steady import run_until_steady
from intrusim.analysis.sweep import sweep_omega
from intrusim.bodies import Drive
from intrusim.forces import make_force_model
from intrusim.geometry import circle
from intrusim.scenarios import drag_force_table, get_scenario

RPM = 2 * np.pi / 60


@pytest.fixture(scope="module")
def wheel():
    return get_scenario("wheel")


def test_quasistatic_rft_round_wheel_v_proportional_to_omega(wheel):
    """Supplement S2: for a ROUND body, RFT steady states at (c V, c omega) and (V, omega) coincide.

    The residual spread comes from the discretisation: elements crossing the free surface or
    switching the leading-edge rule make the force jump, and the discrete steady state dithers
    about those jumps (the impulse a stalled step leaves is made up by the next, bodies.Carry), its
    2-revolution means wandering by ~3e-5 at 90 RPM: the window is 8 revolutions.
    """
    shape = circle(wheel.radius, wheel.width, 1440)
    model = make_force_model("rft", shape, xi=wheel.force_model.xi)
    body = wheel.rigid_body()
    run = wheel.run.model_copy(update={"drift_tol": 1e-5, "dt_max": 0.004, "average_revolutions": 8})
    ratios, sinks = [], []
    for rpm in (10.0, 30.0, 60.0, 90.0):
        st = run_until_steady(model, shape, body, Drive(-rpm * RPM, run.ramp_time), wheel.initial_state(shape), run)
        assert st.settled
        ratios.append(st.velocity / st.omega)
        sinks.append(st.sinkage)
    ratios, sinks = np.array(ratios), np.array(sinks)
    assert np.ptp(ratios) / ratios.mean() < 1e-3, ratios
    assert np.ptp(sinks) < 5e-5, sinks  # same sinkage, to 0.05 mm


def test_drft_wheel_slows_and_sinks_past_30_rpm(wheel):
    """Fig 5A-B: with DRFT, v/(r omega) falls as omega grows past ~30 RPM and sinkage rises, up to 60 RPM.

    Past 60 RPM the converged model (BDF2 at the default step, within 0.2 % of dt -> 0) stays flat:
    v/(r omega) 0.718 -> 0.713 and sinkage 43.03 -> 43.02 mm at 60 -> 90 RPM, where the paper's
    keeps changing (docs/locomotion.md). The former step (backward Euler, 100 steps a revolution)
    showed a rise of 0.24 mm there that was its own phase-locking error.
    """
    res = sweep_omega(wheel, "drft", [10.0, 30.0, 60.0, 90.0], parallel=False, progress=False)
    v_ratio = 1 - res.column("slip")
    sink = res.column("sinkage")
    assert np.all(np.diff(v_ratio[1:]) < 0.0), v_ratio  # strictly falling past 30 RPM ...
    assert v_ratio[1] - v_ratio[2] > 0.02, v_ratio  # ... mostly from 30 to 60 RPM
    assert sink[2] - sink[1] > 5e-4, sink  # sinks 0.5 mm more (0.8 mm) from 30 to 60 RPM ...
    assert abs(sink[3] - sink[2]) < 1e-4, sink  # ... then stays within 0.1 mm (0.01 mm) to 90 RPM
    rft = sweep_omega(wheel, "rft", [10.0, 90.0], parallel=False, progress=False)
    # quasistatic RFT: slip nearly constant (the grousers make the wheel non-round: not exact)
    assert abs(np.diff(rft.column("slip"))[0]) < 0.01
    assert v_ratio[-1] < 1 - rft.column("slip")[-1] - 0.05  # DRFT is clearly slower at 90 RPM


def test_inertial_correction_alone_lowers_sinkage(wheel):
    """Fig 4B: lambda rho v^2 alone makes the wheel ride higher as lambda grows (the wrong trend)."""
    sinks = [sweep_omega(wheel, "drft-inertial", [90.0], lam=lam, parallel=False, progress=False).column("sinkage")[0]
             for lam in (0.0, 1.0, 25.0, 100.0)]  # fmt: skip
    assert np.all(np.diff(sinks) < 0.0), sinks


def test_runner_faster_and_higher_at_high_spin():
    """Fig 7B-C: runner, DRFT lambda = 4: past omega/omega0 ~ 1.2 slip and sinkage fall."""
    r = get_scenario("runner")
    rpm = np.array([100.0, 150.0, 200.0, 300.0])
    assert rpm[0] * RPM / r.omega_0 > 1.2
    res = sweep_omega(r, "drft", rpm, lam=4.0, parallel=False, progress=False)
    v_ratio, sink = 1 - res.column("slip"), res.column("sinkage")
    assert np.all(np.diff(v_ratio) > 0.0), v_ratio
    assert np.all(np.diff(sink) < 0.0), sink
    assert np.all(np.diff(res.column("velocity")) > 0.0)
    lam0 = sweep_omega(r, "drft", [300.0], lam=0.0, parallel=False, progress=False)
    assert sink[-1] < lam0.column("sinkage")[0]  # lambda rho v^2 lifts the runner


def test_plate_drag_follows_static_plus_inertial_law():
    """Fig 6A: DRFT plate drag is exactly K|z| + lambda rho A v^2 with the lambda put in."""
    s = get_scenario("plate-drag")
    f = drag_force_table(s, "drft")
    K, lam = fit_static_plus_inertial(np.array(s.depths), np.array(s.speeds), f, s.force_model.rho, s.area)
    assert lam == pytest.approx(s.force_model.lam, rel=1e-9)
    model = np.outer(s.depths, np.ones(len(s.speeds))) * K + lam * s.force_model.rho * s.area * np.array(s.speeds) ** 2
    assert np.allclose(f, model, rtol=1e-9)
    # RFT's own K: alpha_x of a vertical plate moving horizontally, times its length (per metre)
    rft = make_force_model("rft", s.rft_shape(), xi=s.force_model.xi)
    fx = -rft.wrench(s.state(0.03, 0.1)).fx
    assert K == pytest.approx(fx / 0.03, rel=1e-9)


@pytest.mark.parametrize("name", ["wheel", "small-wheel"])
def test_at_10_rpm_the_papers_drft_is_quasistatic_rft(name):
    """At 10 RPM the structural drop r (r omega^2 / g) is 1.3 mm (large wheel), 0.3 mm (small).

    So the paper's DRFT, with either reading of its rear zone, is quasistatic RFT there: v within
    0.5 % and sinkage within 0.2 mm. The 10 RPM misses against every MPM we ran (18 mm of sinkage
    with the contact band, +51 % in v without it; docs/results.md) are RFT's, which no reading of
    the structural correction can move.
    """
    sc = get_scenario(name)
    assert sc.force_model.structural == "wheel-rear-half" and sc.force_model.psi_slope == 1.0
    dh = sc.radius * (sc.radius * (10.0 * RPM) ** 2 / sc.gravity)
    assert dh < 1.4e-3
    rft = sweep_omega(sc, "rft", [10.0], parallel=False, progress=False)
    for structural in ("wheel-rear-half", "wheel-rear-half-effective"):
        fm = sc.force_model.model_copy(update={"structural": structural})
        drft = sweep_omega(sc.model_copy(update={"force_model": fm}), "drft", [10.0], parallel=False, progress=False)
        assert drft.column("velocity")[0] == pytest.approx(rft.column("velocity")[0], rel=5e-3), structural
        assert abs(drft.column("sinkage")[0] - rft.column("sinkage")[0]) < 2e-4, structural
