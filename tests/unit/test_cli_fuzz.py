"""Property test (hypothesis): an MPM configuration with one field set to a random bad or extreme
value is either refused before compute (exit 2, one line naming the field) or runs to a clean end:
exit 0 with a finite time series, or exit 1 with a guard's diagnosis. Never a traceback or a hang
(the base run is ~130 steps and ``time.max_steps`` caps every accepted run at 2000)."""

import csv
import math
import tempfile
import tomllib
from datetime import timedelta
from pathlib import Path

from cli_helpers import block_config
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from typer.testing import CliRunner

from intrusim.cli import app

runner = CliRunner()

BASE = tomllib.loads(
    "gravity = [0.0, -9.8]\n" + block_config(t_end=0.01, z=0.065).replace("[time]\n", "[time]\nmax_steps = 2000\n", 1)
)

FIELDS = [
    "domain.size.0",
    "domain.cells.1",
    "domain.particles_per_cell",
    "time.t_end",
    "time.cfl",
    "time.dt",
    "time.v_max_expected",
    "material.youngs_modulus",
    "material.rho_c",
    "material.mu_s",
    "material.poisson_ratio",
    "gravity.1",
    "contact_band_cells",
    "bed.density_ratio",
    "bed.rectangles.0.z1",
    "output.record_every",
    "output.checkpoint_every",
    "output.guard_every_steps",
    "intruders.0.width",
    "intruders.0.x",
    "intruders.0.z",
    "intruders.0.theta",
    "intruders.0.mu_w",
    "intruders.0.motion.omega",
    "intruders.0.motion.mass_x",
    "intruders.0.motion.mass_z",
    "intruders.0.motion.external_force.0",
    "intruders.0.vertices.2.1",
]

VALUES = st.one_of(
    st.sampled_from(
        [math.nan, math.inf, -math.inf, 0.0, -1.0, 1e30, -1e30, 1e-30, 1e-300, 1e300, True, False, 0, -3, 10**12]
    ),
    st.floats(allow_nan=True, allow_infinity=True),
    st.integers(min_value=-(10**6), max_value=10**6),
)

GUARDS = ("NaN/inf", "escape", "CFL breach")


def _toml_value(v) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, float):
        return "nan" if math.isnan(v) else ("inf" if v > 0 else "-inf") if math.isinf(v) else repr(v)
    if isinstance(v, int):
        return str(v)
    if isinstance(v, str):
        return '"' + v + '"'
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(_toml_value(x) for x in v) + "]"
    return "{" + ", ".join(f"{k} = {_toml_value(x)}" for k, x in v.items()) + "}"


def _toml(cfg: dict) -> str:
    return "\n".join(f"{k} = {_toml_value(v)}" for k, v in cfg.items()) + "\n"


def _set(cfg: dict, path: str, value) -> dict:
    import copy

    cfg = copy.deepcopy(cfg)
    keys = [int(k) if k.isdigit() else k for k in path.split(".")]
    node = cfg
    for k in keys[:-1]:
        if isinstance(k, str) and k not in node:
            node[k] = {}
        node = node[k]
    node[keys[-1]] = value
    return cfg


@settings(
    max_examples=40, deadline=timedelta(seconds=60), derandomize=True, suppress_health_check=[HealthCheck.too_slow]
)
@given(field=st.sampled_from(FIELDS), value=VALUES)
def test_a_bad_or_extreme_field_is_refused_naming_it_or_runs_cleanly(field, value):
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "c.toml"
        path.write_text(_toml(_set(BASE, field, value)))
        r = runner.invoke(app, ["mpm", "run", str(path), "--out", str(Path(tmp) / "run")])
        out = r.output
        assert "Traceback" not in out and isinstance(r.exception, (SystemExit, type(None))), (
            field,
            value,
            out,
            r.exception,
        )
        errors = [line for line in out.splitlines() if line.startswith("error:")]
        if r.exit_code == 2:
            names = [k for k in field.split(".") if not k.isdigit()]
            assert len(errors) == 1 and (any(n in errors[0] for n in names) or "time.max_steps" in errors[0]), (
                field,
                value,
                out,
            )
            assert not (Path(tmp) / "run" / "timeseries.csv").exists()
        elif r.exit_code == 1:
            assert len(errors) == 1 and any(g in errors[0] for g in GUARDS), (field, value, out)
        else:
            assert r.exit_code == 0, (field, value, out)
            rows = list(csv.DictReader((Path(tmp) / "run" / "timeseries.csv").open()))
            assert rows and all(math.isfinite(float(x)) for row in rows for x in row.values() if x), (field, value)
