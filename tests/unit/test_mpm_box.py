"""The MPM box sizes itself to the body; a box set by hand that cannot hold it is refused naming the limit."""

import pytest

from intrusim._checks import InputError
from intrusim.scenarios import get_scenario, load_scenario
from intrusim.scenarios.mpm_locomotion import base_settings, mpm_config
from intrusim.scenarios.mpm_settings import body_settings, case_settings

SHIPPED = ["wheel", "small-wheel", "runner", "wheel-10-grousers", "wheel-30-grousers", "wheel-tall-grousers"]


@pytest.mark.parametrize("quick", [True, False])
@pytest.mark.parametrize("name", SHIPPED)
def test_a_shipped_body_keeps_its_box(name, quick):
    s = get_scenario(name)
    if name == "wheel-tall-grousers" and quick:  # its quick box is too low: grown (the reference set adds 6 cm)
        assert body_settings(s, quick, echo=False).domain[1] > base_settings(s.body, quick, s.mpm_scale).domain[1]
        return
    assert body_settings(s, quick, echo=False) == base_settings(s.body, quick, s.mpm_scale)


def _wheel(tmp_path, hub=0.2, lug=0.015):
    p = tmp_path / "my_wheel.toml"
    p.write_text(
        f'body = "wheel"\nhub_diameter = {hub}\nlug_height = {lug}\nlug_width = 0.008\nlug_count = 12\n'
        "width = 0.12\nmass_x = 12.0\nmass_z = 5.0\n"
    )
    return load_scenario(p)


def test_a_wheel_too_tall_for_the_quick_box_gets_a_taller_box_of_the_same_cells(tmp_path, capsys):
    sc = _wheel(tmp_path)  # radius 0.115 m: the quick box (0.5 m high, bed 0.25 m) cannot hold it
    base = base_settings("wheel", True)
    with pytest.raises(InputError, match=r"height 0.5 m must be at least .*--set domain="):
        mpm_config(sc, base, 30.0)  # the limit named: the box's height, not start_x
    capsys.readouterr()
    s = body_settings(sc, True)
    assert "box grown" in capsys.readouterr().err
    assert s.h == pytest.approx(base.h) and s.domain[0] == base.domain[0] and s.domain[1] > base.domain[1]
    assert s.domain[1] / s.cells[1] == pytest.approx(s.h)  # square cells
    cfg = mpm_config(sc, s, 30.0)  # fits
    top = cfg.intruders[0].z + sc.radius
    assert top + sc.radius <= s.domain[1] + 1e-9  # a radius of headroom above the body
    # --set over the grown box still applies, and a hand-made box that cannot hold the body is refused at the run
    assert case_settings(sc, True, sets=["t_max=2.0"], echo=False).domain == s.domain


def test_a_wide_body_moves_its_start_and_lengthens_the_bed(tmp_path):
    sc = _wheel(tmp_path, hub=0.3, lug=0.02)  # radius 0.17 m > quick start_x 0.16 m
    base, s = base_settings("wheel", True), body_settings(sc, True, echo=False)
    assert s.start_x - sc.radius >= s.h
    assert s.domain[0] - s.start_x == pytest.approx(base.domain[0] - base.start_x)  # the same run ahead
    mpm_config(sc, s, 30.0)
    with pytest.raises(InputError, match="start_x must be at least its radius plus a cell"):
        mpm_config(sc, s.validated_copy(start_x=0.16), 30.0)


def test_cells_coarser_than_a_fifth_of_the_thinnest_lug_are_warned_of(capsys):
    wheel = get_scenario("wheel")  # 6 mm thick grousers: cells of at most 1.2 mm resolve them
    case_settings(wheel, True)
    assert "warning: grousered_wheel: cells of 20 mm are coarser than a fifth" in capsys.readouterr().err
    case_settings(wheel, False)
    assert "cells of 5 mm" in capsys.readouterr().err
    case_settings(wheel, False, sets=["cell_size=0.001"])
    assert "warning" not in capsys.readouterr().err
    case_settings(wheel, True, echo=False)  # a figure's check: silent
    assert capsys.readouterr().err == ""


@pytest.mark.parametrize("name", SHIPPED)
def test_the_reference_route_resolves_each_body_on_a_bed_that_follows_it(name):
    from intrusim.scenarios.mpm_locomotion import check_run, reference_settings, thinnest_feature

    sc = get_scenario(name)
    s = reference_settings(sc)
    assert s.h == pytest.approx(thinnest_feature(sc) / 5)  # a fifth of the thinnest feature
    assert s.fluidity is not None and s.fluidity.grain_diameter == pytest.approx(max(1e-3, 2.5 * s.h))
    assert s.treadmill is not None and s.settle_tol == 0.01 and s.t_max >= 20.0
    assert (
        s.mu_s == base_settings(sc.body, False).mu_s
        and s.youngs_modulus == base_settings(sc.body, False).youngs_modulus
    )
    for rpm in (10.0, 90.0):
        check_run(sc, s, rpm)  # fits, treadmill clear of both walls, the cap long enough to settle


def test_the_reference_preset_is_chosen_by_name_and_bad_names_are_refused(tmp_path):
    wheel = get_scenario("wheel")
    assert case_settings(wheel, False, preset="reference", echo=False).h == pytest.approx(0.0012)
    assert case_settings(wheel, False, preset="quick", echo=False) == case_settings(wheel, True, echo=False)
    with pytest.raises(InputError, match="--preset must be one of paper, quick, reference"):
        case_settings(wheel, False, preset="fast")
    with pytest.raises(InputError, match="--quick and --preset reference"):
        case_settings(wheel, True, preset="reference")
    with pytest.raises(InputError, match="--quick and --preset paper"):  # not silently quick
        case_settings(wheel, True, preset="paper")


def test_the_box_is_fitted_after_the_users_settings_in_the_dimensions_they_left_free(tmp_path):
    wheel = get_scenario("wheel")
    deep = case_settings(wheel, False, sets=["bed_depth=0.85"], echo=False)  # the paper's 1 m box is too low now
    assert deep.domain[1] > 1.0 and deep.h == pytest.approx(0.005)
    mpm_config(wheel, deep, 30.0)
    hand = case_settings(wheel, False, sets=["bed_depth=0.85", "domain=[1.0, 1.0]", "cell_size=0.005"], echo=False)
    assert hand.domain == (1.0, 1.0)  # set by hand: kept, and refused at the run, naming the height
    with pytest.raises(InputError, match=r"height 1 m must be at least bed_depth \+ the body \+ a cell \(1\.07 m"):
        mpm_config(wheel, hand, 30.0)
