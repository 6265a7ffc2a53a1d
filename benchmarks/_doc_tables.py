"""Generated tables in the docs: replace the lines between a pair of markers (shared by the benchmarks).

A table a script writes sits in its markdown file between ``<!-- NAME: begin -->`` and
``<!-- NAME: end -->``, each on a line of its own; :func:`write_between` replaces what lies between
them and keeps the rest of the file as it is. A file without exactly one such pair is refused
(:class:`MarkerError`): the table is never appended somewhere the text does not expect it.
"""

from __future__ import annotations

import datetime
import os
import platform
import shlex
import sys
from pathlib import Path

from intrusim._doc_markers import MarkerError, markers, replace_between  # noqa: F401 (the benchmarks' and tests' names)

ROOT = Path(__file__).resolve().parents[1]


def check_markers(path: Path | str, name: str) -> str:
    """The text of ``path`` once its markers of ``name`` are checked (a benchmark checks before it measures)."""
    path = Path(path)
    if not path.exists():
        raise MarkerError(f"{path} does not exist (it needs the markers '{markers(name)[0]}' / '{markers(name)[1]}')")
    text = path.read_text()
    replace_between(text, name, [], where=str(path))
    return text


def write_between(path: Path | str, name: str, lines: list[str]) -> None:
    """Replace the table ``name`` of the markdown file ``path`` with ``lines`` (see :func:`replace_between`)."""
    text = check_markers(path, name)
    path = Path(path)
    new = replace_between(text, name, lines, where=str(path))
    if new != text:
        path.write_text(new)


def cpu_model() -> str:
    """The CPU's model name (from /proc/cpuinfo where there is one, else the platform's word)."""
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.lower().startswith("model name"):
                    return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or platform.machine() or "unknown CPU"


def command_line(argv: list[str] | None = None) -> str:
    """The command that ran, as ``python benchmarks/...`` with the script's path relative to the repository."""
    argv = list(sys.argv if argv is None else argv)
    script = Path(argv[0]).resolve() if argv else Path("?")
    try:
        argv[0] = str(script.relative_to(ROOT))
    except ValueError:
        argv[0] = str(script)
    return "python " + " ".join(shlex.quote(a) for a in argv)


def machine_line(argv: list[str] | None = None) -> str:
    """One line for under a generated table: the machine, the date and the command that measured it."""
    try:
        load = ", load average %.1f" % os.getloadavg()[0]
    except OSError:  # pragma: no cover
        load = ""
    return (
        f"Measured on {os.cpu_count()} cores ({cpu_model()}{load}) on {datetime.date.today().isoformat()} "
        f"by `{command_line(argv)}`."
    )
