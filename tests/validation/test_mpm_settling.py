"""Settled by construction: a coarse MPM run stops once its stop test holds, and one that cannot
settle says what it is doing (entrapment), with result.json carrying the outcome."""

import json

import numpy as np
import pytest
from cli_helpers import refused, run

from intrusim._checks import InputError
from intrusim.analysis.settling import settling
from intrusim.scenarios import get_scenario
from intrusim.scenarios.mpm_locomotion import quick_settings, refuse_other_settings, run_mpm_steady, summarise_run


def test_a_run_stops_once_settled_and_answers_with_its_last_revolution(tmp_path):
    # the runner at 200 RPM on 2 cm cells holds v and sinkage within 5 % a revolution by about 1.2 s
    s = quick_settings("runner").validated_copy(settle_tol=0.05, t_max=2.5, cpu_threads=1)
    st = run_mpm_steady(get_scenario("runner"), s, 200.0, tmp_path / "run")
    w = 60.0 / 200.0  # one revolution, s
    assert st.settled and st.outcome == "settled" and st.meta["stop"] == "settled"
    assert st.window[1] < 2.0  # stopped long before the cap
    assert st.window[1] - st.window[0] == pytest.approx(w, abs=0.02)  # the last revolution's means
    t, v = st.series["time"], st.series["vx"]
    assert st.velocity == pytest.approx(v[t > t[-1] - w].mean(), rel=1e-9)
    judged = settling(t, v, st.series["sinkage"], 200 * 2 * np.pi / 60, s.ramp_time + s.settle_time, 0.05)
    assert judged.settled and judged.dv < 0.05 and judged.ds < 0.05
    # the same verdict read back from the folder
    again = summarise_run(tmp_path / "run")
    assert again.outcome == "settled" and again.velocity == pytest.approx(st.velocity, rel=1e-9)
    # the folder answers its own stop test: a run without it (to t_max) on this folder is refused, a longer cap is not
    refuse_other_settings(tmp_path / "run", s)
    refuse_other_settings(tmp_path / "run", s.validated_copy(t_max=4.0, cpu_threads=2))
    with pytest.raises(InputError, match="holds a run of another configuration .differs in settle_tol"):
        refuse_other_settings(tmp_path / "run", s.validated_copy(settle_tol=None))


def test_a_wheel_that_digs_itself_in_is_reported_buried_not_averaged_as_steady(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "heavy.toml").write_text('body = "wheel"\nname = "heavy"\nmass_z = 30.0\n')
    args = ["mpm", "steady", "--scenario", "heavy.toml", "--omega-rpm", "90", "--quick", "--threads", "1"]
    r = run(*args, "--set", "t_max=2.0", "--out", "o")
    assert r.exit_code == 0, r.output
    assert "NOT settled (buried: its top" in r.output and "(entrapped)" in r.output and "steady state" not in r.output
    res = json.loads((tmp_path / "o" / "heavy_90rpm" / "result.json").read_text())
    assert res["outcome"] == "buried" and res["settled"] == 0.0 and res["sinkage"] > 2 * 0.106
    assert res["outcome_text"].startswith("buried") and res["sinkage_rate"] > 0


def test_a_cap_shorter_than_the_settle_test_is_refused_before_compute(tmp_path):
    out = tmp_path / "o"
    refused(
        run("mpm", "steady", "--scenario", "runner", "--omega-rpm", "200", "--quick", "--out", out,
            "--set", "settle_tol=0.02", "--set", "t_max=1.0"),
        "t_max (1 s) is shorter than the settle test needs at 200 RPM", "1.2 s",
    )  # fmt: skip
    assert not out.exists() or not any(out.rglob("*.json"))
