"""A run folder's lock: held for the block, refused to a second writer, and gone afterwards."""

import pytest

from intrusim._checks import InputError
from intrusim.mpm.io import LOCK, run_lock


def test_the_lock_refuses_a_second_writer_and_leaves_no_file(tmp_path):
    run = tmp_path / "run"
    with run_lock(run):
        assert (run / LOCK).exists()
        with pytest.raises(InputError, match="in use by another run"):
            with run_lock(run):
                pass
        (run / "result.json").write_text("{}")
    assert not (run / LOCK).exists() and (run / "result.json").exists()
    with run_lock(run):  # taken again after release
        pass
    assert sorted(p.name for p in run.iterdir()) == ["result.json"]


def test_a_folder_made_for_a_run_that_wrote_nothing_is_removed(tmp_path):
    run = tmp_path / "failed_30rpm"
    with pytest.raises(RuntimeError):
        with run_lock(run):
            raise RuntimeError("the run was refused before writing anything")
    assert not run.exists()
    kept = tmp_path / "kept"
    kept.mkdir()
    with run_lock(kept):  # a folder that was there before stays, empty or not
        pass
    assert kept.is_dir() and not any(kept.iterdir())
