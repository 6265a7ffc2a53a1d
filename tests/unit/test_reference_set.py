"""The MPM reference set (figures/reference_set.py, `intrusim mpm references`): its bodies, a quick
part made and reused, the tables and the index."""

import csv
import json
import math

import pytest
from cli_helpers import refused, run

from intrusim._checks import InputError
from intrusim.figures import reference_set as rs
from intrusim.scenarios import get_scenario, grousered_wheel_scenario
from intrusim.scenarios.mpm_locomotion import mpm_config, quick_settings
from intrusim.scenarios.mpm_settings import apply_settings


def test_the_set_names_its_bodies_and_refuses_an_unknown_part():
    assert [s.name for s in rs.SWEEPS] == [
        "wheel", "small-wheel", "wheel-10-grousers", "wheel-30-grousers", "wheel-tall-grousers", "runner"
    ]  # fmt: skip
    assert rs.selected(["alpha-map", "wheel"]) == ["wheel", "alpha-map"]  # the set's order
    with pytest.raises(InputError, match="unknown reference.*'wheels'"):
        rs.selected(["wheel", "wheels"])
    refused(run("mpm", "references", "--only", "wheel,plates"), "plates", "alpha-map")


def test_the_wheel_variants_differ_from_the_table_s1_wheel_only_where_named():
    base = grousered_wheel_scenario()
    ten, thirty, tall = (get_scenario(f"wheel-{v}") for v in ("10-grousers", "30-grousers", "tall-grousers"))
    assert (ten.lug_count, thirty.lug_count, tall.lug_count) == (10, 30, base.lug_count)
    assert tall.lug_height == 2 * base.lug_height and tall.hub_diameter == base.hub_diameter
    assert tall.radius == pytest.approx(base.radius + base.lug_height)
    assert tall.length_scale == pytest.approx(2 * tall.radius)
    for s in (ten, thirty, tall):
        assert s.mass_x == base.mass_x and s.mass_z == base.mass_z and s.force_model == base.force_model
    assert len({base.name, ten.name, thirty.name, tall.name}) == 4  # run folders apart


def test_the_tall_wheel_gets_a_taller_quick_box():
    sweep = next(s for s in rs.SWEEPS if s.name == "wheel-tall-grousers")
    tall, quick = sweep.scenario(), quick_settings("wheel")
    with pytest.raises(InputError, match="does not fit"):
        mpm_config(tall, quick, 30.0)
    s = apply_settings(quick, sweep.settings_items(True))
    assert s.domain[1] > quick.domain[1] and s.domain[1] / s.cells[1] == pytest.approx(quick.domain[1] / quick.cells[1])
    mpm_config(tall, s, 30.0)  # fits
    assert sweep.settings_items(False) == []


def test_a_quick_part_is_made_tabled_and_reused(tmp_path, monkeypatch):
    monkeypatch.setattr(rs, "MAP_QUICK_DEG", ((0.0, 90.0),))  # one plate pushed down
    out = tmp_path / "refs"
    r = run("mpm", "references", "--quick", "--only", "wheel-10-grousers,alpha-map", "--out", out, "--workers", 1)
    assert r.exit_code == 0, r.output
    rows = list(csv.DictReader((out / "wheel-10-grousers_mpm.csv").open()))
    assert [float(x["omega_rpm"]) for x in rows] == [30.0, 90.0] and all(x["ok"] == "True" for x in rows)
    assert float(rows[1]["velocity_m_s"]) > float(rows[0]["velocity_m_s"]) > 0  # faster at the higher spin
    assert (out / "wheel-10-grousers_mpm.settings.json").is_file()
    plates = list(csv.DictReader((out / "alpha_map.csv").open()))
    assert len(plates) == 1 and float(plates[0]["alpha_z_N_m3"]) > 0  # pushed down: resisted upwards
    assert float(plates[0]["beta_rad"]) == 0.0 and float(plates[0]["gamma_rad"]) == pytest.approx(math.pi / 2)
    index = json.loads((out / "references.json").read_text())
    assert index["quick"] and set(index["parts"]) == {"wheel-10-grousers", "alpha-map"}
    assert index["parts"]["wheel-10-grousers"]["failed_omega_rpm"] == []
    # again: every run reused, nothing recomputed
    done = sorted(out.rglob("result.json")) + sorted((out / "alpha_map").glob("*.json"))
    stamps = [p.stat().st_mtime_ns for p in done]
    r = run("mpm", "references", "--quick", "--only", "wheel-10-grousers,alpha-map", "--out", out, "--workers", 1)
    assert r.exit_code == 0, r.output
    assert len(done) == 3 and [p.stat().st_mtime_ns for p in done] == stamps


def test_workers_sets_the_mpm_runs_at_once_for_the_sweeps_and_the_map(tmp_path, monkeypatch):
    """``--workers N`` reaches each sweep (mpm_sweep_table's ``workers``) and the map's plates (the
    Dask map's ``n_workers``); none given: None to both (one per core). No MPM runs here."""
    from types import SimpleNamespace

    import intrusim.analysis.sweep as sweep_mod
    import intrusim.figures.mpm as figures_mpm

    seen: list[tuple[str, object]] = []

    def fake_table(scn, omegas, quick, root, items, csv_path, workers=None):
        seen.append(("sweep", workers))
        return SimpleNamespace(records=[])

    def fake_map(fn, args, n_workers=None, **kwargs):
        seen.append(("map", n_workers))
        return []

    monkeypatch.setattr(figures_mpm, "mpm_sweep_table", fake_table)
    monkeypatch.setattr(sweep_mod, "dask_map", fake_map)
    monkeypatch.setattr(rs, "MAP_QUICK_DEG", ((0.0, 90.0),))
    rs.make_references(tmp_path, quick=True, only=["wheel", "runner", "alpha-map"], workers=3, echo=lambda s: None)
    assert seen == [("sweep", 3), ("sweep", 3), ("map", 3)]
    seen.clear()
    r = run("mpm", "references", "--quick", "--only", "wheel,alpha-map", "--out", tmp_path, "--workers", 2)
    assert r.exit_code == 0, r.output
    assert seen == [("sweep", 2), ("map", 2)]
    seen.clear()
    rs.make_references(tmp_path, quick=True, only=["small-wheel"], echo=lambda s: None)
    assert seen == [("sweep", None)]
