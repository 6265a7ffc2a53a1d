"""Fault test: `intrusim mpm run` killed (SIGKILL) at random moments, twice, then `mpm resume`d to
its end, gives the uninterrupted run's time series and end state bit for bit, and leaves no
temporary file (one thread: the sums do not depend on the thread order)."""

import os
import random
import signal
import subprocess
import sys
import time

import numpy as np
import pytest
from cli_helpers import block_config

from intrusim.mpm import io as mpm_io

CONFIG = block_config(t_end=0.3, z=0.065, omega=-2.0, record_every=0.005, checkpoint_every=0.01, ramp_time=0.05)


def _cli(*args):
    return [sys.executable, "-m", "intrusim.cli", *map(str, args)]


def _env():
    return {**os.environ, "TI_LOG_LEVEL": "error"}


@pytest.fixture(scope="module")
def reference(tmp_path_factory):
    folder = tmp_path_factory.mktemp("reference")
    (folder / "c.toml").write_text(CONFIG)
    r = subprocess.run(
        _cli("mpm", "run", folder / "c.toml", "--out", folder / "run"),
        capture_output=True,
        text=True,
        env=_env(),
        timeout=300,
    )
    assert r.returncode == 0, r.stderr
    return folder / "c.toml", folder / "run"


def _kill_at_random(cmd, run_dir, rng) -> bool:
    """Start ``cmd``; once the run folder has a checkpoint, SIGKILL it after a random delay. True if killed."""
    proc = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, env=_env())
    try:
        deadline = time.monotonic() + 120
        ckpt = run_dir / "checkpoint.npz"
        start = ckpt.stat().st_mtime_ns if ckpt.exists() else None
        while time.monotonic() < deadline and proc.poll() is None:
            if ckpt.exists() and ckpt.stat().st_mtime_ns != start:
                break
            time.sleep(0.01)
        time.sleep(rng.uniform(0.0, 0.4))
        if proc.poll() is not None:
            return False
        proc.send_signal(signal.SIGKILL)
        proc.wait(timeout=30)
        return True
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()


@pytest.mark.parametrize("seed", [1, 2])
def test_a_run_killed_at_random_moments_resumes_bit_for_bit(tmp_path, reference, seed):
    config, ref = reference
    rng = random.Random(seed)
    run = tmp_path / "run"
    killed = [_kill_at_random(_cli("mpm", "run", config, "--out", run), run, rng)]
    killed.append(_kill_at_random(_cli("mpm", "resume", run), run, rng))
    assert any(killed), "the run ended before it could be killed: make CONFIG longer"
    r = subprocess.run(_cli("mpm", "resume", run), capture_output=True, text=True, env=_env(), timeout=300)
    assert r.returncode == 0, r.stderr
    assert (run / "timeseries.csv").read_text() == (ref / "timeseries.csv").read_text()
    a, meta_a = mpm_io.load_checkpoint(run / "checkpoint.npz")
    b, meta_b = mpm_io.load_checkpoint(ref / "checkpoint.npz")
    assert meta_a["step_count"] == meta_b["step_count"] and meta_a["bodies"] == meta_b["bodies"]
    assert meta_a["rows"] == meta_b["rows"]
    for key in b:
        np.testing.assert_array_equal(a[key], b[key], err_msg=key)
    assert not list(run.rglob("*.tmp"))
