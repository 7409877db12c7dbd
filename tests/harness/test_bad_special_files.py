"""Special files inside a results folder, and a full disk during a sweep.

A FIFO or device where a resume expects ``cell.json`` or a table is damage like a torn file:
the cell is recomputed, the read never blocks. A disk that fills during a sweep stops it with
exit 2 and one line naming the path; cells written before stay and the rerun resumes them.
"""
from __future__ import annotations

import errno
import os
import shutil

import pytest

from core.fileio import OutputError
from harness.sweep import store
from harness.sweep.schedule import run_sweep
from harness.sweep.spec import SweepSpec
from harness.sweep.store import cell_dir
from tests.harness.fakes import FAKE, assert_same_tables


def _spec():
    return SweepSpec(name="sf", scenarios=("fast", "slow"), seeds=(0,), duration_s=0.5)


@pytest.fixture(scope="module")
def clean(tmp_path_factory):
    """A completed stand-in sweep, computed once for the module."""
    out = tmp_path_factory.mktemp("clean") / "r"
    run_sweep(_spec(), out, components=FAKE, progress=False)
    return out


@pytest.mark.timeout(60)
@pytest.mark.parametrize("what", ["cell.json", "detections.parquet"])
@pytest.mark.parametrize("kind", ["fifo", "dev_zero"])
def test_special_file_inside_a_cell_is_damage_and_recomputed(tmp_path, clean, what, kind):
    spec = _spec()
    shutil.copytree(clean, tmp_path / "a")
    f = cell_dir(tmp_path / "a", spec.cells()[0]) / what
    f.unlink()
    os.mkfifo(f) if kind == "fifo" else os.symlink("/dev/zero", f)
    assert store.cell_state(f.parent) == "corrupt"
    o = run_sweep(spec, tmp_path / "a", components=FAKE, progress=False)
    assert (o.n_recomputed, o.n_ok, o.n_skipped) == (1, 1, 1)
    assert_same_tables(tmp_path / "a", clean)


def test_full_disk_mid_sweep_stops_it_and_keeps_written_cells(tmp_path, monkeypatch):
    """The second cell's write hits ENOSPC: OutputError naming the path (exit 2 in the CLI),
    not a cell error; the first cell stays and a rerun computes only the second."""
    import pandas as pd
    spec = _spec()
    real = pd.DataFrame.to_parquet
    calls = {"n": 0}

    def to_parquet(self, path, *a, **k):
        if "slow" in str(path):
            raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC), str(path))
        calls["n"] += 1
        return real(self, path, *a, **k)
    monkeypatch.setattr(pd.DataFrame, "to_parquet", to_parquet)
    with pytest.raises(OutputError, match=r"cannot write .*slow.*No space left on device.*"
                                          r"cells written so far are kept"):
        run_sweep(spec, tmp_path / "a", components=FAKE, progress=False)
    monkeypatch.setattr(pd.DataFrame, "to_parquet", real)
    assert store.cell_state(cell_dir(tmp_path / "a", spec.cells()[0])) == "ok"
    assert store.cell_state(cell_dir(tmp_path / "a", spec.cells()[1])) == "missing"
    assert not [p for p in (tmp_path / "a" / "cells").iterdir() if p.name.startswith(".")]
    o = run_sweep(spec, tmp_path / "a", components=FAKE, progress=False)
    assert (o.n_ok, o.n_skipped, o.n_error) == (1, 1, 0)


@pytest.mark.timeout(30)
@pytest.mark.parametrize("kind", ["fifo", "dev_zero"])
def test_regrouped_capture_that_is_a_special_file_is_named(tmp_path, kind):
    """`--regroup-frames` sizes the capture itself (radarsim.capture.regroup.check_regroup)."""
    import radarsim
    from radarsim.capture.regroup import check_regroup
    f = tmp_path / "a.bin"
    os.mkfifo(f) if kind == "fifo" else os.symlink("/dev/zero", f)
    with pytest.raises(ValueError, match=r"capture '.*a\.bin': is a (FIFO|character device)"):
        check_regroup(f, radarsim.presets.r79_ddma(), 2)
