"""intrusim: granular intrusion with MPM, RFT and Dynamic RFT.

Reproduces Agarwal, Karsai, Goldman & Kamrin (2021), "Surprising simplicity in the
modeling of dynamic granular intrusion", Science Advances. SI units throughout.

The public names are listed in ``__all__``; each is imported on first use (``import intrusim``
itself stays fast: Numba, Taichi and matplotlib load only when a name that needs them is used)::

    import intrusim as im

    wheel = im.grousered_wheel_scenario()
    st = im.run_steady(wheel, "drft", omega_rpm=30)            # one steady state
    sweep = im.sweep_omega(wheel, "drft", [10, 30, 60])        # an omega sweep (Dask)
    mpm = im.run_mpm_steady(wheel, im.quick_settings("wheel"), 30)   # the continuum solver
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING, Any

from intrusim._version import __version__

#: public name -> the module that defines it
_EXPORTS: dict[str, str] = {
    # errors
    "InputError": "intrusim.errors",
    "RunFailed": "intrusim.errors",
    # shapes and body state
    "Shape": "intrusim.geometry",
    "SurfaceElements": "intrusim.geometry",
    "polygon_shape": "intrusim.geometry",
    "grousered_wheel": "intrusim.geometry",
    "four_flap_runner": "intrusim.geometry",
    "circle": "intrusim.geometry",
    "plate": "intrusim.geometry",
    "BodyState": "intrusim.kinematics",
    "Wrench": "intrusim.kinematics",
    # force models (RFT, DRFT)
    "make_force_model": "intrusim.forces",
    "ResistiveForceModel": "intrusim.forces",
    "ForceModel": "intrusim.forces",
    # rigid bodies and their integration
    "RigidBody": "intrusim.bodies",
    "Drive": "intrusim.bodies",
    "IntegratorSettings": "intrusim.bodies",
    "Trajectory": "intrusim.bodies",
    "simulate": "intrusim.bodies",
    # scenarios
    "LocomotorScenario": "intrusim.scenarios",
    "PlateScenario": "intrusim.scenarios",
    "ForceModelConfig": "intrusim.scenarios",
    "RunConfig": "intrusim.scenarios",
    "get_scenario": "intrusim.scenarios",
    "load_scenario": "intrusim.scenarios",
    "grousered_wheel_scenario": "intrusim.scenarios",
    "small_wheel_scenario": "intrusim.scenarios",
    "four_flap_runner_scenario": "intrusim.scenarios",
    "plate_drag_scenario": "intrusim.scenarios",
    "vertical_plate_scenario": "intrusim.scenarios",
    # steady states and sweeps
    "run_steady": "intrusim.analysis.steady",
    "steady_state": "intrusim.analysis.steady",
    "SteadyState": "intrusim.analysis.steady",
    "sweep_omega": "intrusim.analysis.sweep",
    "SweepResult": "intrusim.analysis.sweep",
    # calibration of DRFT on MPM runs
    "calibrate": "intrusim.analysis.calibration",
    "compare": "intrusim.analysis.calibration",
    "load_reference": "intrusim.analysis.calibration",
    "CalibrationResult": "intrusim.analysis.calibration",
    # the MPM continuum solver
    "MPMConfig": "intrusim.mpm.config",
    "Solver": "intrusim.mpm.solver",
    "MPMSettings": "intrusim.scenarios.mpm_locomotion",
    "paper_settings": "intrusim.scenarios.mpm_locomotion",
    "quick_settings": "intrusim.scenarios.mpm_locomotion",
    "run_mpm_steady": "intrusim.scenarios.mpm_locomotion",
    "MPMSteadyState": "intrusim.scenarios.mpm_locomotion",
    # the paper's figures and the default demonstration
    "FIGURES": "intrusim.figures",
    "run_demo": "intrusim.demo",
}

__all__ = ["__version__", *_EXPORTS]


def __getattr__(name: str) -> Any:
    module = _EXPORTS.get(name)
    if module is None:
        raise AttributeError(f"module 'intrusim' has no attribute {name!r}")
    value = getattr(importlib.import_module(module), name)
    globals()[name] = value  # later look-ups skip __getattr__
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(__all__))


if TYPE_CHECKING:  # for type checkers and IDEs: the same names, imported eagerly
    from intrusim.analysis.calibration import CalibrationResult, calibrate, compare, load_reference
    from intrusim.analysis.steady import SteadyState, run_steady, steady_state
    from intrusim.analysis.sweep import SweepResult, sweep_omega
    from intrusim.bodies import Drive, IntegratorSettings, RigidBody, Trajectory, simulate
    from intrusim.demo import run_demo
    from intrusim.errors import InputError, RunFailed
    from intrusim.figures import FIGURES
    from intrusim.forces import ForceModel, ResistiveForceModel, make_force_model
    from intrusim.geometry import (
        Shape,
        SurfaceElements,
        circle,
        four_flap_runner,
        grousered_wheel,
        plate,
        polygon_shape,
    )
    from intrusim.kinematics import BodyState, Wrench
    from intrusim.mpm.config import MPMConfig
    from intrusim.mpm.solver import Solver
    from intrusim.scenarios import (
        ForceModelConfig,
        LocomotorScenario,
        PlateScenario,
        RunConfig,
        four_flap_runner_scenario,
        get_scenario,
        grousered_wheel_scenario,
        load_scenario,
        plate_drag_scenario,
        small_wheel_scenario,
        vertical_plate_scenario,
    )
    from intrusim.scenarios.mpm_locomotion import (
        MPMSettings,
        MPMSteadyState,
        paper_settings,
        quick_settings,
        run_mpm_steady,
    )
