"""User-facing errors and the command line's exit codes.

Exit codes of every ``intrusim`` command:

- 0 (:data:`EXIT_OK`): done;
- 1 (:data:`EXIT_FAILED`): the run started and failed (a guard stopped it, the disk filled); its
  diagnosis is printed and its run folder keeps the last good checkpoint (and a failure one);
- 2 (:data:`EXIT_BAD_INPUT`): bad input, refused before any compute, with one line naming the
  field and the value.

Errors are one line on stderr (``error: ...``); ``intrusim --debug`` shows the traceback too.
"""

from __future__ import annotations

import functools
from typing import Any

EXIT_OK = 0
EXIT_FAILED = 1
EXIT_BAD_INPUT = 2


class InputError(ValueError):
    """A user-supplied value is invalid; the message names the parameter and the value (exit 2)."""


class RunFailed(RuntimeError):
    """A run started and could not finish (exit 1); its run folder keeps what was done."""


def validation_message(err: Any, prefix: str = "") -> str:
    """One line from a pydantic ``ValidationError``: each failed field by its dotted name, what it
    must be and the value given, e.g. ``time.t_end: Input should be a finite number (got inf)``."""
    parts = []
    for e in err.errors(include_url=False):
        loc = ".".join(str(p) for p in e.get("loc", ()) if not (isinstance(p, str) and p in ("prescribed", "coupled")))
        msg = e.get("msg", "invalid").removeprefix("Value error, ")
        got = e.get("input", None)
        shown = (
            ""
            if e.get("type") in ("missing", "model_type", "dict_type") or isinstance(got, dict)
            else f" (got {_short(got)})"
        )
        where = f"{prefix}{loc}" if loc else prefix.rstrip(".")
        parts.append(f"{where}: {msg}{shown}" if where else f"{msg}{shown}")
    return "; ".join(parts) if parts else str(err)


def _short(value: Any, limit: int = 60) -> str:
    text = repr(value)
    return text if len(text) <= limit else text[: limit - 3] + "..."


# programming errors: a sweep never turns them into a failed data point, the CLI calls them internal
PROGRAMMING_ERRORS: tuple[type[BaseException], ...] = (
    TypeError,
    AttributeError,
    NameError,
    KeyError,
    IndexError,
    ZeroDivisionError,
    AssertionError,
    NotImplementedError,
    ImportError,
    RecursionError,
)


def classify(err: BaseException) -> tuple[int, str]:
    """(exit code, one-line message) of an exception that reached the command line."""
    import json
    import sys
    import tomllib

    from pydantic import ValidationError

    # a SimulationError exists only once the solver's module is loaded (importing it starts Taichi)
    diagnostics = sys.modules.get("intrusim.mpm.diagnostics")
    SimulationError = getattr(diagnostics, "SimulationError", RunFailed)  # noqa: N806
    if isinstance(err, ValidationError):
        return EXIT_BAD_INPUT, validation_message(err)
    if isinstance(err, (RunFailed, SimulationError)):
        return EXIT_FAILED, _one_line(err)
    if isinstance(err, (tomllib.TOMLDecodeError, json.JSONDecodeError, UnicodeDecodeError)):
        return EXIT_BAD_INPUT, f"unreadable input ({type(err).__name__}: {_one_line(err)})"
    if isinstance(err, (FileNotFoundError, IsADirectoryError, NotADirectoryError, PermissionError, FileExistsError)):
        return EXIT_BAD_INPUT, f"{err.strerror or type(err).__name__}: {err.filename or ''}".rstrip(": ")
    if isinstance(err, OSError):  # a full disk, an I/O error: the run failed, its folder keeps its last checkpoint
        where = f": {err.filename}" if err.filename else ""
        return EXIT_FAILED, f"{err.strerror or _one_line(err)}{where}"
    if isinstance(err, PROGRAMMING_ERRORS) or not isinstance(err, ValueError):
        return EXIT_FAILED, (
            f"internal error {type(err).__name__}: {_one_line(err)} (a bug; `intrusim --debug ...` shows the traceback)"
        )
    return EXIT_BAD_INPUT, _one_line(err)  # InputError and other ValueErrors: bad input


def _one_line(err: BaseException) -> str:
    return " ".join(str(err).split("\n")).strip() or type(err).__name__


def _passthrough() -> tuple[type[BaseException], ...]:
    """The exceptions the command line library handles itself (exits, aborts, usage errors)."""
    import typer

    types: list[type[BaseException]] = [typer.Exit, typer.Abort]
    for name in ("typer._click.exceptions", "click.exceptions"):  # typer's own click (>= 0.20), or click
        try:
            mod = __import__(name, fromlist=["ClickException"])
            types += [getattr(mod, n) for n in ("ClickException", "Exit", "Abort") if hasattr(mod, n)]
        except ImportError:
            pass
    return tuple(types)


@functools.cache
def guarded_group() -> Any:
    """A typer group whose commands end with one line and an exit code on any exception
    (:func:`classify`), or with the traceback under ``intrusim --debug`` (or INTRUSIM_DEBUG=1)."""
    import os

    import typer
    from typer.core import TyperGroup

    passthrough = _passthrough()

    class GuardedGroup(TyperGroup):
        def invoke(self, ctx: Any) -> Any:
            try:
                return super().invoke(ctx)
            except passthrough:
                raise
            except Exception as err:
                if (isinstance(ctx.obj, dict) and ctx.obj.get("debug")) or os.environ.get("INTRUSIM_DEBUG"):
                    raise
                code, text = classify(err)
                typer.echo(f"error: {text}", err=True)
                raise typer.Exit(code) from None

    return GuardedGroup
