"""The step's other code paths (``step_graph``, ``device_bodies``, ``simd_lanes``) are internal switches
of the benchmarks and tests (``intrusim.mpm.backend.BenchmarkSwitches``), no longer settings of a run:
a run's configuration that names one is refused with one line, while a run folder or checkpoint written
when they were ``backend`` settings still loads, as the same configuration at the defaults, and on its
own switches where it was made with others. That each switch still switches its path is checked by
test_mpm_step_graph.py, test_mpm_device_bodies.py, test_mpm_simd_lanes.py and test_mpm_flip.py."""

import dataclasses
import json

import numpy as np
import pytest
from cli_helpers import refused, run, tiny_config
from pydantic import ValidationError

from intrusim.errors import InputError, validation_message
from intrusim.mpm import io as mpm_io
from intrusim.mpm.backend import DEFAULT_SWITCHES, BenchmarkSwitches
from intrusim.mpm.config import REMOVED_BACKEND_KEYS, BackendConfig, MPMConfig
from intrusim.mpm.solver import CHECKPOINT, Solver

# backend of a config.json written before the switches left the configuration (their defaults)
OLD_BACKEND = {"step_graph": True, "device_bodies": True, "simd_lanes": True}


def _tiny(tmp_path, name="run", t_end=0.02) -> MPMConfig:
    path = tmp_path / f"{name}.toml"
    path.write_text(tiny_config(t_end))
    cfg = MPMConfig.from_toml(path)
    cfg.output.directory = str(tmp_path / name)
    return cfg


def _make_old(run_dir, **backend) -> None:
    """Rewrite the folder's config.json and checkpoint as a version before the change wrote them: the
    switches among the ``backend`` settings (their defaults, or ``backend``), no ``switches`` entry."""
    old = {**OLD_BACKEND, **backend}
    payload = json.loads((run_dir / "config.json").read_text())
    payload.pop(mpm_io.SWITCHES_KEY, None)
    payload["config"]["backend"].update(old)
    (run_dir / "config.json").write_text(json.dumps(payload, indent=2))
    arrays, meta = mpm_io.load_checkpoint(run_dir / CHECKPOINT)
    meta.pop(mpm_io.SWITCHES_KEY, None)
    meta["config"]["backend"].update(old)
    mpm_io.save_checkpoint(run_dir / CHECKPOINT, arrays, meta)


def test_the_switches_are_the_removed_backend_keys_and_their_defaults_the_former_ones():
    assert tuple(f.name for f in dataclasses.fields(BenchmarkSwitches)) == REMOVED_BACKEND_KEYS
    assert dataclasses.asdict(DEFAULT_SWITCHES) == OLD_BACKEND  # every run's path, as before
    assert DEFAULT_SWITCHES.changed() == {}
    assert BenchmarkSwitches(simd_lanes=False).changed() == {"simd_lanes": False}
    assert not set(REMOVED_BACKEND_KEYS) & set(BackendConfig.model_fields)
    with pytest.raises(TypeError, match="simd_lanes"):
        BenchmarkSwitches(simd_lanes=0)
    with pytest.raises(dataclasses.FrozenInstanceError):
        DEFAULT_SWITCHES.step_graph = False
    with pytest.raises(TypeError, match="BenchmarkSwitches"):
        Solver(MPMConfig(), switches={"step_graph": False})


@pytest.mark.parametrize("key", REMOVED_BACKEND_KEYS)
@pytest.mark.parametrize("value", [True, False])
def test_a_run_configuration_naming_a_switch_is_refused_with_one_line(tmp_path, key, value):
    path = tmp_path / "run.toml"
    path.write_text(tiny_config(0.02) + f"[backend]\n{key} = {str(value).lower()}\n")
    with pytest.raises(ValidationError) as err:
        MPMConfig.from_toml(path)
    line = validation_message(err.value)
    assert "\n" not in line and line.startswith(f"backend: {key} is no longer a setting of a run"), line
    with pytest.raises(ValidationError, match=key):
        BackendConfig(**{key: value})
    # the command line: exit 2 before any compute, one line naming the key
    refused(run("mpm", "run", path, "--out", tmp_path / "out"), f"backend: {key} is no longer a setting")
    assert not (tmp_path / "out" / "config.json").exists()


def test_a_saved_configuration_with_the_switches_at_their_defaults_loads_without_them():
    saved = MPMConfig().model_dump(mode="json")
    old = {**saved, "backend": {**saved["backend"], **OLD_BACKEND}}
    config, switches = mpm_io.split_switches(old)
    assert switches == DEFAULT_SWITCHES and config == saved
    assert MPMConfig.model_validate(config) == MPMConfig()
    assert old["backend"]["simd_lanes"] is True  # the saved dict itself is left as it was
    assert mpm_io.checkpoint_mismatch(old, MPMConfig()) == []
    # older still: a folder written before a switch existed is at its default
    config, switches = mpm_io.split_switches({**saved, "backend": {**saved["backend"], "step_graph": False}})
    assert switches == BenchmarkSwitches(step_graph=False) and config == saved
    assert mpm_io.split_switches(saved, {"simd_lanes": False})[1] == BenchmarkSwitches(simd_lanes=False)


@pytest.mark.parametrize(
    "backend, recorded, words",
    [
        ({"simd_lanes": "no"}, None, "backend.simd_lanes = 'no'"),
        ({}, {"vectors": False}, "switches.vectors"),
        ({}, [False], "must be a table"),
    ],
)
def test_a_saved_switch_that_is_not_true_or_false_is_refused_by_name(backend, recorded, words):
    saved = MPMConfig().model_dump(mode="json")
    saved["backend"].update(backend)
    with pytest.raises(InputError, match="^config.json: ") as err:
        mpm_io.split_switches(saved, recorded, "config.json")
    assert words in str(err.value)


def test_a_folder_written_before_the_change_is_the_same_run_and_resumes(tmp_path):
    cfg = _tiny(tmp_path)
    solver = Solver(cfg)
    solver.run(t_end=0.0)  # config.json, its first row
    solver.checkpoint_run_folder()
    run_dir = solver.run_dir
    assert "simd_lanes" not in json.loads((run_dir / "config.json").read_text())["config"]["backend"]
    assert mpm_io.SWITCHES_KEY not in json.loads((run_dir / "config.json").read_text())
    _make_old(run_dir)
    # the same configuration: refuse_other_run lets it go on, the checkpoint loads
    assert mpm_io.refuse_other_run(run_dir, cfg) is False
    again = Solver(_tiny(tmp_path))
    assert again.continue_in_run_dir() and again.switches == DEFAULT_SWITCHES
    resumed = Solver.resume(run_dir)
    assert resumed.switches == DEFAULT_SWITCHES and resumed.cfg == cfg
    resumed.run(t_end=0.0)  # config.json is written again, without the keys
    assert "step_graph" not in json.loads((run_dir / "config.json").read_text())["config"]["backend"]


def test_a_folder_made_with_other_switches_resumes_on_them_and_a_default_run_is_refused_there(tmp_path):
    cfg = _tiny(tmp_path)
    solver = Solver(cfg)
    solver.run(t_end=0.0)
    solver.checkpoint_run_folder()
    run_dir = solver.run_dir
    _make_old(run_dir, simd_lanes=False)  # as a run with `simd_lanes = false` in its TOML wrote it
    resumed = Solver.resume(run_dir)
    assert resumed.switches == BenchmarkSwitches(simd_lanes=False) and not resumed._lanes
    with pytest.raises(InputError, match=r"another configuration \(differs in backend.simd_lanes\)"):
        mpm_io.refuse_other_run(run_dir, cfg)
    with pytest.raises(InputError, match=r"differs in backend.simd_lanes"):
        Solver(_tiny(tmp_path)).continue_in_run_dir()
    with pytest.raises(InputError, match=r"checkpoint of another configuration \(differs in backend.simd_lanes\)"):
        Solver(_tiny(tmp_path)).load_checkpoint(run_dir / CHECKPOINT)
    # the benchmarks' path: the same switches go on there
    lanes_off = Solver(_tiny(tmp_path), switches=BenchmarkSwitches(simd_lanes=False))
    assert lanes_off.continue_in_run_dir()


def test_a_run_with_other_switches_records_them_and_resumes_on_them(tmp_path):
    switches = BenchmarkSwitches(step_graph=False, device_bodies=False)
    solver = Solver(_tiny(tmp_path), switches=switches)
    solver.run(t_end=0.0)
    solver.checkpoint_run_folder()
    run_dir = solver.run_dir
    payload = json.loads((run_dir / "config.json").read_text())
    assert payload[mpm_io.SWITCHES_KEY] == {"step_graph": False, "device_bodies": False}
    assert not set(REMOVED_BACKEND_KEYS) & set(payload["config"]["backend"])
    assert MPMConfig.model_validate(payload["config"]) == solver.cfg  # the configuration alone is a run's
    assert mpm_io.load_checkpoint(run_dir / CHECKPOINT)[1][mpm_io.SWITCHES_KEY] == switches.changed()
    assert Solver.resume(run_dir).switches == switches
    with pytest.raises(InputError, match="backend.device_bodies, backend.step_graph"):
        Solver(_tiny(tmp_path)).continue_in_run_dir()


def test_the_command_line_goes_on_in_a_folder_written_before_the_change(tmp_path):
    toml = tmp_path / "tiny.toml"
    toml.write_text(tiny_config(0.01))
    out = tmp_path / "run"
    assert run("mpm", "run", toml, "--out", out).exit_code == 0
    _make_old(out)
    longer = tmp_path / "longer.toml"
    longer.write_text(tiny_config(0.015))
    r = run("mpm", "run", longer, "--out", out)
    assert r.exit_code == 0 and "continuing" in r.output, r.output
    _make_old(out)
    r = run("mpm", "resume", out, "--t-end", "0.02")
    assert r.exit_code == 0 and "resuming" in r.output, r.output
    times = np.loadtxt(out / "timeseries.csv", delimiter=",", skiprows=1, usecols=0)
    assert abs(times.max() - 0.02) < 1e-4  # to the step
    _make_old(out, step_graph=False)  # a run made with a switch other than the default: refused by name
    longer.write_text(tiny_config(0.03))
    line = refused(run("mpm", "run", longer, "--out", out), "(differs in backend.step_graph)")
    assert "t_end" not in line
