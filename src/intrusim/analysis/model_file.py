"""A calibrated force model as a file: what ``intrusim calibrate`` writes and ``intrusim steady|sweep
--model FILE`` read.

The file (JSON) holds the force model's kind, every :class:`~intrusim.scenarios.base.ForceModelConfig`
field as calibrated, whether the body gets the constant forward push of the MPM runs it was
calibrated on (``mpm_push``: the push is the body's own, recomputed for whichever body the model
drives), and a record of the fit. Applied to a scenario, it replaces that scenario's force model:
the medium and the corrections are the model's, the body is the scenario's. The structural
correction is a wheel's (the rear of its contact arc): a body that has none of its own (the runner)
keeps none, as ``intrusim calibrate --check`` runs it.
"""

from __future__ import annotations

import json
import os
import sys
from pathlib import Path
from typing import Any, Literal

from pydantic import Field

from intrusim._checks import InputError
from intrusim.scenarios.base import ALL_KINDS, Config, ForceModelConfig
from intrusim.scenarios.locomotor import LocomotorScenario

SUFFIX = ".model.json"


class ModelFile(Config):
    """A force model written by a calibration (see the module docstring).

    Attributes
    ----------
    intrusim_model : format version (1).
    kind : force model: "drft", "drft-inertial" or "rft".
    force_model : the calibrated force-model parameters (a relative ``rft_coefficients`` path is
        relative to the model file's folder).
    mpm_push : give the body the constant forward push of its MPM runs
        (:func:`intrusim.analysis.calibration.with_mpm_push`), as during the calibration.
    calibrated_on : the scenario the model was fitted to.
    fit : what the calibration fitted and how well (parameters, reference runs, errors).
    """

    intrusim_model: Literal[1] = 1
    kind: Literal["rft", "drft-inertial", "drft"] = "drft"
    force_model: ForceModelConfig
    mpm_push: bool = True
    calibrated_on: str = ""
    fit: dict[str, Any] = Field(default_factory=dict)

    def apply(self, scenario: LocomotorScenario) -> LocomotorScenario:
        """``scenario`` driven by this model: its force model replaced (a body without a structural
        correction of its own keeps none), the MPM push its own."""
        from intrusim.analysis.calibration import with_mpm_push

        fm = self.force_model.model_dump()
        if scenario.force_model.structural == "none":
            fm["structural"] = "none"
        s = scenario.validated_copy(force_model=fm)
        return with_mpm_push(s) if self.mpm_push else s


def write_model(path: str | Path, model: ModelFile) -> Path:
    """Write ``model`` to ``path`` (whole or not at all); a relative RFT table path is stored
    relative to the file's folder."""
    from intrusim.mpm.io import atomic_write_bytes

    p = Path(path)
    data = model.model_dump()
    table = data["force_model"].get("rft_coefficients")
    if table is not None:
        data["force_model"]["rft_coefficients"] = os.path.relpath(os.path.abspath(table), os.path.abspath(p.parent))
    p.parent.mkdir(parents=True, exist_ok=True)
    atomic_write_bytes(p, (json.dumps(data, indent=1) + "\n").encode())
    return p


def read_model(path: str | Path) -> ModelFile:
    """The model of a file written by :func:`write_model` (InputError, naming the file and the
    field, if it is missing or not such a model)."""
    p = Path(path)
    if not p.is_file():
        raise InputError(f"model file not found: {p}")
    try:
        data = json.loads(p.read_text())
    except (json.JSONDecodeError, UnicodeDecodeError) as err:
        raise InputError(f"{p}: not a model file (invalid JSON: {err})") from None
    if not isinstance(data, dict) or "intrusim_model" not in data:
        raise InputError(f"{p}: not a model file written by `intrusim calibrate` (no intrusim_model entry)")
    fm = data.get("force_model")
    table = fm.get("rft_coefficients") if isinstance(fm, dict) else None
    if isinstance(table, str) and not Path(table).is_absolute():
        data = {**data, "force_model": {**fm, "rft_coefficients": os.path.normpath(p.parent / table)}}
    return ModelFile.from_dict(data, source=str(p))  # type: ignore[return-value]


def resolve_model(model: str, scenario: LocomotorScenario) -> tuple[str, LocomotorScenario]:
    """The force-model kind and scenario of a command's ``--model``: a kind (the scenario as it
    is) or a model file (its kind, and the scenario with its force model)."""
    if model in ALL_KINDS:
        return model, scenario
    if model.endswith(".json") or Path(model).is_file():
        m = read_model(model)
        out = m.apply(scenario)
        if out.external_fx != scenario.external_fx:  # a force on the body: said, never silent
            print(
                f"{model}: mpm_push = true gives {out.name} a constant forward push of {out.external_fx:.3g} N "
                f"(was {scenario.external_fx:.3g} N): the MPM runs' rig-friction compensation the model was calibrated with",
                file=sys.stderr,
            )
        return m.kind, out
    raise InputError(f"--model must be one of {', '.join(ALL_KINDS)} or a model file (*{SUFFIX}), got {model!r}")


def with_rft_table(scn: LocomotorScenario, path: str | Path | None) -> LocomotorScenario:
    """The scenario with its RFT coefficient table read from ``path`` and xi = 1 (None: unchanged).

    A measured table is the medium's own, so it is used as it is (a calibration may still fit
    xi, a scale of it, from 1). The path is kept as given (relative to the working folder, as
    the sweep's local workers see it) and read once here, so a missing or malformed file fails
    before any compute.
    """
    if path is None:
        return scn
    from intrusim.laws.rft import load_coefficients

    load_coefficients(path)
    fm = scn.force_model.validated_copy(rft_coefficients=str(path), xi=1.0)
    return scn.validated_copy(force_model=fm)
