"""Plate cases of the MPM RFT map: geometry, validation, the alpha measurement."""

import math

import numpy as np
import pytest

from intrusim._checks import InputError
from intrusim.mpm.config import DEFAULT_CONTACT
from intrusim.mpm.rft_map import PlateMapCase, map_cases, measure_alpha


def test_plate_passes_the_set_depth_at_mid_travel_along_gamma():
    c = PlateMapCase(beta=0.3, gamma=math.radians(60))
    vx, vz = c.velocity
    assert math.atan2(-vz, -vx) == pytest.approx(c.gamma) and math.hypot(vx, vz) == pytest.approx(c.speed)
    x0, z0 = c.start()
    t_half = 0.5 * c.travel / c.speed
    shift = c.grid_offset * c.cell_size  # off the grid lines
    assert x0 + vx * t_half == pytest.approx(0.5 * c.domain[0] + shift)
    assert z0 + vz * t_half == pytest.approx(c.bed_height - c.depth - shift)
    cfg = c.config()
    body = cfg.intruders[0]
    assert body.theta == pytest.approx(-0.3) and cfg.contact_band_cells == 0.0
    assert cfg.domain.cells == (120, 80)
    assert cfg.time.t_end == pytest.approx(c.travel / c.speed + 0.5 * c.ramp_time)


def test_bad_cases_fail_before_compute():
    with pytest.raises(InputError, match="surface"):
        PlateMapCase(beta=math.pi / 2, gamma=-math.pi / 2, depth=0.015)
    with pytest.raises(InputError, match="floor or a side wall"):
        PlateMapCase(beta=0.0, gamma=0.0, travel=0.25)
    with pytest.raises(InputError, match="> 0"):
        PlateMapCase(beta=0.0, gamma=0.0, speed=0.0)
    with pytest.raises(InputError, match="contact must be one of nodes, surface, band"):
        PlateMapCase(beta=0.0, gamma=0.0, contact="nodse")


def test_the_plate_meets_the_grains_through_the_mpm_default_contact():
    assert PlateMapCase(beta=0.0, gamma=0.0).config().contact == DEFAULT_CONTACT == "nodes"
    cfg = PlateMapCase(beta=0.0, gamma=0.0, contact="band", contact_band_cells=0.5).config()
    assert (cfg.contact, cfg.contact_band_cells) == ("band", 0.5)


def test_map_counts_the_vertical_plate_once():
    cases = map_cases(np.radians([-90, 0, 90]), np.radians([0, 90]))
    assert len(cases) == 4


def test_alpha_is_force_over_length_and_current_depth():
    c = PlateMapCase(beta=0.0, gamma=math.pi / 2)
    rows = [{"time": t, "fx": 1.0, "fz": 100.0 * (c.bed_height - z), "z": z}
            for t, z in zip(np.linspace(0, 0.3, 31), np.linspace(0.12, 0.10, 31))]  # fmt: skip
    a = measure_alpha(rows, c)
    assert a["alpha_z"] == pytest.approx(100.0 / c.plate_length)
    assert a["alpha_z_std"] == pytest.approx(0.0, abs=1e-9)
    assert a["alpha_x"] > 0 and a["depth_mean"] == pytest.approx(
        np.mean(c.bed_height - np.linspace(0.12, 0.10, 31)[16:])
    )


def test_the_nonlocal_law_is_an_option_of_the_plate():
    assert PlateMapCase(beta=0.0, gamma=math.pi / 2).config().material.fluidity is None  # the paper's law
    cfg = PlateMapCase(beta=0.0, gamma=math.pi / 2, fluidity_diameter=6e-3).config()
    assert cfg.material.fluidity.grain_diameter == pytest.approx(6e-3)
    for bad in (0.0, -1e-3, math.nan):
        with pytest.raises(InputError, match="fluidity_diameter"):
            PlateMapCase(beta=0.0, gamma=0.0, fluidity_diameter=bad)
