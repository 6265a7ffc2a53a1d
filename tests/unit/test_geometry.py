"""Unit tests of intruder shapes and their surface elements."""

import numpy as np
import pytest

from intrusim import geometry as g
from intrusim._checks import InputError


def closure_checks(els, area):
    # divergence theorem on a closed curve: sum n dl = 0 and sum (r . n) dl = 2 A
    assert np.allclose((els.normal * els.length[:, None]).sum(axis=0), 0.0, atol=1e-9)
    assert np.sum(np.einsum("ij,ij->i", els.midpoint, els.normal) * els.length) == pytest.approx(2 * area, rel=2e-3)


def test_paper_wheel_element_counts():
    assert len(g.grousered_wheel().elements) == 760  # Table S1: 20 grousers
    assert len(g.grousered_wheel(grouser_count=15).elements) == 570  # the paper's quoted count
    assert g.element_count_for_wheel(20) == 760


def hub_area(r, h, w, n):
    half = np.arcsin(0.5 * w / r)
    base = np.sqrt(r * r - 0.25 * w * w)
    segment = 0.5 * r * r * (2 * half - np.sin(2 * half))  # hub cap covered by the lug
    return np.pi * r * r + n * (w * (r + h - base) - segment)


def test_wheel_dimensions_and_outline():
    w = g.grousered_wheel()
    assert w.radius == pytest.approx(0.106)
    assert w.outer_diameter == pytest.approx(0.212, abs=1e-3)
    assert g.signed_area(w.polygon) > 0 and not g.self_intersections(w.polygon)
    area = hub_area(0.094, 0.012, 0.006, 20)
    assert g.signed_area(w.polygon) == pytest.approx(area, rel=2e-3)
    closure_checks(w.elements, area)
    assert np.all(np.einsum("ij,ij->i", w.elements.midpoint, w.elements.normal) > 0)  # outward


def test_grouser_shadowing_scales_elements_only():
    w = g.grousered_wheel(grouser_height_scale=1 / 3)
    r = np.linalg.norm(w.elements.midpoint, axis=1)
    assert r.max() == pytest.approx(np.hypot(0.094 + 0.004, 0.0), abs=5e-4)
    assert w.outer_diameter == pytest.approx(0.212, abs=1e-3)  # outline keeps the true height


def test_runner():
    r = g.four_flap_runner()
    assert r.radius == pytest.approx(0.095) and r.width == 1.0
    closure_checks(r.elements, hub_area(0.025, 0.070, 0.014, 4))


def test_plate_faces():
    p = g.plate(0.016, 0.1, angle=0.3, n_elements=5)
    assert len(p.elements) == 10
    assert np.allclose(p.elements.normal[:5], -p.elements.normal[5:])
    assert p.elements.area.sum() == pytest.approx(2 * 0.016 * 0.1)


def test_polygon_orientation_and_elements():
    square_cw = [[0, 0], [0, 1], [1, 1], [1, 0]]
    s = g.polygon_shape(square_cw, width=1.0, element_size=0.25)
    assert g.signed_area(s.polygon) == pytest.approx(1.0)
    assert len(s.elements) == 16
    closure_checks(s.elements, 1.0)


@pytest.mark.parametrize(
    "points,match",
    [
        ([[0, 0], [1, 1], [1, 0], [0, 1]], "self-intersecting"),
        ([[0, 0], [1, 1]], "at least 3"),
        ([[0, 0], [1, 0], [2, 0]], "zero area"),
        ([[0, 0], [1, 0], [np.nan, 1]], "non-finite"),
        ([[0, 0], [0, 0], [1, 1]], "zero-length"),
    ],
)
def test_bad_polygons(points, match):
    with pytest.raises(InputError, match=match):
        g.polygon_shape(points, width=1.0)


@pytest.mark.parametrize(
    "kwargs,name",
    [
        (dict(inner_diameter=-0.1), "inner_diameter"),
        (dict(grouser_height=float("nan")), "lug_height"),
        (dict(grouser_count=0), "lug_count"),
        (dict(width=0.0), "width"),
        (dict(rim_elements_per_segment=0), "hub_elements_per_segment"),
        (dict(grouser_count=200), "overlap"),
    ],
)
def test_bad_wheels(kwargs, name):
    with pytest.raises(InputError, match=name):
        g.grousered_wheel(**kwargs)


def test_zero_elements_rejected():
    with pytest.raises(InputError, match="at least one"):
        g.SurfaceElements(np.zeros((0, 2)), np.zeros((0, 2)), np.zeros(0), 1.0)
