"""Bad configs fail before any compute, naming the parameter."""

import pytest
from pydantic import ValidationError

from intrusim.mpm.config import (
    BedConfig,
    DomainConfig,
    IntruderConfig,
    MaterialConfig,
    MPMConfig,
    Rectangle,
    WallConfig,
)


@pytest.mark.parametrize(
    "build, name",
    [
        (lambda: MaterialConfig(rho_c=0.0), "rho_c"),
        (lambda: MaterialConfig(mu_s=-0.1), "mu_s"),
        (lambda: MaterialConfig(youngs_modulus=-1.0), "youngs_modulus"),
        (lambda: MaterialConfig(poisson_ratio=0.5), "poisson_ratio"),
        (lambda: DomainConfig(size=(1.0, -1.0)), "size"),
        (lambda: DomainConfig(size=(1.0, 1.0), cells=(100, 50)), "cells must be square"),
        (lambda: WallConfig(kind="coulomb", mu=-1), "mu"),
        (lambda: IntruderConfig(vertices=[(0, 0), (1, 0), (0, 1)], width=0.0), "width"),
        (lambda: IntruderConfig(vertices=[(0, 0), (1, 0), (0, 1)], mu_w=-0.2), "mu_w"),
        (lambda: Rectangle(x0=1, z0=0, x1=0, z1=1), "x1 > x0"),
        (lambda: MPMConfig(bed=BedConfig(rectangles=[Rectangle(x0=0, z0=0, x1=2, z1=0.5)])), "outside the domain"),
        (lambda: MPMConfig(gravity=(0.0, -9.8), unknown_key=1), "unknown_key"),
        (lambda: MaterialConfig(rho_floor_fraction=1.0), "rho_floor_fraction"),
        (
            lambda: MPMConfig(bed=BedConfig(rectangles=[Rectangle(x0=0, z0=0, x1=1, z1=0.5)], density_ratio=0.05)),
            "below material.rho_floor_fraction",
        ),
    ],
)
def test_bad_config_names_the_parameter(build, name):
    with pytest.raises(ValidationError) as err:
        build()
    assert name in str(err.value)


def test_derived_elastic_constants():
    m = MaterialConfig(youngs_modulus=2.6e6, poisson_ratio=0.3)
    assert m.shear_modulus == pytest.approx(1.0e6)
    assert m.lame_lambda == pytest.approx(2.6e6 * 0.3 / (1.3 * 0.4))
