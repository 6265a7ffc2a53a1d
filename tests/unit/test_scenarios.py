"""Scenario configs: Table S1 defaults, TOML loading, validation, small-wheel scaling."""

from importlib import resources
from pathlib import Path

import numpy as np
import pytest
from cli_helpers import MY_WHEEL

from intrusim._checks import InputError
from intrusim.params import table_s1
from intrusim.scenarios import get_scenario, load_scenario


def test_wheel_defaults_from_table_s1():
    s, t = get_scenario("wheel"), table_s1()["grousered_wheel"]
    assert (s.mass_x, s.mass_z) == (t["effective_horizontal_inertia"], t["effective_vertical_inertia"])
    assert s.rft_shape().outer_diameter == pytest.approx(t["outer_diameter"], abs=5e-4)
    assert s.radius == pytest.approx(0.5 * t["outer_diameter"])
    assert s.force_model.structural == "wheel-rear-half" and s.force_model.lam == 1.0
    assert np.sqrt(s.gravity * s.length_scale) == pytest.approx(
        t_scale := table_s1()["scales"]["wheel_velocity_scale"], rel=2e-3
    )
    assert s.omega_0 * 60 / (2 * np.pi) == pytest.approx(table_s1()["scales"]["wheel_omega_0_rpm"], rel=0.01)
    del t_scale


def test_small_wheel_is_half_size_with_eighth_mass():
    big, small = get_scenario("wheel"), get_scenario("small-wheel")
    assert small.rft_shape().outer_diameter == pytest.approx(0.5 * big.rft_shape().outer_diameter)
    assert small.width == pytest.approx(0.5 * big.width)
    assert small.mass_x == pytest.approx(big.mass_x / 8) and small.mass_z == pytest.approx(big.mass_z / 8)


def test_runner_mass_ratio_is_as_printed_not_6():
    r = get_scenario("runner")
    ratio = r.mass_z / (r.force_model.rho * r.length_scale**2 * r.width)
    assert ratio == pytest.approx(0.46, abs=0.01)  # the paper says ~6: documented inconsistency
    assert r.force_model.structural == "none"


def test_toml_partial_override(tmp_path):
    p = tmp_path / "w.toml"
    p.write_text(
        'body = "wheel"\nname = "heavy"\nmass_z = 12.0\n[force_model]\nlam = 2.0\n[run]\naverage_revolutions = 1\n'
    )
    s = load_scenario(p)
    assert s.name == "heavy" and s.mass_z == 12.0 and s.force_model.lam == 2.0 and s.run.average_revolutions == 1
    assert s.force_model.xi == 0.35 and s.mass_x == 23.0  # untouched defaults kept


def test_toml_table_path_is_relative_to_the_toml(tmp_path, monkeypatch):
    """force_model.rft_coefficients in a TOML is read from the TOML's folder, whatever the working folder."""
    (tmp_path / "cases" / "tables").mkdir(parents=True)
    src = resources.files("intrusim.data") / "rft_li2013.toml"  # the generic table, copied where the TOML points
    (tmp_path / "cases" / "tables" / "t.toml").write_bytes(src.read_bytes())
    p = tmp_path / "cases" / "w.toml"
    p.write_text('body = "wheel"\n[force_model]\nrft_coefficients = "tables/t.toml"\n')
    monkeypatch.chdir(tmp_path)  # not the TOML's folder
    s = load_scenario("cases/w.toml")
    assert s.force_model.rft_coefficients == str(Path("cases/tables/t.toml"))
    s.build_model("rft")  # reads the table: found from tmp_path
    absolute = tmp_path / "cases" / "tables" / "t.toml"
    p.write_text(f'body = "wheel"\n[force_model]\nrft_coefficients = "{absolute.as_posix()}"\n')
    assert load_scenario(p).force_model.rft_coefficients == absolute.as_posix()


@pytest.mark.parametrize(
    "text, field",
    [("mass_z = -1.0", "mass_z"), ("typo_field = 3", "typo_field"), ("[force_model]\nstructural = 'front'", "structural"),
     ("lug_count = 400", "overlap")],
)  # fmt: skip
def test_toml_errors_name_the_field(tmp_path, text, field):
    p = tmp_path / "bad.toml"
    p.write_text('body = "wheel"\n' + text + "\n")
    with pytest.raises(InputError, match=field):
        load_scenario(p)


def test_a_body_file_must_say_its_body(tmp_path):
    p = tmp_path / "w.toml"
    p.write_text("mass_z = 3.0\n")
    with pytest.raises(InputError, match="body is required"):
        load_scenario(p)


def test_a_body_file_is_named_after_itself_and_derives_its_length_scale(tmp_path):
    p = tmp_path / "my_wheel.toml"
    p.write_text(MY_WHEEL)
    s = load_scenario(p)
    assert s.name == "my_wheel"  # not the shipped "grousered_wheel"
    assert s.length_scale == pytest.approx(0.2 + 2 * 0.015)  # the outer diameter, not Table S1's 0.212 m
    assert s.radius == pytest.approx(0.115)
    p.write_text(MY_WHEEL + "length_scale = 0.3\nname = 'w12'\n")  # given: kept
    s = load_scenario(p)
    assert s.name == "w12" and s.length_scale == 0.3
    # a shipped body is not changed: its l is Table S1's outer diameter, the same number
    assert get_scenario("wheel").length_scale == pytest.approx(0.212)


def test_a_body_file_says_its_effective_body_and_the_defaults_it_took(tmp_path, capsys):
    from intrusim.scenarios.locomotor import describe_body, effective_body

    p = tmp_path / "lean.toml"
    p.write_text('body = "wheel"\nlug_count = 12\nmass_z = 5.0\n')  # no hub_diameter: Table S1's, said so
    s = load_scenario(p)
    said = capsys.readouterr().err
    assert "hub_diameter = 0.188 m *" in said and "taken from the Table S1 wheel" in said
    assert "lug_count = 12," in said and "mass_z = 5 kg," in said  # given: no star
    assert "length_scale = 0.212 m (= hub_diameter + 2 lug_height)" in said
    load_scenario(p)
    assert capsys.readouterr().err == ""  # said once per file
    assert {"hub_diameter", "lug_height", "mass_x"} <= set(s.defaulted) and "lug_count" not in s.defaulted
    body = effective_body(s)
    assert body["name"] == "lean" and body["hub_diameter"] == 0.188 and body["units"]["mass_z"] == "kg"
    assert "hub_diameter" in body["defaulted"]
    assert describe_body(get_scenario("wheel")).count("*") == 0  # a shipped body took no defaults


def test_unsupported_model_kind():
    s = get_scenario("wheel").model_copy(update={"supported_models": ("rft",)})
    with pytest.raises(InputError, match="supports"):
        s.build_model("drft")
    with pytest.raises(InputError, match="unknown scenario"):
        get_scenario("tank")


def test_mpm_forward_push_is_table_s1_for_the_wheel_and_scales_with_mass():
    from intrusim.scenarios import four_flap_runner_scenario, grousered_wheel_scenario, small_wheel_scenario
    from intrusim.scenarios.mpm_locomotion import forward_force, paper_settings

    wheel = paper_settings("wheel")
    assert forward_force(grousered_wheel_scenario(), wheel) == pytest.approx(4.0)  # Table S1
    assert forward_force(small_wheel_scenario(), wheel) == pytest.approx(4.0 / 8)  # mass x 1/8
    assert forward_force(four_flap_runner_scenario(), paper_settings("runner")) == 0.0
    assert forward_force(small_wheel_scenario(), wheel.model_copy(update=dict(forward_force=2.0))) == 2.0


def test_without_lugs_keeps_the_outer_radius():
    import pytest

    from intrusim._checks import InputError
    from intrusim.scenarios import get_scenario
    from intrusim.scenarios.locomotor import without_lugs

    wheel = get_scenario("wheel")
    smooth = without_lugs(wheel)
    assert smooth.radius == pytest.approx(wheel.radius) and smooth.lug_height == 0.0005
    from intrusim.geometry import TAG_LUG_SIDE

    def sides(sc):  # RFT area of the grousers' sides; the tips stay on the outer surface
        e = sc.rft_shape().elements
        return e.area[e.tag == TAG_LUG_SIDE].sum()

    assert sides(smooth) < 0.1 * sides(wheel)
    with pytest.raises(InputError):
        without_lugs(wheel, stub=0.5)


def test_with_lug_count_changes_only_the_lug_count_and_checks_the_fit():
    from pydantic import ValidationError

    from intrusim.geometry import TAG_LUG_TIP
    from intrusim.scenarios.locomotor import with_lug_count

    wheel = get_scenario("wheel")
    thirty = with_lug_count(wheel, 30)
    assert thirty.lug_count == 30 and thirty.name == "grousered_wheel_30lugs"
    assert thirty.model_dump(exclude={"lug_count", "name"}) == wheel.model_dump(exclude={"lug_count", "name"})
    tips = thirty.rft_shape().elements.tag == TAG_LUG_TIP
    assert tips.sum() == 30 * (wheel.rft_shape().elements.tag == TAG_LUG_TIP).sum() // 20
    with pytest.raises((ValidationError, InputError)):
        with_lug_count(wheel, 200)  # 200 grousers of 6 mm do not fit on a 94 mm hub


def test_with_mass_z_changes_only_the_load_and_refuses_a_non_positive_mass():
    from pydantic import ValidationError

    from intrusim.scenarios.locomotor import with_mass_z

    wheel = get_scenario("wheel")
    light = with_mass_z(wheel, 3.15)
    assert light.mass_z == 3.15 and light.name == wheel.name  # the same body: run folders keep their names
    assert light.model_dump(exclude={"mass_z"}) == wheel.model_dump(exclude={"mass_z"})
    assert light.rigid_body().weight == pytest.approx(3.15 * wheel.gravity)
    for bad in (0.0, -1.0):
        with pytest.raises((ValidationError, InputError)):
            with_mass_z(wheel, bad)


def test_load_scenario_takes_the_small_wheel_spelt_either_way():
    assert load_scenario("small_wheel") == load_scenario("small-wheel") == get_scenario("small-wheel")
    with pytest.raises(InputError, match="small-wheel"):
        load_scenario("smallwheel")


@pytest.mark.parametrize("name", ["wheel", "runner"])
def test_finer_elements_keeps_the_body_and_its_outline(name):
    """factor x the elements on every rim segment and lug face; the total area, the outline's reach
    and everything but the discretisation unchanged (the rim's polygon gets the finer arcs); a
    factor that is not a whole number >= 1 refused."""
    s = get_scenario(name)
    f = s.finer_elements(3)
    a, b = s.rft_shape(), f.rft_shape()
    assert len(b.elements.area) == 3 * len(a.elements.area)
    assert b.elements.area.sum() == pytest.approx(a.elements.area.sum(), rel=1e-12)
    assert np.hypot(*b.polygon.T).max() == pytest.approx(np.hypot(*a.polygon.T).max(), rel=1e-12)
    assert np.hypot(*b.polygon.T).min() == pytest.approx(np.hypot(*a.polygon.T).min(), rel=1e-3)
    assert f.model_dump(exclude={"hub_elements_per_segment", "lug_elements_per_face"}) == s.model_dump(
        exclude={"hub_elements_per_segment", "lug_elements_per_face"}
    )
    for bad in (0, 1.5, True):
        with pytest.raises(InputError):
            s.finer_elements(bad)


def test_finer_steps_runs_a_given_step_divided():
    """About dt / factor at that omega (at most that: the step rule puts k + 0.618 steps in a pitch),
    averaged over the revolutions asked."""
    s = get_scenario("wheel")
    omega = 30.0 * 2.0 * np.pi / 60.0
    dt = s.run.dt(omega, s.lug_count)
    f = s.finer_steps(dt, omega, 16, revolutions=8)
    assert dt / 16 * (1 - 1e-2) < f.run.dt(omega, s.lug_count) <= dt / 16 * (1 + 1e-12)
    assert f.run.average_revolutions == 8 and f.model_dump(exclude={"run"}) == s.model_dump(exclude={"run"})
    with pytest.raises(InputError):
        s.finer_steps(dt, omega, 0)
