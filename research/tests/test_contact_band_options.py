"""research/mpm_contact_band.py wheel: the set-up options a Froude twin scales (--start-x,
--youngs-modulus, --ramp-time, --chunk, --cfl) and the transfer's --flip and --shape are validated before any
simulation starts."""

import subprocess
import sys
from pathlib import Path

import pytest

SCRIPT = Path(__file__).resolve().parents[1] / "mpm_contact_band.py"


def _run(*options: str) -> subprocess.CompletedProcess:
    return subprocess.run(
        [sys.executable, str(SCRIPT), "wheel", "30", *options], capture_output=True, text=True, timeout=120
    )


@pytest.mark.parametrize("option, value, field", [("--youngs-modulus", "-1", "youngs_modulus"), ("--cfl", "1.5", "cfl"),
                                                  ("--chunk", "0", "chunk"), ("--ramp-time", "-0.1", "ramp_time"),
                                                  ("--flip", "1.5", "flip")])  # fmt: skip
def test_a_bad_setting_is_refused_by_name(option, value, field, tmp_path):
    res = _run(option, value, "--out", str(tmp_path))
    assert res.returncode != 0
    assert "bad setting" in res.stderr and field in res.stderr
    assert not any(tmp_path.iterdir())  # nothing ran, nothing written


def test_a_start_past_the_treadmill_trigger_is_refused(tmp_path):
    res = _run("--domain", "0.5", "0.2", "--treadmill", "0.325", "0.25", "--start-x", "0.4", "--out", str(tmp_path))
    assert res.returncode != 0 and "must lie ahead of start_x" in res.stderr
    assert not any(tmp_path.iterdir())


def test_an_unknown_shape_is_refused(tmp_path):
    res = _run("--shape", "cubic", "--out", str(tmp_path))
    assert res.returncode == 2 and "invalid choice: 'cubic'" in res.stderr
    assert not any(tmp_path.iterdir())
