"""Helpers shared by the command-line tests (importable from any test: tests/ is on sys.path)."""

from __future__ import annotations

from typer.testing import CliRunner

from intrusim.cli import app

runner = CliRunner()


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
