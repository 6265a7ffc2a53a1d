"""Helpers shared by the command-line tests (importable from any test: tests/ is on sys.path)."""

from __future__ import annotations

from typer.testing import CliRunner

from intrusim.cli import app

runner = CliRunner()


# a user's 12-grouser wheel (radius 0.115 m: taller than the quick box holds), as a body TOML
MY_WHEEL = """body = "wheel"
hub_diameter = 0.2
lug_height = 0.015
lug_width = 0.008
lug_count = 12
width = 0.12
mass_x = 12.0
mass_z = 5.0
"""


def run(*args):
    """``intrusim ARGS`` in this process (typer's runner), every argument as a string."""
    return runner.invoke(app, [str(a) for a in args])


def refused(r, *words):
    """Exit 2, one error line naming ``words``, no traceback; returns that line."""
    out = r.output
    assert r.exit_code == 2, out
    assert "Traceback" not in out and isinstance(r.exception, SystemExit), out
    errors = [line for line in out.splitlines() if line.startswith("error:")]
    assert len(errors) == 1, out
    for w in words:
        assert w in errors[0], out
    return errors[0]


def tiny_config(t_end: float) -> str:
    """An MPM run file of a 10 x 10 cell box half full of grains, ``t_end`` seconds long."""
    return f"""
[domain]
size = [0.1, 0.1]
cells = [10, 10]
[bed]
rectangles = [{{ x0 = 0.0, z0 = 0.0, x1 = 0.1, z1 = 0.05 }}]
[time]
t_end = {t_end}
[output]
record_every = 0.005
checkpoint_every = 0.01
"""


def block_config(
    t_end: float = 0.02, z: float = 0.06, omega: float = -1.0, record_every: float = 0.0025,
    checkpoint_every: float = 0.005, ramp_time: float = 0.0,
) -> str:  # fmt: skip
    """An MPM run file of a 20 x 10 cell box half full of grains with a coupled 4 x 2 cm block, its
    centre at height ``z`` (0.06 m: resting on the bed), spinning at ``omega`` (reached over
    ``ramp_time``), ``t_end`` seconds long, recorded and checkpointed every so often."""
    return f"""
[domain]
size = [0.2, 0.1]
cells = [20, 10]
[bed]
rectangles = [{{ x0 = 0.0, z0 = 0.0, x1 = 0.2, z1 = 0.05 }}]
[time]
t_end = {t_end}
[output]
record_every = {record_every}
checkpoint_every = {checkpoint_every}
[backend]
cpu_threads = 1
[[intruders]]
vertices = [[-0.02, -0.01], [0.02, -0.01], [0.02, 0.01], [-0.02, 0.01]]
width = 0.1
x = 0.1
z = {z}
[intruders.motion]
kind = "coupled"
omega = {omega}
ramp_time = {ramp_time}
mass_x = 1.0
mass_z = 1.0
"""
