"""CLI: the settings of `mpm steady|sweep` (--settings FILE.toml, --set key=value), `mpm run --threads`,
`--version`, `mpm sweep --omega-rpm` ranges, and `reproduce` refusing runs of other settings."""

import json
import math

import pytest
from cli_helpers import refused as _refused
from cli_helpers import run as _run
from cli_helpers import tiny_config
from hypothesis import given, settings
from hypothesis import strategies as st
from typer.testing import CliRunner

from intrusim._checks import InputError
from intrusim.scenarios.mpm_locomotion import MPMSettings, quick_settings

runner = CliRunner()


def _case(*sets, settings=None, scenario="wheel"):
    from intrusim.cli_mpm import _case as case

    return case(scenario, True, None, settings, list(sets))


# ---------------------------------------------------------------- a body's similar set-up (mpm_scale)


def test_small_wheel_runs_a_geometrically_similar_setup():
    """Fig S1's half-size wheel: lengths x 0.5 (so the cell size), times x sqrt(0.5), cells kept;
    a --set still applies over the scaled base."""
    from intrusim.scenarios.mpm_locomotion import paper_settings, similar_settings

    big, small = _case().mpm, _case(scenario="small-wheel").mpm
    assert small.cells == big.cells and small.h == pytest.approx(0.5 * big.h)
    for key in ("bed_depth", "start_x", "wall_margin"):
        assert getattr(small, key) == pytest.approx(0.5 * getattr(big, key)), key
    for key in ("t_max", "settle_time", "ramp_time", "chunk"):
        assert getattr(small, key) == pytest.approx(math.sqrt(0.5) * getattr(big, key)), key
    assert small.youngs_modulus == big.youngs_modulus and small.mu_s == big.mu_s
    assert paper_settings("wheel", 0.5).h == pytest.approx(0.0025)
    assert _case("t_max=1.0", scenario="small-wheel").mpm.t_max == 1.0
    tread = similar_settings(big.validated_copy(treadmill=(0.5, 0.3)), 0.5)
    assert tread.treadmill == pytest.approx((0.25, 0.15))
    with pytest.raises(ValueError, match="scale"):
        similar_settings(big, 0.0)


# ---------------------------------------------------------------- --settings and --set


def test_precedence_base_then_file_then_each_set_in_order(tmp_path):
    f = tmp_path / "s.toml"
    f.write_text("t_max = 2.0\nflip = 0.5\n[mu_i]\ngrain_diameter = 2e-3\n")
    s = _case("t_max=3.0", "contact_band=0", "t_max=2.5", settings=f).mpm
    assert s.t_max == 2.5 and s.flip == 0.5 and s.mu_i.grain_diameter == 2e-3
    assert s.contact == "band" and s.contact_band_cells == 0.0
    base = quick_settings("wheel")
    changed = {"t_max", "flip", "mu_i", "contact", "contact_band_cells"}
    assert {k: v for k, v in s.model_dump().items() if k not in changed} == {
        k: v for k, v in base.model_dump().items() if k not in changed
    }
    assert _case(settings=f).mpm.t_max == 2.0  # the file over the base
    assert _case().mpm == base


def test_set_values_are_toml_or_bare_strings():
    from intrusim.scenarios.mpm_settings import parse_assignment

    assert parse_assignment("shape=linear") == ("shape", "linear")
    assert parse_assignment('shape="linear"') == ("shape", "linear")
    assert parse_assignment("treadmill = [0.5, 0.35]") == ("treadmill", [0.5, 0.35])
    assert parse_assignment("drop_escaped=true") == ("drop_escaped", True)
    assert parse_assignment("max_steps=1000") == ("max_steps", 1000)
    assert math.isnan(parse_assignment("t_max=nan")[1])
    assert _case("cells=[60, 30]").mpm.cells == (60, 30)
    with pytest.raises(InputError, match="cells must be square.*cell_size"):  # one side alone: refused, the fix named
        _case("cells.0=60")


@pytest.mark.parametrize("cmd", ["steady", "sweep"])
@pytest.mark.parametrize(
    "item,words",
    [
        ("bogus=1", ("unknown setting 'bogus'", "valid keys", "cell_size", "t_max", "mu_i")),
        ("mu_i.bogus=1", ("mu_i.bogus",)),
        ("t_max=nan", ("t_max", "nan")),
        ("t_max=inf", ("t_max", "inf")),
        ("cell_size=nan", ("cell_size", "nan")),
        ("t_max=true", ("t_max", "true/false")),
        ("cell_size=true", ("cell_size", "True")),
        ("mu_s=-1", ("mu_s", "-1")),
        ("flip=high", ("flip", "'high'")),
        ("cells=[0, 10]", ("cells.0", "0")),
        ("t_max", ("KEY=VALUE", "'t_max'")),
    ],
)
def test_a_bad_key_or_value_is_one_line_naming_it_before_compute(tmp_path, cmd, item, words):
    out = tmp_path / "o"
    _refused(_run("mpm", cmd, "--quick", "--serial", "--out", out, "--set", item) if cmd == "sweep"
             else _run("mpm", cmd, "--quick", "--out", out, "--set", item), *words)  # fmt: skip
    assert not out.exists() or not any(out.iterdir())


def test_a_bad_settings_file_is_one_line(tmp_path):
    _refused(_run("mpm", "steady", "--quick", "--settings", tmp_path / "missing.toml"), "--settings", "no such file")
    bad = tmp_path / "bad.toml"
    bad.write_text("t_max = \n")
    _refused(_run("mpm", "steady", "--quick", "--settings", bad), "--settings", "invalid TOML")
    bad.write_text("[contact]\nband = 1\n")
    _refused(_run("mpm", "steady", "--quick", "--settings", bad), "contact")
    bad.write_text("cell_size = -0.01\n")
    _refused(_run("mpm", "steady", "--quick", "--settings", bad), "cell_size", "-0.01")


KEYS = [
    *MPMSettings.model_fields,
    "cell_size",
    "length",
    "contact_band",
    "mu_i_diameter",
    "fluidity_diameter",
    "mu_i.grain_diameter",
    "fluidity.amplitude",
    "cells.0",
    "domain.1",
    "treadmill.0",
]
VALUES = st.one_of(
    st.sampled_from([math.nan, math.inf, -math.inf, 0.0, -1.0, 1e30, 1e-30, 1e-320, True, False, 0, -3, 10**12]),
    st.floats(allow_nan=True, allow_infinity=True),
    st.integers(min_value=-(10**6), max_value=10**6),
    st.sampled_from(["linear", "band", "cpu", "", "x"]),
    st.lists(st.floats(min_value=-2, max_value=2), max_size=3),
)


@settings(max_examples=300, deadline=None, derandomize=True)
@given(key=st.sampled_from(KEYS), value=VALUES)
def test_any_key_and_value_is_valid_settings_or_an_input_error_naming_the_key(key, value):
    """The property the command line relies on: a --set is either applied (settings that pass
    their validation) or refused with an InputError that names the key; never another exception."""
    from intrusim._checks import InputError
    from intrusim.scenarios.mpm_settings import apply_settings

    try:
        s = apply_settings(quick_settings("wheel"), [(key, value)])
    except InputError as err:
        names = {key, key.split(".")[0]} | {"contact_band": {"contact_band_cells"}}.get(key, set())
        cross = ("t_max must exceed", "bed length must exceed", "treadmill", "cells.")  # checks across fields
        assert any(n in str(err) for n in names) or any(c in str(err) for c in cross), (key, value, str(err))
        return
    assert isinstance(s, MPMSettings)


# ---------------------------------------------------------------- --version, mpm run --threads


def test_version_names_the_package():
    from intrusim import __version__

    for args in (["--version"], ["version"]):
        r = _run(*args)
        assert r.exit_code == 0 and r.output.strip() == f"intrusim {__version__}"


TINY = tiny_config(0.01)


def test_mpm_run_threads_sets_the_backend_and_a_bad_count_is_refused(tmp_path):
    cfg = tmp_path / "tiny.toml"
    cfg.write_text(TINY)
    r = _run("mpm", "run", cfg, "--out", tmp_path / "run", "--threads", "1")
    assert r.exit_code == 0, r.output
    assert json.loads((tmp_path / "run" / "config.json").read_text())["config"]["backend"]["cpu_threads"] == 1
    _refused(_run("mpm", "run", cfg, "--threads", "0"), "backend.cpu_threads", "0")
    _refused(_run("mpm", "steady", "--quick", "--threads", "0"), "--threads", "0")


# ---------------------------------------------------------------- mpm sweep --omega-rpm


def test_mpm_sweep_takes_the_omega_syntax_of_sweep_and_records_its_settings(tmp_path, monkeypatch):
    import intrusim.analysis.sweep as sweep_module
    from intrusim.analysis.sweep import SweepResult
    from intrusim.scenarios.mpm_settings import read_record

    seen = {}

    def fake_sweep(case, kind, omegas, **kwargs):
        seen.update(omegas=list(omegas), case=case)
        return SweepResult(case.name, kind, None, [{"omega_rpm": w, "ok": False, "error": "x"} for w in omegas])

    monkeypatch.setattr(sweep_module, "sweep_omega", fake_sweep)
    r = _run("mpm", "sweep", "--quick", "--serial", "--omega-rpm", "10:30:10", "--out", tmp_path, "--set", "flip=1")
    assert r.exit_code == 1, r.output  # every (fake) point failed
    assert seen["omegas"] == [10.0, 20.0, 30.0] and seen["case"].mpm.flip == 1.0
    record = read_record(tmp_path / "grousered_wheel_mpm_sweep.csv")
    assert sorted(record) == [10.0, 20.0, 30.0] and record[20.0]["flip"] == 1.0
    r = _run("mpm", "sweep", "--quick", "--serial", "--omega-rpm", "10,25", "--out", tmp_path)
    assert seen["omegas"] == [10.0, 25.0]
    _refused(_run("mpm", "sweep", "--quick", "--serial", "--omega-rpm", "10:90:0", "--out", tmp_path), "omega range")
    _refused(_run("mpm", "sweep", "--quick", "--serial", "--omega-rpm", "10,x", "--out", tmp_path), "omega list")


# ---------------------------------------------------------------- reproduce: the runs' settings


def _sweep_csv(folder, omegas=(10.0, 30.0, 50.0, 70.0, 90.0)):
    folder.mkdir(parents=True, exist_ok=True)
    rows = ["omega_rpm,ok,velocity,sinkage,slip,velocity_std,sinkage_std,drift,settled,error"]
    rows += [f"{w},True,{0.002 * w},0.02,0.3,0,0,0,True," for w in omegas]
    path = folder / "grousered_wheel_mpm_sweep.csv"
    path.write_text("\n".join(rows) + "\n")
    return path, omegas


def test_reproduce_refuses_a_sweep_of_other_settings_and_takes_one_of_the_case_asked_for(tmp_path):
    from intrusim.scenarios.mpm_settings import write_record

    runs = tmp_path / "runs"
    path, omegas = _sweep_csv(runs)
    band = _case("contact_band=0").mpm
    write_record(path, "grousered_wheel", {w: band for w in omegas})
    args = ["reproduce", "fig3ab", "--quick", "--no-parallel", "--runs", runs, "--out", tmp_path / "fig"]
    _refused(_run(*args), "grousered_wheel_mpm_sweep.csv", "other settings", "contact, contact_band_cells")
    assert not (tmp_path / "fig").exists()
    r = _run(*args, "--set", "contact_band=0")  # the case of those runs
    assert r.exit_code == 0, r.output
    assert (tmp_path / "fig" / "fig3ab.png").exists()
    # a record of the quick settings themselves (thread count and arch are no difference)
    write_record(path, "grousered_wheel", {w: quick_settings("wheel").validated_copy(cpu_threads=1) for w in omegas})
    assert _run(*args).exit_code == 0
    _refused(_run(*args, "--set", "flip=1"), "flip")
    _refused(_run(*args, "--set", "bogus=1"), "unknown setting 'bogus'")
    # a CSV without a record: the run folders beside it, else a warning
    path.with_name("grousered_wheel_mpm_sweep.settings.json").unlink()
    r = _run(*args)
    assert r.exit_code == 0 and "records no settings" in r.output, r.output
    folder = runs / "grousered_wheel_30rpm"
    folder.mkdir()
    (folder / "locomotion.json").write_text(json.dumps({"settings": band.model_dump(mode="json")}))
    _refused(_run(*args), "grousered_wheel_30rpm", "contact, contact_band_cells")


def test_reproduce_mpm_refuses_a_run_folder_of_other_settings_before_any_compute(tmp_path):
    runs = tmp_path / "runs"
    folder = runs / "grousered_wheel_30rpm"
    folder.mkdir(parents=True)
    other = quick_settings("wheel").validated_copy(mu_s=0.4, t_max=1.5)
    (folder / "locomotion.json").write_text(json.dumps({"settings": other.model_dump(mode="json")}))
    (folder / "result.json").write_text("{}")
    args = ["reproduce", "fig5c", "--quick", "--no-parallel", "--runs", runs, "--out", tmp_path / "fig"]
    _refused(_run(*args), "grousered_wheel_30rpm", "differs in mu_s, t_max")
    # a shorter recorded run is the same case (it is extended), so only mu_s differs
    shorter = other.validated_copy(t_max=1.0)
    (folder / "locomotion.json").write_text(json.dumps({"settings": shorter.model_dump(mode="json")}))
    _refused(_run(*args), "differs in mu_s)")


# ---------------------------------------------------------------- refused before compute (review fixes)


@pytest.mark.parametrize(
    "sets,words",
    [
        (["cells=5", "length=0.5"], ("cells", "5", "length")),
        (["domain=[0,1]", "length=1"], ("domain.0", "0", "length")),
        (["domain=[0,1]", "cell_size=0.1"], ("domain.0", "0", "cell_size")),
        (["cells=[10]", "cell_size=0.1"], ("cells.1", "cell_size")),
        (["domain=[1,inf]", "cell_size=0.1"], ("domain.1", "inf", "cell_size")),
    ],
)
def test_a_derived_key_after_a_bad_field_names_the_field_not_an_internal_error(tmp_path, sets, words):
    args = [a for s in sets for a in ("--set", s)]
    _refused(_run("mpm", "steady", "--quick", "--out", tmp_path / "o", *args), *words)
    assert not (tmp_path / "o").exists()


@settings(max_examples=300, deadline=None, derandomize=True)
@given(first=st.sampled_from(["domain", "cells", "domain.0", "cells.1"]), value=VALUES,
       derived=st.sampled_from(["cell_size", "length"]), size=st.sampled_from([0.02, 0.5, 1.0]))  # fmt: skip
def test_any_field_then_a_derived_key_is_valid_settings_or_an_input_error(first, value, derived, size):
    """A derived key reads fields a --set before it may have made bad: an InputError, never another exception."""
    from intrusim._checks import InputError
    from intrusim.scenarios.mpm_settings import apply_settings

    try:
        s = apply_settings(quick_settings("wheel"), [(first, value), (derived, size)])
    except InputError:
        return
    assert isinstance(s, MPMSettings)


@pytest.mark.parametrize("cmd", ["steady", "sweep"])
def test_an_unknown_precision_is_refused_before_compute(tmp_path, cmd):
    from typing import get_args

    from intrusim.mpm.backend import PRECISIONS
    from intrusim.mpm.config import Precision

    assert get_args(Precision) == PRECISIONS  # the settings take what the backend does
    out = tmp_path / "o"
    extra = ["--serial", "--omega-rpm", "30"] if cmd == "sweep" else []
    _refused(_run("mpm", cmd, "--quick", *extra, "--out", out, "--set", "precision=f16"), "precision", "f16")
    assert not out.exists()
    assert _case("precision=f64").mpm.precision == "f64"


def test_mpm_sweep_refuses_a_point_beyond_reach_before_any_point_runs_or_file_is_made(tmp_path, monkeypatch):
    import intrusim.analysis.sweep as sweep_module

    def no_sweep(*args, **kwargs):
        raise AssertionError("a point ran")

    monkeypatch.setattr(sweep_module, "sweep_omega", no_sweep)
    out = tmp_path / "o"
    args = ["mpm", "sweep", "--quick", "--serial", "--out", out]
    _refused(_run(*args, "--omega-rpm", "30", "--set", "cell_size=1e-6"), "domain.cells", "cells")
    _refused(_run(*args, "--omega-rpm", "30,60", "--set", "max_steps=10"), "time.max_steps")
    _refused(_run(*args, "--omega-rpm", "30,0"), "omega_rpm", "0")
    _refused(_run(*args, "--omega-rpm", ","), "--omega-rpm", "','")
    assert not out.exists()


def test_frames_every_is_a_difference_of_the_runs_settings():
    """frames_every sets the chunks a run advances by (when the drop is sampled, the treadmill
    shifts): a run recorded with another one is another case; the thread count is not."""
    from intrusim.scenarios.mpm_settings import RUN_CONTROL, settings_differences

    base = quick_settings("wheel")
    assert "frames_every" not in RUN_CONTROL
    recorded = base.validated_copy(frames_every=0.01).model_dump(mode="json")
    assert settings_differences(recorded, base) == ["frames_every"]
    assert settings_differences(base.validated_copy(cpu_threads=1).model_dump(mode="json"), base) == []


def test_mpm_collect_removes_the_record_of_an_earlier_sweep_when_its_runs_record_none(tmp_path, monkeypatch):
    import intrusim.analysis.sweep as sweep_module
    import intrusim.scenarios.mpm_locomotion as loco
    from intrusim.scenarios.mpm_settings import read_record, record_path, write_record

    monkeypatch.setattr(loco, "load_result", lambda run, t_start=None: run)
    monkeypatch.setattr(sweep_module, "steady_record", lambda w, st: {"omega_rpm": w, "ok": False, "error": "x"})
    for w in (30, 60):  # runs written before settings were recorded
        run = tmp_path / f"grousered_wheel_{w}rpm"
        run.mkdir()
        (run / "result.json").write_text("{}")
        (run / "locomotion.json").write_text(json.dumps({"scenario": {"name": "grousered_wheel"}, "omega_rpm": w}))
    csv_path = tmp_path / "grousered_wheel_mpm_sweep.csv"
    write_record(csv_path, "grousered_wheel", {10.0: quick_settings("wheel")})  # an earlier sweep's
    r = _run("mpm", "collect", tmp_path)
    assert r.exit_code == 0, r.output
    assert csv_path.exists() and not record_path(csv_path).exists() and read_record(csv_path) is None


# figs1: a treadmill inside the Table S1 wheel's 1 m box but beyond the half-size wheel's 0.5 m one
@pytest.mark.parametrize(
    "figure,item",
    [("fig5ab", "flip=2"), ("fig7bc", "length=0.1"), ("fig4b", "t_max=nan"), ("figs1", "treadmill=[0.6, 0.3]")],
)
def test_reproduce_refuses_a_bad_setting_value_before_any_curve_is_computed(tmp_path, monkeypatch, figure, item):
    import intrusim.figures.rft as rft

    def no_curves(*args, **kwargs):
        raise AssertionError("a curve was computed")

    monkeypatch.setattr(rft, "_curves", no_curves)
    out = tmp_path / "fig"
    args = ["reproduce", figure, "--quick", "--no-parallel", "--mpm", "--runs", tmp_path / "runs", "--out", out]
    _refused(_run(*args, "--set", item), item.split("=")[0])
    assert not out.exists() and not (tmp_path / "runs").exists()


def test_the_slow_list_names_tests_that_exist():
    """Each entry of tests/conftest.py's SLOW is a test file, or a test function in one."""
    import importlib.util
    from pathlib import Path

    root = Path(__file__).resolve().parents[2]
    spec = importlib.util.spec_from_file_location("_conftest", root / "tests" / "conftest.py")
    conftest = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(conftest)
    missing = []
    for entry in conftest.SLOW:
        path, _, test = entry.partition("::")
        file = root / path
        if not file.is_file() or (test and f"def {test}(" not in file.read_text()):
            missing.append(entry)
    assert not missing, missing
