"""Scenarios as validated configs (pydantic v2, loadable from TOML); see docs/locomotion.md.

``get_scenario(name)`` returns a shipped default; ``load_scenario(path)`` reads a TOML file
whose ``body`` key ("wheel" or "runner") selects the defaults it is merged onto.
"""

from __future__ import annotations

from pathlib import Path

from intrusim._checks import InputError
from intrusim.scenarios.base import ALL_KINDS, ForceModelConfig, RunConfig
from intrusim.scenarios.locomotor import (
    LocomotorScenario,
    four_flap_runner_scenario,
    grousered_wheel_scenario,
    small_wheel_scenario,
    tall_grouser_wheel_scenario,
    ten_grouser_wheel_scenario,
    thirty_grouser_wheel_scenario,
)
from intrusim.scenarios.plates import PlateScenario, drag_force_table, plate_drag_scenario, vertical_plate_scenario

LOCOMOTORS = {
    "wheel": grousered_wheel_scenario,
    "small-wheel": small_wheel_scenario,
    "runner": four_flap_runner_scenario,
    "wheel-10-grousers": ten_grouser_wheel_scenario,
    "wheel-30-grousers": thirty_grouser_wheel_scenario,
    "wheel-tall-grousers": tall_grouser_wheel_scenario,
}
PLATES = {"plate-drag": plate_drag_scenario, "vertical-plate": vertical_plate_scenario}


def get_scenario(name: str) -> LocomotorScenario | PlateScenario:
    """A shipped scenario by name: wheel, small-wheel, runner, the wheel's variants (wheel-10-grousers,
    wheel-30-grousers, wheel-tall-grousers), plate-drag, vertical-plate."""
    table = {**LOCOMOTORS, **PLATES}
    if name not in table:
        raise InputError(f"unknown scenario {name!r}; known: {sorted(table)}")
    return table[name]()


def load_scenario(path_or_name: str | Path) -> LocomotorScenario:
    """A locomotor scenario from a shipped name (``small_wheel`` spelt either way) or a TOML file."""
    s = str(path_or_name)
    name = s.replace("_", "-")
    if name in LOCOMOTORS:
        return LOCOMOTORS[name]()
    if s.endswith(".toml") or Path(s).exists():
        return LocomotorScenario.from_toml(s)  # type: ignore[return-value]
    raise InputError(f"scenario must be one of {sorted(LOCOMOTORS)} or a .toml file, got {s!r}")


__all__ = [
    "ALL_KINDS", "ForceModelConfig", "RunConfig", "LocomotorScenario", "PlateScenario",
    "grousered_wheel_scenario", "small_wheel_scenario", "four_flap_runner_scenario",
    "plate_drag_scenario", "vertical_plate_scenario", "drag_force_table",
    "get_scenario", "load_scenario", "LOCOMOTORS", "PLATES",
]  # fmt: skip
