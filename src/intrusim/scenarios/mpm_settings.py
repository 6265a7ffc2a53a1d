"""Settings of an MPM locomotion run from a TOML file and ``key=value`` overrides, and the record of
the settings a sweep's runs were made with.

The command line (``intrusim mpm steady|sweep``, ``intrusim reproduce``) builds its
:class:`~intrusim.scenarios.mpm_locomotion.MPMSettings` here, in one order: the base (the quick or
paper settings of the scenario's body), then the ``--settings`` file, then each ``--set key=value``
in the order given. Every value goes through the settings' validation before any compute; an
error names the key and the value.

Keys are the fields of ``MPMSettings`` (dotted for the parts of a field: ``mu_i.grain_diameter``,
``cells.0``) and the derived keys of :data:`DERIVED`, each of which sets one or more fields.
A ``--set`` value is read as a TOML value (``1e-3``, ``true``, ``[0.5, 0.35]``, ``"linear"``); what is
not one is taken as a bare string (``shape=linear``).
"""

from __future__ import annotations

import json
import math
import tomllib
from pathlib import Path
from typing import Any, Iterable

from intrusim._checks import InputError
from intrusim.errors import validation_message
from intrusim.scenarios.mpm_locomotion import RUN_CONTROL, _flat, settings_differences  # noqa: F401 - re-exported

# derived keys: a convenience that sets one or more MPMSettings fields
DERIVED: dict[str, str] = {
    "cell_size": "grid cell size, m: cells = domain / cell_size",
    "length": "bed length, m: domain's first entry, the cell size kept",
    "contact_band": "cells: contact = 'band' with contact_band_cells = this (docs/mpm.md)",
    "mu_i_diameter": "grain diameter, m: mu_i = {grain_diameter = this} (friction mu(I), not the paper's law)",
    "fluidity_diameter": "grain diameter, m: fluidity = {grain_diameter = this} (nonlocal fluidity, not the paper's law)",
}


def settings_keys() -> list[str]:
    """Every key ``--set`` and a settings file take (the fields, then the derived keys)."""
    from intrusim.scenarios.mpm_locomotion import MPMSettings

    return [*MPMSettings.model_fields, *DERIVED]


def parse_assignment(item: str) -> tuple[str, Any]:
    """``"key=value"`` -> (key, value): the value read as TOML, else taken as a bare string."""
    key, sep, text = item.partition("=")
    key = key.strip()
    if not sep or not key:
        raise InputError(f"--set takes KEY=VALUE, got {item!r}")
    try:
        value = tomllib.loads(f"v = {text.strip()}")["v"]
    except tomllib.TOMLDecodeError:
        value = text.strip()
    return key, value


def read_settings_file(path: str | Path) -> list[tuple[str, Any]]:
    """The (key, value) pairs of a settings TOML file, tables as dotted keys (``[mu_i]`` then
    ``grain_diameter = 1e-3`` is ``mu_i.grain_diameter``)."""
    p = Path(path)
    if not p.is_file():
        raise InputError(f"--settings: no such file: {p}" if not p.exists() else f"--settings: {p} is not a file")
    try:
        table = tomllib.loads(p.read_text())
    except UnicodeDecodeError:
        raise InputError(f"--settings {p}: not a text (TOML) file") from None
    except tomllib.TOMLDecodeError as err:
        raise InputError(f"--settings {p}: invalid TOML ({err})") from None
    return [(k, v) for k, v in _flat(table).items() if v != {}]  # an empty table sets nothing


def _number(key: str, value: Any, what: str, positive: bool = True) -> float:
    """A derived key's value: a finite number (not true/false), > 0 (or >= 0)."""
    ok = isinstance(value, (int, float)) and not isinstance(value, bool) and math.isfinite(value)
    if not ok or not (value > 0 if positive else value >= 0):
        raise InputError(f"{key} must be {'>' if positive else '>='} 0 {what} (a finite number), got {value!r}")
    return float(value)


def _set_path(data: dict[str, Any], key: str, value: Any) -> None:
    """Set a dotted key in a nested dict (a missing part, e.g. mu_i of None, becomes a table)."""
    parts = key.split(".")
    node: Any = data
    for i, part in enumerate(parts):
        last = i == len(parts) - 1
        where = ".".join(parts[: i + 1])
        if isinstance(node, list):
            if not (part.isdigit() and int(part) < len(node)):
                raise InputError(f"unknown setting {key!r}: {'.'.join(parts[:i]) or key} has {len(node)} entries")
            part = int(part)  # type: ignore[assignment]
        elif not isinstance(node, dict):
            raise InputError(f"unknown setting {key!r}: {'.'.join(parts[:i])} is not a table")
        if last:
            node[part] = value
        else:
            if isinstance(node, dict) and node.get(part) is None:
                node[part] = {}
            node = node[part]
            if not isinstance(node, (dict, list)):
                raise InputError(f"unknown setting {key!r}: {where} is not a table")


def check_keys(items: Iterable[tuple[str, Any]]) -> None:
    """Refuse (InputError) a key that is neither a settings field nor a derived key."""
    from intrusim.scenarios.mpm_locomotion import MPMSettings

    for key, _ in items:
        if key.split(".", 1)[0] not in (*MPMSettings.model_fields, *DERIVED):
            raise InputError(f"unknown setting {key!r}; valid keys: {', '.join(settings_keys())}")


def apply_settings(base: Any, items: Iterable[tuple[str, Any]]) -> Any:
    """``base`` (an MPMSettings) with ``items`` (key, value) applied in order, validated as one
    whole: a bad key or value is an InputError naming it, raised before any compute."""
    from pydantic import ValidationError

    from intrusim.scenarios.mpm_locomotion import MPMSettings

    items = list(items)
    check_keys(items)
    data = base.model_dump(mode="json")
    for key, value in items:
        top = key.split(".", 1)[0]
        if top in DERIVED:
            if key != top:
                raise InputError(f"unknown setting {key!r}: {top} is a number, not a table")
            _derived(data, key, value)
        else:
            _set_path(data, key, value)
    try:
        s = MPMSettings.model_validate(data)
    except ValidationError as err:
        raise InputError(validation_message(err)) from None
    if not s.t_max > s.ramp_time + s.settle_time:
        raise InputError(
            f"t_max must exceed ramp_time + settle_time ({s.ramp_time + s.settle_time:g} s), got {s.t_max!r}"
        )
    if not s.domain[0] > s.start_x + s.wall_margin:
        raise InputError(
            f"bed length must exceed start_x + wall_margin ({s.start_x + s.wall_margin:g} m), got {s.domain[0]!r}"
        )
    if s.mu_i is not None and s.fluidity is not None:
        raise InputError("give one of mu_i (mu_i_diameter) and fluidity (fluidity_diameter), not both")
    return s


def _fields_read(data: dict[str, Any], key: str, names: tuple[str, ...]) -> dict[str, Any]:
    """The fields ``names`` of the settings' dict, validated (as fields of MPMSettings, the others
    at their defaults) before the derived key ``key`` reads them: one set earlier to a bad value is
    an InputError naming it, not an error of the arithmetic."""
    from pydantic import ValidationError

    from intrusim.scenarios.mpm_locomotion import MPMSettings

    try:
        checked = MPMSettings.model_validate({n: data[n] for n in names}, context={"partial": True})
    except ValidationError as err:
        raise InputError(f"{validation_message(err)} (read by {key})") from None
    return {n: getattr(checked, n) for n in names}


def _derived(data: dict[str, Any], key: str, value: Any) -> None:
    """Apply one derived key (:data:`DERIVED`) to the settings' dict."""
    if key in ("cell_size", "length"):  # these read the grid: it must be valid settings first
        grid = _fields_read(data, key, ("domain", "cells"))
        domain, cells = grid["domain"], grid["cells"]

    def count(length: float, h: float) -> int:  # cells of one side
        n = length / h if h > 0 else math.inf  # h of a tiny (subnormal) length over cells is 0
        if not math.isfinite(n):
            raise InputError(f"{key} = {value!r} gives a non-finite number of cells ({length:g} m / {h:g} m)")
        return max(1, round(n))

    if key == "cell_size":
        h = _number(key, value, "m")
        data["cells"] = [count(d, h) for d in domain]
    elif key == "length":
        length = _number(key, value, "m")
        data["domain"], data["cells"] = [length, domain[1]], [count(length, domain[0] / cells[0]), cells[1]]
    elif key == "contact_band":
        data["contact"], data["contact_band_cells"] = "band", _number(key, value, "cells", positive=False)
    elif key == "mu_i_diameter":
        data["mu_i"] = {"grain_diameter": _number(key, value, "m")}
    elif key == "fluidity_diameter":
        data["fluidity"] = {"grain_diameter": _number(key, value, "m")}


def settings_items(settings_file: str | Path | None = None, sets: Iterable[str] = ()) -> list[tuple[str, Any]]:
    """The (key, value) pairs of a command's ``--settings`` file, then of each ``--set key=value``, in order."""
    items = [] if settings_file is None else read_settings_file(settings_file)
    return items + [parse_assignment(s) for s in sets]


def body_settings(
    scenario: Any,
    quick: bool,
    echo: Any = True,
    preset: str | None = None,
    items: Any = (),
) -> Any:
    """The settings of ``scenario``'s runs: the base (``preset``: "paper", the default, :func:`~intrusim.scenarios.mpm_locomotion.base_settings`
    of its body at its ``mpm_scale``; "quick", as ``quick``; "reference", :func:`~intrusim.scenarios.mpm_locomotion.reference_settings`),
    then ``items`` ((key, value) pairs, :func:`~intrusim.scenarios.mpm_settings.apply_settings`),
    then the box grown, where needed, to hold this body (:func:`~intrusim.scenarios.mpm_locomotion.fit_box`) in the dimensions the items
    did not set. A body that fits (every shipped one) gets its settings unchanged. ``echo``: say on
    stderr what was grown."""
    from intrusim.scenarios.mpm_locomotion import PRESETS, base_settings, fit_box, reference_settings

    if preset is not None and preset not in PRESETS:
        raise InputError(f"--preset must be one of {', '.join(PRESETS)}, got {preset!r}")
    if quick and preset not in (None, "quick"):
        raise InputError(f"--quick and --preset {preset}: give one (--quick is --preset quick)")
    if preset == "reference":
        base = reference_settings(scenario)
    else:
        base = base_settings(scenario.body, quick or preset == "quick", scenario.mpm_scale)
    items = list(items)
    given = {key.split(".", 1)[0] for key, _ in items}
    s = apply_settings(base, items) if items else base
    height = not ({"domain", "cells"} & given)  # a box set by hand is kept (and refused if too small)
    start = not ({"domain", "cells", "length", "start_x"} & given)
    return fit_box(s, scenario, echo, height=height, start=start)


def case_settings(
    scenario: Any,
    quick: bool,
    settings_file: str | Path | None = None,
    sets: Iterable[str] = (),
    echo: Any = True,
    preset: str | None = None,
) -> Any:
    """The MPMSettings of a command: the quick or paper base of ``scenario``'s body (at its
    ``mpm_scale``, the box grown to hold the body: :func:`~intrusim.scenarios.mpm_locomotion.body_settings`),
    then the settings file, then each ``key=value`` of ``sets`` in order. ``echo``: say what was grown
    and warn of cells coarser than a fifth of the body's thinnest feature, on stderr (True) or to this
    callable."""
    import sys

    from intrusim.scenarios.mpm_locomotion import resolution_warning

    s = body_settings(scenario, quick, echo, preset, settings_items(settings_file, sets))
    note = resolution_warning(scenario, s.h, quick or preset == "quick") if echo else None
    if note:
        echo(note) if callable(echo) else print(f"warning: {note}", file=sys.stderr)
    return s


# ---------------------------------------------------------------- the record of a sweep's settings


def record_path(csv_path: str | Path) -> Path:
    """The file beside a sweep CSV that records the settings of its runs."""
    p = Path(csv_path)
    return p.with_name(p.stem + ".settings.json")


def write_record(csv_path: str | Path, scenario: str, settings: dict[float, Any]) -> Path:
    """Record the settings (an MPMSettings or its dict, per omega) of the runs of a sweep CSV."""
    from intrusim.mpm.io import atomic_write_bytes

    runs = {f"{w:g}": s if isinstance(s, dict) else s.model_dump(mode="json") for w, s in settings.items()}
    path = record_path(csv_path)
    atomic_write_bytes(path, json.dumps({"scenario": scenario, "settings": runs}, indent=1).encode())
    return path


def read_record(csv_path: str | Path) -> dict[float, dict[str, Any]] | None:
    """The recorded settings per omega of a sweep CSV's runs, or None where none were recorded."""
    path = record_path(csv_path)
    if not path.is_file():
        return None
    return {float(w): s for w, s in json.loads(path.read_text())["settings"].items()}
