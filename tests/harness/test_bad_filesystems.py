"""Real small filesystems (slow set): a full tmpfs and a read-only remount under the
results folder. Skipped where the machine does not let the test mount one (needs root or a
user namespace); the fast set simulates the same faults (`test_probes_writes`)."""
from __future__ import annotations

import re
import shutil
import subprocess
import uuid
from pathlib import Path

import pytest

from harness.cli import main
from tests.harness.probes import GATES, fake_results

pytestmark = pytest.mark.slow


@pytest.fixture
def small_fs(tmp_path):
    """A 512 kB tmpfs at tmp_path/fs (unmounted afterwards)."""
    mnt = tmp_path / "fs"
    mnt.mkdir()
    r = subprocess.run(["mount", "-t", "tmpfs", "-o", "size=512k", "tmpfs", str(mnt)],
                       capture_output=True, text=True)
    if r.returncode != 0:
        pytest.skip(f"cannot mount a tmpfs here: {r.stderr.strip()}")
    try:
        yield mnt
    finally:
        subprocess.run(["umount", "-l", str(mnt)], capture_output=True)


def _results_on(fs: Path, tmp_path: Path) -> Path:
    res = fs / "results"
    shutil.copytree(fake_results(tmp_path), res)
    return res


def _fill(fs: Path) -> None:
    """Write until the file system is full (the last flush fails with ENOSPC)."""
    try:
        with open(fs / f"filler-{uuid.uuid4().hex}", "wb") as fh:
            while True:
                fh.write(b"\0" * 4096)
                fh.flush()
    except OSError:
        pass


def _remount_ro(fs: Path) -> None:
    r = subprocess.run(["mount", "-o", "remount,ro", str(fs)], capture_output=True, text=True)
    if r.returncode != 0:
        pytest.skip(f"cannot remount read-only: {r.stderr.strip()}")


@pytest.mark.parametrize("fault", ["full", "read_only"])
def test_gate_verdict_survives_an_unwritable_results_folder(small_fs, tmp_path, capsys, fault):
    res = _results_on(small_fs, tmp_path)
    gates = tmp_path / "g.toml"
    gates.write_text(GATES)
    _fill(small_fs) if fault == "full" else _remount_ro(small_fs)
    assert main(["gate", str(res), "--thresholds", str(gates)]) == 0
    err = capsys.readouterr().err
    assert "gates.md" in err and "the verdict (pass) stands as the exit code" in err
    assert not (res / "gates.md").exists()
    assert not [p for p in res.iterdir() if p.name.startswith(".tmp-")]


@pytest.mark.parametrize("fault", ["full", "read_only"])
def test_report_on_an_unwritable_results_folder_exits_2_leaving_nothing(small_fs, tmp_path,
                                                                       capsys, fault):
    res = _results_on(small_fs, tmp_path)
    _fill(small_fs) if fault == "full" else _remount_ro(small_fs)
    assert main(["report", str(res), "--no-maps"]) == 2
    err = [ln for ln in capsys.readouterr().err.splitlines() if "error" in ln]
    assert len(err) == 1 and "report.html" in err[0]
    assert not (res / "report.html").exists()
    assert not [p for p in res.iterdir() if p.name.startswith(".tmp-")]


def test_sweep_on_a_full_disk_exits_2_and_resumes(small_fs, tmp_path, capsys):
    """The real sweep tables do not fit in 512 kB: exit 2 naming a path under the folder; after
    freeing space (a bigger folder) nothing half-written is reused."""
    sweep = tmp_path / "s.toml"
    sweep.write_text('name = "fs"\nscenarios = ["head_on_aliasing"]\nduration_s = 0.5\n')
    _fill(small_fs)
    rc = main(["sweep", str(sweep), "--out", str(small_fs / "r"), "--workers", "1",
               "--no-progress"])
    err = [ln for ln in capsys.readouterr().err.splitlines() if ": error: " in ln]
    assert rc == 2 and len(err) == 1 and str(small_fs) in err[0], err


def test_process_and_simulate_on_a_full_disk_exit_2_naming_out(small_fs, tmp_path, capsys):
    """A full disk under ``--out`` of process and simulate: one line naming the option and the
    file (was a bare "[Errno 28] No space left on device"), no temporary left behind."""
    import numpy as np

    from radarsim.capture import write_capture
    from radarsim.ti import parse_ti_cfg
    from tests.radarsim.profiles import PROFILE_DIR
    profile = PROFILE_DIR / "xwr18_visualizer.cfg"
    cfg = parse_ti_cfg(profile).radar
    capture = tmp_path / "cap.bin"
    write_capture(capture, [np.zeros((cfg.n_chirps, cfg.n_rx, cfg.n_samples), np.complex64)],
                  cfg=cfg)
    out = small_fs / "o"
    out.mkdir()
    _fill(small_fs)
    for argv in (["simulate", "head_on_aliasing", "--cfg", str(profile), "--out",
                  str(out / "c.bin"), "--frames", "1"],
                 ["process", str(capture), "--cfg", str(profile), "--out", str(out / "p.csv"),
                  "--no-track"]):
        assert main(argv) == 2
        err = [ln for ln in capsys.readouterr().err.splitlines() if "error" in ln]
        name = "c.bin" if argv[0] == "simulate" else "p.csv"
        assert len(err) == 1 and re.search(rf"--out: cannot write '.*/o/{name}': no space left "
                                           "on the device", err[0]), err
    assert list(out.iterdir()) == []
