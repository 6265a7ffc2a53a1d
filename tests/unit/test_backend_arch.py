"""The Taichi backend: what runs is what is reported, a missing GPU is said out loud, and the
GPU-facing command-line and benchmark options refuse bad input before any compute.

Taichi is initialised once per process, so each backend request runs in a fresh interpreter.
"""

import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from intrusim.cli import app

ROOT = Path(__file__).resolve().parents[2]

PROBE = """
import json, warnings
with warnings.catch_warnings(record=True) as caught:
    warnings.simplefilter("always")
    from intrusim.mpm.backend import arch_in_use, ensure_initialized
    b = ensure_initialized({arch!r}, "f32", 1)
    again = ensure_initialized({arch!r}, "f32", 1)  # the same request again: no second warning
print(json.dumps({{"arch": b.arch, "requested": b.requested, "fell_back": b.fell_back, "taichi": arch_in_use(),
                  "same": again is b, "warnings": [str(w.message) for w in caught if w.category is RuntimeWarning]}}))
"""


def _probe(arch: str, **env) -> dict:
    proc = subprocess.run(
        [sys.executable, "-c", PROBE.format(arch=arch)],
        capture_output=True,
        text=True,
        env={**os.environ, "INTRUSIM_TI_ARCH": "", **env},
        timeout=120,
    )
    assert proc.returncode == 0, proc.stderr[-2000:]
    return json.loads(proc.stdout.strip().splitlines()[-1])


def test_a_requested_gpu_reports_the_backend_that_really_runs():
    got = _probe("cuda")
    assert got["requested"] == "cuda" and got["same"]
    assert got["arch"] == got["taichi"]  # read back from Taichi, not copied from the request
    if got["arch"] == "cpu":  # no CUDA here (CI): Taichi fell back, and we say so once
        assert got["fell_back"]
        assert len(got["warnings"]) == 1 and "running on the CPU" in got["warnings"][0]
    else:
        assert got["arch"] == "cuda" and not got["fell_back"] and not got["warnings"]


def test_the_cpu_is_no_fallback():
    got = _probe("cpu")
    assert got == {"arch": "cpu", "requested": "cpu", "fell_back": False, "taichi": "cpu", "same": True, "warnings": []}


def test_the_environment_overrides_the_callers_arch():
    got = _probe("cuda", INTRUSIM_TI_ARCH="cpu")
    assert got["requested"] == "cpu" and got["arch"] == "cpu" and not got["fell_back"] and not got["warnings"]


def test_a_bad_arch_in_the_environment_is_refused_by_name():
    proc = subprocess.run(
        [sys.executable, "-c", PROBE.format(arch="cpu")],
        capture_output=True,
        text=True,
        env={**os.environ, "INTRUSIM_TI_ARCH": "tpu"},
        timeout=120,
    )
    assert proc.returncode != 0
    assert "INTRUSIM_TI_ARCH" in proc.stderr and "'tpu'" in proc.stderr


@pytest.mark.parametrize("command", ["steady", "sweep"])
def test_cli_refuses_an_unknown_arch_before_compute(command, tmp_path):
    r = CliRunner().invoke(app, ["mpm", command, "--quick", "--set", "arch=tpu", "--out", str(tmp_path / "o")])
    assert r.exit_code == 2
    assert "arch: must be one of cpu, cuda, vulkan, metal, gpu" in r.output and "'tpu'" in r.output
    assert not (tmp_path / "o").exists() or not any((tmp_path / "o").iterdir())


def _benchmark_module(name: str):
    sys.path.insert(0, str(ROOT / "benchmarks"))
    try:
        return __import__(name)
    finally:
        sys.path.pop(0)


def test_gpu_check_compares_series_recorded_at_the_same_times():
    gc = _benchmark_module("gpu_check")
    t = [0.0, 0.005, 0.01]
    a = {"series": {"time": t, **{k: [1.0, 2.0, -4.0] for k in gc.SERIES}}}
    b = {"series": {"time": t, **{k: [1.0, 2.5, -4.0] for k in gc.SERIES}}}
    d = gc.compare(a, b)
    assert set(d) == set(gc.SERIES)
    assert d["x"]["max_abs_diff"] == pytest.approx(0.5) and d["x"]["relative"] == pytest.approx(0.5 / 4.0)
    assert d["z"]["end_a"] == -4.0 and d["z"]["end_b"] == -4.0
    assert all(v["max_abs_diff"] == 0.0 for v in gc.compare(a, a).values())
    late = {"series": {**b["series"], "time": list(np.asarray(t) + 0.001)}}
    with pytest.raises(ValueError, match="different times"):
        gc.compare(a, late)


@pytest.mark.parametrize(
    "args, message",
    [
        (["--cases", "64k,2M"], "unknown ['2M']"),
        (["--repeat", "0"], "--repeat must be >= 1"),
    ],
)
def test_bench_mpm_refuses_bad_options_before_compute(args, message):
    proc = subprocess.run(
        [sys.executable, str(ROOT / "benchmarks" / "bench_mpm.py"), *args], capture_output=True, text=True, timeout=60
    )
    assert proc.returncode == 2 and message in proc.stderr


def test_gpu_check_refuses_a_non_positive_time():
    proc = subprocess.run(
        [sys.executable, str(ROOT / "benchmarks" / "gpu_check.py"), "--t-end", "0"],
        capture_output=True,
        text=True,
        timeout=60,
    )
    assert proc.returncode == 2 and "--t-end and --record-every must be > 0" in proc.stderr


def test_gpu_check_on_the_cpu_against_itself_finds_no_difference(tmp_path):
    # the script end to end, with the CPU in the GPU's place: two processes from the same state give
    # the same numbers bit for bit (the CPU's P2G sums in a fixed order), and it says so
    out = tmp_path / "check.json"
    proc = subprocess.run(
        [
            sys.executable,
            str(ROOT / "benchmarks" / "gpu_check.py"),
            "--arch",
            "cpu",
            "--threads",
            "1",
            "--t-end",
            "0.003",
            "--record-every",
            "0.001",
            "--json",
            str(out),
        ],
        capture_output=True,
        text=True,
        timeout=300,
        env={**os.environ, "INTRUSIM_TI_ARCH": ""},
    )
    assert proc.returncode == 0, proc.stderr[-2000:]
    got = json.loads(out.read_text())
    assert [r["arch"] for r in got["runs"]] == ["cpu", "cpu"]
    assert len(got["runs"][0]["series"]["time"]) == 4  # t = 0 and every 1 ms to 3 ms
    assert all(d["max_abs_diff"] == 0.0 for d in got["difference"].values())
    assert got["difference"]["fz"]["max_abs"] > 0.0  # the wheel touches the bed: a force was compared
    assert "cpu / cpu speed" in proc.stdout and "largest difference" in proc.stdout
