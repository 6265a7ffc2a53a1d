"""Rear free-surface measurement (Fig 5C method) and the MP4 writer."""

import numpy as np
import pytest

from intrusim._checks import InputError
from intrusim.analysis.free_surface import (
    polygon_signed_distance,
    rear_contact_drop,
    wake_drop,
)
from intrusim.geometry import circle


def test_signed_distance_square():
    sq = np.array([[0, 0], [1, 0], [1, 1], [0, 1]], float)
    d = polygon_signed_distance(np.array([[0.5, 0.5], [1.5, 0.5], [0.5, -0.2], [0.9, 0.5]]), sq)
    assert d == pytest.approx([-0.5, 0.5, 0.2, -0.1])


def synthetic_bed(dh_rear, r=0.1, cz=0.04, h=0.004):
    """Particles on a grid below z = 0, outside a wheel, with the rear surface lowered by dh_rear.

    Pressure = rho g (local surface - z); a loose grain hovers above the rear surface (P = 0).
    """
    xs, zs = np.meshgrid(np.arange(-0.3, 0.3, h) + h / 2, np.arange(-0.2, 0.0, h) + h / 2)
    pos = np.column_stack([xs.ravel(), zs.ravel()])
    surface = np.where(pos[:, 0] < 0, -dh_rear, 0.0)
    keep = (pos[:, 1] < surface) & (np.hypot(pos[:, 0], pos[:, 1] - cz) > r)
    pos, surface = pos[keep], surface[keep]
    p = 638 * 9.8 * (surface - pos[:, 1])
    # a loose grain touching the wheel's rear, above the rear surface
    zl = -dh_rear + 0.015
    cos_a = (cz - zl) / (r + 0.003)
    loose = np.array([[-(r + 0.003) * np.sqrt(1 - cos_a**2), zl]])
    # the loosened wake under the wheel's rear carries no pressure: it is not the free surface
    wake = (pos[:, 0] < 0) & (pos[:, 0] > -0.06) & (np.hypot(pos[:, 0], pos[:, 1] - cz) < r + 2 * h)
    p[wake] = 0.0
    return np.vstack([pos, loose]), np.append(p, 0.0)


@pytest.mark.parametrize("dh", [0.01, 0.03])
def test_rear_contact_drop_recovers_surface(dh):
    wheel = circle(0.1, 0.1, 256).polygon + [0.0, 0.04]
    pos, p = synthetic_bed(dh)
    h = 0.004
    got = rear_contact_drop(pos, p, wheel, (0.0, 0.04), +1.0, 0.0, band=1.5 * h, pressure_tol=0.5 * 638 * 9.8 * h)
    assert got == pytest.approx(dh, abs=1.5 * h)


def test_rear_contact_drop_no_contact_is_nan():
    wheel = circle(0.1, 0.1, 64).polygon + [0.0, 0.5]
    pos, p = synthetic_bed(0.01)
    assert np.isnan(rear_contact_drop(pos, p, wheel, (0.0, 0.5), 1.0, 0.0, band=0.006, pressure_tol=10.0))


def test_rear_contact_drop_below_surface_only_skips_grains_carried_up():
    """A loaded pile riding up the wheel's rear, above the surface, hides the drop unless skipped."""
    wheel = circle(0.1, 0.1, 256).polygon + [0.0, 0.04]
    pos, p = synthetic_bed(0.02)
    h = 0.004
    angles = np.linspace(np.pi / 2 + 0.2, np.pi / 2 + 0.9, 12)  # rear-upper arc, above z = 0
    pile = np.column_stack([(0.1 + 0.002) * np.cos(angles), 0.04 + (0.1 + 0.002) * np.sin(angles)])
    pos, p = np.vstack([pos, pile]), np.append(p, np.full(len(pile), 638 * 9.8 * 0.01))
    args = (pos, p, wheel, (0.0, 0.04), +1.0, 0.0)
    kw = dict(band=1.5 * h, pressure_tol=0.5 * 638 * 9.8 * h)
    assert rear_contact_drop(*args, **kw) < 0.0  # the pile above the surface
    assert rear_contact_drop(*args, **kw, below_surface_only=True) == pytest.approx(0.02, abs=1.5 * h)


def test_lowest_free_contact_finds_the_wake_not_the_surface():
    """Read literally (lowest pressure-free contact), the rule finds the loosened wake under the wheel."""
    wheel = circle(0.1, 0.1, 256).polygon + [0.0, 0.04]
    pos, p = synthetic_bed(0.01)
    h = 0.004
    got = rear_contact_drop(
        pos, p, wheel, (0.0, 0.04), +1.0, 0.0, band=1.5 * h, pressure_tol=0.5 * 638 * 9.8 * h, rule="lowest_free"
    )
    assert got > 0.04  # deeper than the 1 cm drop: near the wheel's bottom (0.06 m below the surface)
    assert got == pytest.approx(0.06, abs=3 * h)
    with pytest.raises(InputError, match="rule"):
        rear_contact_drop(pos, p, wheel, (0.0, 0.04), +1.0, 0.0, band=h, pressure_tol=1.0, rule="lowest")


def test_wake_drop_strip_behind_the_rear():
    pos = np.array([[-0.50, -0.03], [-0.45, -0.01], [-0.31, -0.02], [-0.2, 0.05], [0.3, 0.1]])
    # forward +x, rear at x = -0.3: the strip 0.05-0.2 m behind holds the first two points
    assert wake_drop(pos, -0.3, 1.0, 0.0, (0.05, 0.2)) == pytest.approx(0.01)
    assert wake_drop(pos, 0.2, -1.0, 0.0, (0.05, 0.2)) == pytest.approx(-0.1)  # travelling -x
    assert np.isnan(wake_drop(pos, -0.3, 1.0, 0.0, (1.0, 2.0)))
    with pytest.raises(InputError, match="width"):
        wake_drop(pos, -0.3, 1.0, 0.0, (0.2, 0.05))


def test_movie_written(tmp_path):
    from intrusim.io.movie import write_movie

    frames = [np.full((32, 48, 3), 10 * i, np.uint8) for i in range(5)]
    out = write_movie(frames, tmp_path / "m.mp4", fps=5)
    assert out.exists() and out.stat().st_size > 100
    assert not (tmp_path / "m.part.mp4").exists()
    with pytest.raises(ValueError, match="no frames"):
        write_movie([], tmp_path / "empty.mp4")
