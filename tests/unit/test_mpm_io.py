"""Run-folder files are replaced whole or not at all (nothing lost when a write fails)."""

import numpy as np
import pytest

from intrusim.mpm.io import atomic_write_bytes, load_checkpoint, save_checkpoint, write_csv


def test_checkpoint_round_trip_leaves_no_temporary(tmp_path):
    path = tmp_path / "checkpoint.npz"
    save_checkpoint(path, {"x": np.arange(6.0).reshape(3, 2)}, {"step_count": 7})
    arrays, meta = load_checkpoint(path)
    np.testing.assert_array_equal(arrays["x"], np.arange(6.0).reshape(3, 2))
    assert meta == {"step_count": 7}
    assert [p.name for p in tmp_path.iterdir()] == ["checkpoint.npz"]


def test_failed_checkpoint_keeps_the_previous_one(tmp_path):
    path = tmp_path / "checkpoint.npz"
    save_checkpoint(path, {"x": np.ones(4)}, {"step_count": 1})
    before = path.read_bytes()

    class Unsaveable:  # np.savez fails on it half-way through the archive
        def __array__(self, *args, **kwargs):
            raise RuntimeError("disk full")

    with pytest.raises(RuntimeError, match="disk full"):
        save_checkpoint(path, {"x": np.zeros(4), "y": Unsaveable()}, {"step_count": 2})
    assert path.read_bytes() == before
    assert [p.name for p in tmp_path.iterdir()] == ["checkpoint.npz"]


def test_failed_write_keeps_the_previous_file(tmp_path):
    path = tmp_path / "config.json"
    atomic_write_bytes(path, b"old")
    with pytest.raises(TypeError):
        atomic_write_bytes(path, "not bytes")  # the write fails after the temporary exists
    assert path.read_bytes() == b"old"
    assert [p.name for p in tmp_path.iterdir()] == ["config.json"]


def test_csv_columns_are_the_union_in_order_of_first_appearance(tmp_path):
    path = tmp_path / "ts.csv"
    write_csv(path, [{"time": 0.0, "fx": 1.0}, {"time": 0.1, "fx": 2.0, "fx_ahead": 1.5}])
    assert path.read_text().splitlines() == ["time,fx,fx_ahead", "0.0,1.0,", "0.1,2.0,1.5"]


def test_cached_json_computes_once_and_then_reads_the_file(tmp_path):
    from intrusim.mpm.io import cached_json

    calls = []
    path = tmp_path / "sub" / "run.json"
    compute = lambda: calls.append(1) or {"drag": [1.5, 2.0]}  # noqa: E731
    assert cached_json(path, compute) == {"drag": [1.5, 2.0]}
    assert cached_json(path, compute) == {"drag": [1.5, 2.0]}
    assert len(calls) == 1 and path.exists()
