"""Force models: compiled vs NumPy path, symmetries, leading edge, hand formulas."""

import numpy as np
import pytest

from intrusim import geometry as g
from intrusim._checks import InputError
from intrusim.forces import ResistiveForceModel, make_force_model
from intrusim.kinematics import BodyState

WHEEL = g.grousered_wheel(grouser_height_scale=1 / 3)
KINDS = ["rft", "drft-inertial", "drft"]


def random_states(n, seed=0):
    rng = np.random.default_rng(seed)
    for _ in range(n):
        yield BodyState(rng.uniform(-1, 1), rng.uniform(0.04, 0.12), rng.uniform(-3, 3),
                        rng.uniform(-1, 1), rng.uniform(-0.3, 0.3), rng.uniform(-12, 12))  # fmt: skip


@pytest.mark.parametrize("width", [0.0, 0.3])
@pytest.mark.parametrize("structural", ["wheel-rear-half", "wheel-rear-half-effective", "wheel-rear-half-circle"])
@pytest.mark.parametrize("kind", KINDS)
def test_compiled_matches_numpy_laws(kind, structural, width):
    m = make_force_model(kind, WHEEL, structural=structural, zone_width=width)
    for st in random_states(300):
        a, b = m.wrench(st).as_array(), m.wrench_numpy(st).as_array()
        assert np.allclose(a, b, rtol=1e-9, atol=1e-9 * (1 + np.abs(b).max()))


def test_effective_split_is_stronger_than_submerged_split():
    # same state, dh > 0: ending the contact arc at the lowered rear surface moves the split
    # forward, so more of the wheel sees the lowered surface and the support drops
    st = BodyState(0.0, 0.075, 0.0, 0.4, 0.0, -3 * np.pi)
    sub = make_force_model("drft", WHEEL, structural="wheel-rear-half").wrench(st)
    eff = make_force_model("drft", WHEEL, structural="wheel-rear-half-effective").wrench(st)
    assert eff.fz < 0.9 * sub.fz


def test_circle_split_mid_angle_is_continuous_in_height():
    """The circle split's zone boundary follows the wheel's height smoothly; the effective split's,
    set by the submerged elements' extreme angles, jumps as a lug tip crosses the lowered surface."""
    from intrusim.laws.drft import circle_arc_mid

    r, dh = 0.106, 0.05

    def largest_change(n):  # the largest change of the mid-angle between heights (0.105 - 0.02) / n apart
        mid = np.array([circle_arc_mid(x, r, dh) for x in np.linspace(0.02, 0.105, n + 1)])
        assert np.all(np.isfinite(mid))
        return np.max(np.abs(np.diff(mid)))

    # continuous: the change shrinks with the spacing (as its square root near tangency, where acos is steep)
    assert largest_change(16000) < 0.3 * largest_change(1000) and largest_change(16000) < 0.004
    assert np.isnan(circle_arc_mid(r, r, dh)) and circle_arc_mid(r - 1e-9, r, dh) > 0.0  # just touching: in front
    # hand values: centre at r/2 with dh = r/2: front end acos(1/2) = 60 deg, rear end straight down
    assert circle_arc_mid(0.5 * r, r, 0.5 * r) == pytest.approx(np.pi / 6)
    assert circle_arc_mid(0.5 * r, r, 0.0) == pytest.approx(0.0, abs=1e-15)  # no drop: the arc is symmetric


def test_models_differ_as_they_should():
    st = BodyState(0.0, 0.085, 0.0, 0.3, 0.0, -2 * np.pi)
    rft, inert, drft = (make_force_model(k, WHEEL, structural="wheel-rear-half").wrench(st) for k in KINDS)
    assert inert.fz > rft.fz  # lambda rho v^2 pushes the wheel up (Fig 4B)
    # lowered rear free surface weakens the base the wheel pushes off: less thrust (paper, Fig 5)
    assert drft.fx < 0.8 * inert.fx


def test_body_above_surface_feels_nothing():
    m = make_force_model("drft", WHEEL, structural="wheel-rear-half")
    w = m.wrench(BodyState(0.0, 0.2, 0.4, 0.5, -1.0, -5.0))
    assert (w.fx, w.fz, w.moment) == (0.0, 0.0, 0.0)


@pytest.mark.parametrize("kind", KINDS)
def test_mirrored_body_mirrored_force(kind):
    pts = np.array([[-0.05, -0.02], [0.06, -0.03], [0.02, 0.04], [-0.03, 0.03]])
    body = g.polygon_shape(pts, width=0.1, element_size=0.002)
    mirror = g.polygon_shape(pts * [-1, 1], width=0.1, element_size=0.002)
    m1 = make_force_model(kind, body, structural="none")
    m2 = make_force_model(kind, mirror, structural="none")
    for st in random_states(20, seed=3):
        st = BodyState(st.x, st.z - 0.06, st.theta, st.vx, st.vz, st.omega)
        a, b = m1.wrench(st).as_array(), m2.wrench(st.mirrored()).as_array()
        assert np.allclose(a * [-1, 1, -1], b, atol=1e-9 * (1 + np.abs(a).max()))


def test_trailing_face_of_plate_is_free():
    p = g.plate(0.1, 0.05, n_elements=4)
    top = ResistiveForceModel(
        g.SurfaceElements(p.elements.midpoint[:4], p.elements.normal[:4], p.elements.length[:4], 0.05), lam=2.0
    )
    # top face (normal +z) of a plate moving down is trailing: no force at any depth
    assert top.wrench(BodyState(0, -0.05, 0, 0, -1.0, 0)).as_array() == pytest.approx([0, 0, 0])


def test_horizontal_plate_pushed_down_hand_formula():
    L, W, d, v = 0.03, 0.03, 0.02, 0.5
    p = g.plate(L, W, n_elements=10)
    rft = make_force_model("rft", p, xi=0.35)
    assert rft.wrench(BodyState(0, -d, 0, 0, -v, 0)).fz == pytest.approx(0.35e6 * 1.0 * d * L * W)
    dr = make_force_model("drft-inertial", p, xi=0.35, rho=1450.0, lam=1.1)
    assert dr.wrench(BodyState(0, -d, 0, 0, -v, 0)).fz == pytest.approx(0.35e6 * d * L * W + 1.1 * 1450 * v * v * L * W)


def test_quasistatic_rft_is_rate_independent():
    m = make_force_model("rft", WHEEL)
    for st in random_states(10, seed=5):
        fast = BodyState(st.x, st.z, st.theta, 3 * st.vx, 3 * st.vz, 3 * st.omega)
        assert np.allclose(m.wrench(st).as_array(), m.wrench(fast).as_array())


def test_bad_model_kind_and_parameters():
    with pytest.raises(InputError, match="kind"):
        make_force_model("fancy", WHEEL)  # type: ignore[arg-type]
    with pytest.raises(InputError, match="lambda"):
        make_force_model("drft", WHEEL, lam=-1.0)
    with pytest.raises(InputError, match="omega"):
        BodyState(omega=float("nan"))
