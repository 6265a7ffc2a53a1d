"""Generated blocks in the markdown docs: the lines between ``<!-- NAME: begin -->`` and ``<!-- NAME: end -->``.

Shared by ``intrusim status`` (the status table of docs/results.md) and the benchmarks that write
their tables (``benchmarks/_doc_tables.py``). A text without exactly one such pair is refused
(:class:`MarkerError`): a table is never appended somewhere the text does not expect it.
"""

from __future__ import annotations


class MarkerError(ValueError):
    """The file does not hold exactly one ``<!-- NAME: begin -->`` ... ``<!-- NAME: end -->`` pair."""


def markers(name: str) -> tuple[str, str]:
    """The begin and end markers of the table ``name``."""
    return f"<!-- {name}: begin -->", f"<!-- {name}: end -->"


def replace_between(text: str, name: str, lines: list[str], where: str = "the text") -> str:
    """``text`` with the lines between the markers of ``name`` replaced by ``lines`` (markers kept)."""
    begin, end = markers(name)
    n_begin, n_end = text.count(begin), text.count(end)
    if n_begin != 1 or n_end != 1:
        raise MarkerError(
            f"{where} needs exactly one '{begin}' and one '{end}', each on a line of its own, around the "
            f"generated table (found {n_begin} and {n_end}); add them where the table belongs"
        )
    head, rest = text.split(begin, 1)
    if end not in rest:
        raise MarkerError(f"{where}: '{end}' comes before '{begin}'")
    tail = rest.split(end, 1)[1]
    return head + "\n".join([begin, *lines, end]) + tail
