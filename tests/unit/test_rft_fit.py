"""Li-form fit of a measured alpha map, and RFT coefficient tables other than the generic one."""

import json

import numpy as np
import pytest

from intrusim import geometry as g
from intrusim._checks import InputError
from intrusim.analysis.rft_fit import X_TERMS, Z_TERMS, fit_li_form, scale_to, write_coefficients
from intrusim.forces import make_force_model
from intrusim.kinematics import BodyState
from intrusim.laws.rft import LI2013, N_PER_CM3, alpha, alpha_fit, load_coefficients
from intrusim.scenarios import get_scenario

GRID = np.radians(np.arange(-90, 91, 30.0))
B, G = (a.ravel() for a in np.meshgrid(GRID[1:], GRID))  # beta = -90 is beta = 90


def random_table(seed):
    rng = np.random.default_rng(seed)
    t = np.zeros((4, 3, 2))
    for k, m, n in Z_TERMS + X_TERMS:
        t[k, m + 1, n] = rng.uniform(-0.3, 0.3)
    return t


def test_fit_recovers_the_generic_table_from_its_own_map():
    ax, az = alpha(B, G)
    coef, info = fit_li_form(B, G, ax, az)
    assert np.allclose(coef, LI2013, atol=1e-12)
    assert info["rms_z"] < 1e-6 and info["rms_x"] < 1e-6 and info["points"] == 42
    assert scale_to(0.35 * LI2013, LI2013) == pytest.approx(0.35)


def test_fit_residual_reports_what_the_form_cannot_hold():
    ax, az = alpha(B, G)
    bump = np.where((B == 0) & (G == 0), 5e4, 0.0)  # one point off the form, N/m^3
    _, info = fit_li_form(B, G, ax, az + bump)
    assert 1e4 < info["max_z"] < 5e4 and info["rms_x"] < 1e-6


def test_fit_needs_a_map_that_determines_every_term():
    with pytest.raises(InputError, match="rank"):
        fit_li_form(B[G == 0], G[G == 0], *alpha(B[G == 0], G[G == 0]))
    with pytest.raises(InputError, match="same length"):
        fit_li_form(B, G[:-1], *alpha(B, G))
    with pytest.raises(InputError, match="non-finite"):
        fit_li_form(B, G, np.full_like(B, np.nan), B)


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_any_li_form_table_extends_continuously_past_the_fitted_range(seed):
    t = random_table(seed)
    b = np.linspace(-1.5, 1.5, 31)
    for edge in (0.5 * np.pi, -0.5 * np.pi):
        inside = np.array(alpha(b, edge - 1e-7 * np.sign(edge), coef=t))
        outside = np.array(alpha(b, edge + 1e-7 * np.sign(edge), coef=t))
        assert np.allclose(inside, outside, atol=1e-6 * N_PER_CM3)


def test_force_model_uses_its_table_on_both_paths():
    wheel = g.grousered_wheel(grouser_height_scale=1 / 3)
    st = BodyState(0.0, 0.07, 0.3, 0.2, -0.05, -4.0)
    doubled = make_force_model("drft", wheel, xi=0.35, coef=2 * LI2013, structural="wheel-rear-half")
    scaled = make_force_model("drft", wheel, xi=0.70, structural="wheel-rear-half")
    assert np.allclose(doubled.wrench(st).as_array(), scaled.wrench(st).as_array(), rtol=1e-12)
    rft2 = make_force_model("rft", wheel, xi=0.35, coef=2 * LI2013)
    assert np.allclose(rft2.wrench_numpy(st).as_array(), make_force_model("rft", wheel, xi=0.7).wrench(st).as_array())
    other = make_force_model("drft", wheel, xi=1.0, coef=random_table(4), structural="wheel-rear-half-effective")
    assert np.allclose(other.wrench(st).as_array(), other.wrench_numpy(st).as_array(), rtol=1e-9, atol=1e-9)
    assert not np.allclose(doubled.wrench(st).as_array(), other.wrench(st).as_array())
    with pytest.raises(InputError, match="shape"):
        make_force_model("rft", wheel, coef=np.ones((4, 3)))


def test_coefficient_file_round_trip_and_scenario(tmp_path):
    t = random_table(5)
    path = write_coefficients(tmp_path / "map.json", t, {"source": "test"})
    assert np.allclose(load_coefficients(path), t)
    sc = get_scenario("wheel")
    sc.force_model.rft_coefficients = str(path)
    model = sc.build_model("rft")
    assert np.allclose(model.coef, t)
    assert alpha_fit(0.2, 0.4, t)[1] == pytest.approx(alpha(0.2, 0.4, coef=t)[1] / N_PER_CM3)
    (tmp_path / "bad.json").write_text(json.dumps({"units": "N/m^3", "A": {"0,0": 1.0}}))
    with pytest.raises(InputError, match="N/cm"):
        load_coefficients(tmp_path / "bad.json")
    with pytest.raises(InputError, match="not found"):
        load_coefficients(tmp_path / "missing.json")
    for text, match in (("{not json", "not valid JSON"), ('{"A": {"2,0": 1.0}}', "outside"),
                        ('{"A": {"0,0": "x"}}', "to a number"), ("[1, 2]", "no coefficient blocks")):  # fmt: skip
        (tmp_path / "bad.json").write_text(text)
        with pytest.raises(InputError, match=match):
            load_coefficients(tmp_path / "bad.json")


def test_interpolated_map_holds_its_points_and_the_mirror():
    from intrusim.analysis.rft_fit import interpolated_map

    ax, az = alpha(B, G)
    fn = interpolated_map(B, G, ax, az)
    assert np.allclose(np.array(fn(B, G)), np.array([ax, az]), rtol=1e-9, atol=1e-3)  # N/m^3
    assert np.allclose(
        np.array(fn(-0.5 * np.pi + 0 * G, G)), np.array(alpha(0.5 * np.pi, G)), atol=1e-3
    )  # beta -90 = 90
    rng = np.random.default_rng(0)
    b, g = rng.uniform(-1.5, 1.5, 200), rng.uniform(-np.pi, np.pi, 200)
    x, z = fn(b, g)
    mx, mz = fn(-b, np.pi - g)  # the mirror image x -> -x
    assert np.allclose(mx, -x) and np.allclose(mz, z)
    ex, ez = alpha(b, g)  # linear interpolation of the generic map on a 30 degree grid
    scale = np.abs(np.concatenate([ex, ez])).max()
    assert np.abs(np.concatenate([x - ex, z - ez])).max() < 0.1 * scale
    with pytest.raises(InputError, match="every"):
        interpolated_map(B[1:], G[1:], ax[1:], az[1:])
    with pytest.raises(InputError, match="span"):
        interpolated_map(B[G > -1.0], G[G > -1.0], ax[G > -1.0], az[G > -1.0])
