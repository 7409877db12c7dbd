"""Sweeps never mix or lose results: duplicates, code versions, corrupt cells, kills, paths.

A failing duplicate must never replace a completed cell; a resume after a code change
must not mix versions; a corrupt table under an "ok" cell.json is recomputed; killed writes leave
no `.tmp-*` behind for good; a relative --out reaches Dask workers as an absolute path; a sweep
that ends with missing cells says so and exits non-zero; SIGKILL at random points and resume
gives the tables of an uninterrupted run.
"""
from __future__ import annotations

import contextlib
import json
import multiprocessing
import os
import shutil
import signal
import time
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from harness.cli import main
from harness.sweep import file as sweepfile
from harness.sweep import schedule, store
from harness.sweep import spec as sweepspec
from harness.sweep.schedule import run_sweep
from harness.sweep.spec import SweepSpec
from harness.sweep.store import cell_dir, completed_cells
from harness.sweep.worker import execute_cell
from tests.harness.fakes import FAILING, FAKE, TABLES, assert_same_tables
from tests.harness.forked import (
    ctrl_c_at_the_next_fork,
    fork_call,
    fork_sweep,
    forked_children,
    wait_exit,
    wait_group_gone,
)


def small_spec(**kw) -> SweepSpec:
    base = dict(name="t", scenarios=("fast",), seeds=(0, 1, 2), duration_s=0.2)
    base.update(kw)
    return SweepSpec(**base)


def _snapshot(d: Path) -> dict[str, bytes]:
    return {f.name: f.read_bytes() for f in sorted(d.iterdir())}


def test_failing_duplicate_never_replaces_a_completed_cell(tmp_path):
    spec = small_spec()
    run_sweep(spec, tmp_path, components=FAKE, progress=False)
    cell = spec.cells()[0]
    before = _snapshot(cell_dir(tmp_path, cell))
    # A duplicate execution (a concurrent run, an orphaned Dask task) that fails late ...
    r = execute_cell(cell, str(tmp_path), FAILING)
    assert (r["status"], r["written"]) == ("ok", "kept")
    # ... and one that succeeds late: neither touches the completed cell.
    r = execute_cell(cell, str(tmp_path), FAKE)
    assert r["written"] == "kept"
    assert _snapshot(cell_dir(tmp_path, cell)) == before
    assert not [p for p in (tmp_path / "cells").iterdir() if p.name.startswith(".")]


def test_error_record_is_replaced_by_a_later_success(tmp_path):
    cell = small_spec().cells()[0]
    assert execute_cell(cell, str(tmp_path), FAILING)["status"] == "error"
    assert store.cell_state(cell_dir(tmp_path, cell)) == "error"
    assert execute_cell(cell, str(tmp_path), FAKE)["written"] == "written"
    assert store.cell_state(cell_dir(tmp_path, cell)) == "ok"


def test_every_cell_records_its_code_version(tmp_path):
    spec = small_spec()
    run_sweep(spec, tmp_path, components=FAKE, progress=False)
    version = store.code_version()
    assert len(version["hash"]) == 16
    for c in spec.cells():
        meta = json.loads((cell_dir(tmp_path, c) / "cell.json").read_text())
        assert meta["code_version"]["hash"] == version["hash"]
        assert set(meta["files"]) >= {f"{t}.parquet" for t in TABLES}
    manifest = json.loads((tmp_path / "manifest.json").read_text())
    assert manifest["code_version"] == version["hash"]
    assert {c["origin"] for c in manifest["cells"]} == {"computed"}


def test_resume_after_a_code_change_never_mixes_versions(tmp_path, monkeypatch):
    spec = small_spec()
    first = spec.cells()[:2]
    # Half of the sweep completed by the current code ...
    for c in first:
        execute_cell(c, str(tmp_path), FAKE)
    old = store.code_version()["hash"]
    # ... then the code changes.
    new_version = {**store.code_version(), "hash": "0123456789abcdef"}
    monkeypatch.setattr(store, "code_version", lambda: new_version)
    with pytest.raises(ValueError, match=rf"2 completed cell\(s\) were computed by code version "
                                         rf"{old}, this is 0123456789abcdef: rerun with --force"):
        run_sweep(spec, tmp_path, components=FAKE, progress=False)
    # Nothing was touched by the refusal.
    assert all(store.cell_state(cell_dir(tmp_path, c), old) == "ok" for c in first)
    o = run_sweep(spec, tmp_path, components=FAKE, progress=False, force=True)
    assert (o.n_recomputed, o.n_skipped, o.n_ok, o.n_missing) == (2, 0, 3, 0)
    manifest = json.loads((tmp_path / "manifest.json").read_text())
    assert {c["code_version"] for c in manifest["cells"]} == {"0123456789abcdef"}
    # A further resume of the same version reuses everything and says so.
    o = run_sweep(spec, tmp_path, components=FAKE, progress=False)
    assert (o.n_skipped, o.n_ok) == (3, 0)
    manifest = json.loads((tmp_path / "manifest.json").read_text())
    assert manifest["n_resumed"] == 3 and manifest["n_computed"] == 0


def test_cli_refuses_a_resume_across_versions_with_exit_2(tmp_path, monkeypatch, capsys):
    spec = small_spec(seeds=(0,))
    run_sweep(spec, tmp_path, components=FAKE, progress=False)
    monkeypatch.setattr(store, "code_version", lambda: {"hash": "f" * 16, "commit": None,
                                                        "dirty": None})
    monkeypatch.setattr(sweepfile, "load_sweep", lambda path: spec)
    monkeypatch.setattr(schedule, "validate_cells", lambda spec, source=None: None)
    assert main(["sweep", "x.toml", "--out", str(tmp_path), "--workers", "1"]) == 2
    last = capsys.readouterr().err.splitlines()[-1]
    assert last.startswith("radar-harness sweep: error: ")
    assert "computed by code version" in last and "--force" in last


def test_corrupt_table_under_an_ok_cell_is_recomputed(tmp_path):
    spec = small_spec()
    run_sweep(spec, tmp_path / "a", components=FAKE, progress=False)
    shutil.copytree(tmp_path / "a", tmp_path / "clean")  # the tables before the damage
    d = cell_dir(tmp_path / "a", spec.cells()[1])
    f = d / "detections.parquet"
    f.write_bytes(f.read_bytes()[: f.stat().st_size // 2])  # a torn write
    (cell_dir(tmp_path / "a", spec.cells()[2]) / "truth.parquet").unlink()
    assert store.cell_state(d) == "corrupt"
    o = run_sweep(spec, tmp_path / "a", components=FAKE, progress=False)
    assert (o.n_recomputed, o.n_ok, o.n_skipped) == (2, 2, 1)
    assert_same_tables(tmp_path / "a", tmp_path / "clean")


def test_temporaries_of_dead_writers_are_cleaned(tmp_path):
    spec = small_spec()
    cells = tmp_path / "cells"
    cells.mkdir(parents=True)
    host = store._HOST
    dead = cells / f".tmp-x__s0__abc-{host}-99999999-abcdef"
    retired = cells / f".old-x__s0__abc-{host}-99999999-abcdef"
    alive = cells / f".tmp-y__s0__abc-{host}-1-abcdef"  # pid 1 is alive: a concurrent writer
    foreign = cells / ".tmp-z__s0__abc-otherhost-5-abcdef"  # another host, young: kept
    for d in (dead, retired, alive, foreign):
        d.mkdir()
        (d / "cell.json").write_text("{}")
    run_sweep(spec, tmp_path, components=FAKE, progress=False)
    assert not dead.exists() and not retired.exists()
    assert alive.exists() and foreign.exists()
    old = time.time() - store.FOREIGN_TEMP_MAX_AGE_S - 10
    os.utime(foreign, (old, old))
    store.clean_temporaries(cells)
    assert not foreign.exists()


@pytest.mark.skipif(not Path("/proc/self/stat").exists(), reason="needs Linux procfs")
def test_temporaries_of_a_zombie_writer_are_removed(tmp_path):
    """A killed sweep's pool workers can stay zombies (exited, never reaped): not writers."""
    pid = os.fork()
    if pid == 0:
        os._exit(0)
    try:
        deadline = time.monotonic() + 10
        while Path(f"/proc/{pid}/stat").read_text().split(") ")[-1][:1] != "Z":
            assert time.monotonic() < deadline
            time.sleep(0.01)
        tmp = tmp_path / f".tmp-x__s0__abc-{store._HOST}-{pid}-abcdef"
        tmp.mkdir()
        assert store.clean_temporaries(tmp_path) == [tmp] and not tmp.exists()
        assert store._pid_alive(os.getpid())
    finally:
        os.waitpid(pid, 0)


def test_relative_out_is_resolved_before_dask_workers_see_it(tmp_path, monkeypatch):
    import distributed
    monkeypatch.chdir(tmp_path)
    spec = small_spec()
    with distributed.LocalCluster(n_workers=1, threads_per_worker=2, processes=False,
                                  dashboard_address=None) as cluster:
        o = run_sweep(spec, "rel/out", scheduler=cluster.scheduler_address, components=FAKE,
                      progress=False)
    assert o.out_dir == (tmp_path / "rel" / "out") and o.out_dir.is_absolute()
    assert o.complete and o.n_ok == 3
    assert len(pd.read_parquet(tmp_path / "rel" / "out" / "summary.parquet")) == 3 * 3


def test_a_scheduler_without_workers_fails_within_the_timeout(tmp_path):
    import distributed
    with distributed.LocalCluster(n_workers=0, processes=False,
                                  dashboard_address=None) as cluster:
        t0 = time.monotonic()
        with pytest.raises(ValueError, match=r"no Dask worker joined the scheduler within 1 s"):
            run_sweep(small_spec(), tmp_path, scheduler=cluster.scheduler_address,
                      components=FAKE, progress=False, scheduler_timeout_s=1.0)
        assert time.monotonic() - t0 < 15


def _lost_cell(spec, out, comps=None, plugins=(), frame_threads=2):
    """A worker that reports success but writes nowhere visible (its own working directory)."""
    return {"cell_id": spec.cell_id, "status": "ok", "elapsed_s": 0.0, "written": "written"}


def test_missing_cells_make_the_sweep_incomplete(tmp_path, monkeypatch):
    monkeypatch.setattr(schedule, "execute_cell", _lost_cell)
    o = run_sweep(small_spec(), tmp_path, components=FAKE, progress=False)
    assert (o.n_missing, o.n_ok, o.complete) == (3, 0, False)
    manifest = json.loads((tmp_path / "manifest.json").read_text())
    assert manifest["n_missing"] == 3
    assert {c["status"] for c in manifest["cells"]} == {"missing"}


def test_cli_sweep_with_missing_cells_exits_1_and_says_so(tmp_path, monkeypatch, capsys):
    monkeypatch.setattr(schedule, "execute_cell", _lost_cell)
    rc = main(["sweep", str(sweepspec.CI_SWEEP_PATH), "--scenarios", "head_on_aliasing",
               "--workers", "1", "--out", str(tmp_path / "r")])
    out, err = capsys.readouterr()
    assert rc == 1
    assert "0 cells computed" in out and "1 missing" in out
    assert "1 of 1 cells are missing" in err and "rerun the same command" in err


# ------------------------------------------------------------------------- kill and resume
def _kill_resume_trials(tmp_path: Path, n_trials: int, seed: int,
                        scenarios=("fast", "slow", "mid")) -> None:
    """SIGKILL the whole process group (parent and pool workers) of a real pool sweep at
    seeded random moments, rerun the same sweep each time, and compare the final tables with
    an uninterrupted run. The sweep runs in a forked process (its pool forks the workers from
    it), so it starts at once: every kill lands 0.1-1.5 s after the start, before, during or
    after the cells (the whole sweep of 3 cells on 2 workers takes ~1.1-1.9 s here)."""
    rng = np.random.default_rng(seed)
    out = tmp_path / "killed"
    spec = SweepSpec(name="k", scenarios=tuple(scenarios), seeds=(0, 1, 2), duration_s=0.3)
    for _ in range(n_trials):
        pid = fork_sweep(spec, out, env={"FAKE_PROCESS_DELAY_S": "0.01"}, own_group=True)
        time.sleep(float(rng.uniform(0.1, 1.5)))
        try:
            os.killpg(pid, signal.SIGKILL)
        except ProcessLookupError:
            pass
        wait_exit(pid, 30)
        wait_group_gone(pid, 30)
        # Whatever the moment, every cell on disk is either complete and intact or absent.
        for c in spec.cells():
            assert store.cell_state(cell_dir(out, c)) in ("ok", "missing")
    done = completed_cells(out, spec.cells())
    o = run_sweep(spec, out, components=FAKE, progress=False)
    assert o.complete and o.n_skipped == len(done) and o.n_ok == len(spec.cells()) - len(done)
    assert not [p for p in (out / "cells").iterdir() if p.name.startswith(".")]
    run_sweep(spec, tmp_path / "clean", components=FAKE, progress=False)
    assert_same_tables(out, tmp_path / "clean")


def test_sigkill_at_random_points_then_resume_gives_the_same_tables(tmp_path):
    _kill_resume_trials(tmp_path, n_trials=1, seed=15, scenarios=("fast",))


@pytest.mark.slow
def test_sigkill_at_random_points_many_trials(tmp_path):
    _kill_resume_trials(tmp_path, n_trials=12, seed=1515)


def _ctrl_c_able_main(argv: list[str]) -> int:
    """The CLI's `main` with SIGINT at its default, as a terminal's foreground job has it: a
    suite started with ``&`` by a script inherits SIGINT ignored (POSIX), and the sweep, like
    Python, keeps an inherited ignore (a background job must survive the script's Ctrl-C)."""
    signal.signal(signal.SIGINT, signal.default_int_handler)
    return main(argv)


def test_sigint_prints_the_resume_hint_not_a_traceback(tmp_path):
    """Ctrl-C on a real pool sweep: exit 130, one line, cells already written stay valid.

    The sweep is the CLI's `main` in a child forked from the test process (a fresh
    interpreter only adds seconds of imports). The signal goes 0.3 s after the pool's two
    workers exist (they are forked together at the first submit), so they are computing their
    first cells, which take seconds: the sweep cannot have finished. An exit 0 is a lost
    signal, a failure (a Ctrl-C during the workers' fork used to be dropped:
    `test_ctrl_c_while_the_pool_forks_its_workers_...`)."""
    out = tmp_path / "r"
    argv = ["sweep", str(sweepspec.CI_SWEEP_PATH), "--scenarios",
            "blind_spot_overtaking", "head_on_aliasing", "--duration-s", "2", "--workers", "2",
            "--out", str(out)]
    err_file = tmp_path / "stderr"
    pid = fork_call(_ctrl_c_able_main, argv, stdout=tmp_path / "stdout", stderr=err_file)
    try:
        deadline, ended = time.monotonic() + 120, 0
        while time.monotonic() < deadline and len(forked_children(pid)) < 2 and not ended:
            ended = os.waitpid(pid, os.WNOHANG)[0]
            time.sleep(0.05)
        assert not ended and len(forked_children(pid)) >= 2, \
            f"the sweep's pool did not start 2 workers: {err_file.read_text()[-2000:]}"
        time.sleep(0.3)
        os.kill(pid, signal.SIGINT)
        code = wait_exit(pid, 120)
    except BaseException:
        with contextlib.suppress(OSError):  # no sweep left running behind a failed test
            os.kill(pid, signal.SIGKILL)
            os.waitpid(pid, 0)
        raise
    err = err_file.read_text()
    assert code == 130, err
    assert "Traceback" not in err
    assert err.strip().splitlines()[-1].endswith("interrupted: rerun the same command to resume")
    states = [store.cell_state(cell_dir(out, c))
              for c in sweepfile.load_sweep(sweepspec.CI_SWEEP_PATH).with_overrides(
                  scenarios=["blind_spot_overtaking", "head_on_aliasing"], duration_s=2.0).cells()]
    assert set(states) <= {"ok", "missing"}
    # Signalled 0.3 s into cells of seconds: the sweep stopped there, not after its last cell.
    assert "missing" in states


def test_ctrl_c_while_the_pool_forks_its_workers_stops_the_sweep(tmp_path):
    """A SIGINT that arrives while a pool worker is being forked is raised inside os.fork's
    at-fork hooks, where Python only prints it ("Exception ignored") and drops it: the sweep
    used to run to the end and exit 0. It must stop the sweep like any other Ctrl-C."""
    if multiprocessing.get_start_method() != "fork":
        pytest.skip("this Python starts pool workers without forking the sweep's process: "
                    "no at-fork hook runs there")
    spec = small_spec(seeds=(0, 1, 2, 3))
    with ctrl_c_at_the_next_fork() as ctrl_c, pytest.raises(KeyboardInterrupt):
        run_sweep(spec, tmp_path, workers=2, components=FAKE, progress=False)
    assert ctrl_c["fired"]
    assert not (tmp_path / "manifest.json").exists()
    for c in spec.cells():
        assert store.cell_state(cell_dir(tmp_path, c)) in ("ok", "missing")


def test_the_code_version_hashes_the_source_of_every_package():
    root = Path(store.__file__).resolve().parents[2]
    files = {f.relative_to(root).as_posix() for f in store.code_source_files()}
    assert {"core/registry.py", "radarsim/radar_config.py", "pipeline/chain.py",
            "metrics/registry.py", "scenarios/cases/blind_spot_overtaking.toml",
            "harness/sweep/store.py"} <= files
