"""Sweeps: TOML suites, atomic cells, resume, errors, process pool, Dask, interruption."""
from __future__ import annotations

import dataclasses
import json
import os
import signal
import textwrap
import time

import pandas as pd
import pytest

import radarsim
from harness.cell import run as cellrun
from harness.cell.run import FRAME_THREADS, cell_frame_threads
from harness.sweep import schedule
from harness.sweep.file import load_sweep
from harness.sweep.schedule import run_sweep
from harness.sweep.spec import SCHEMES_SWEEP_PATH, SweepSpec, Variant
from harness.sweep.store import completed_cells
from harness.sweep.worker import execute_cell
from tests.harness.fakes import FAKE, assert_same_tables
from tests.harness.forked import fork_sweep, forked_children, wait_exit


def small_spec(**kw) -> SweepSpec:
    base = dict(name="t", scenarios=("fast", "slow"), seeds=(0, 1), duration_s=0.4)
    base.update(kw)
    return SweepSpec(**base)


def test_load_sweep_vary_product(tmp_path):
    f = tmp_path / "s.toml"
    f.write_text(textwrap.dedent("""
        name = "pn"
        scenarios = ["a", "b"]
        seeds = [0, 1, 2]
        frame_stride = 2
        [base.radar]
        tx_phase_error_deg = [0.0, 3.0, -2.0, 1.0]
        [vary]
        "radar.phase_noise_deg_rms" = [0.0, 5.0]
        "processing.cfar_threshold_db" = [12.0, 15.0]
    """))
    spec = load_sweep(f, check_scenarios=False)
    assert len(spec.variants) == 4 and len(spec.cells()) == 2 * 4 * 3
    v = spec.variants[1]
    assert v.name == "phase_noise_deg_rms=0.0,cfar_threshold_db=15.0"
    assert v.radar == {"tx_phase_error_deg": [0.0, 3.0, -2.0, 1.0], "phase_noise_deg_rms": 0.0}
    assert v.processing == {"cfar_threshold_db": 15.0}
    assert spec.frame_stride == 2
    # Deterministic id: rerunning the same command resumes the same directory.
    assert spec.run_id == load_sweep(f, check_scenarios=False).run_id
    assert spec.with_overrides(seeds=[7]).seeds == (7,)


def test_radar_keys_by_part_build_the_cell_radar(tmp_path):
    """A part's table (``[base.radar.impairments]``) and a dotted key
    (``"radar.waveform.n_chirps"``) reach the cell's RadarConfig; a flat key still does and
    warns with the new key."""
    from harness.cell.config import radar_config
    f = tmp_path / "s.toml"
    f.write_text(textwrap.dedent("""
        scenarios = ["a"]
        [base.radar.impairments]
        phase_noise_deg_rms = 2.0
        [vary]
        "radar.waveform.n_chirps" = [384]
    """))
    v = load_sweep(f, check_scenarios=False).variants[0]
    assert v.radar == {"impairments": {"phase_noise_deg_rms": 2.0}, "waveform.n_chirps": 384}
    cfg = radar_config(v.radar, "tdma")
    assert (cfg.phase_noise_deg_rms, cfg.n_chirps, cfg.mimo) == (2.0, 384, "tdma")
    with pytest.warns(DeprecationWarning, match=r"use 'impairments.phase_noise_deg_rms'"):
        assert radar_config({"phase_noise_deg_rms": 2.0}, "tdma").phase_noise_deg_rms == 2.0


def test_tracker_keys_by_sub_config_build_the_cell_tracker(tmp_path):
    """A sub-config's table (``[base.tracker.gating]``) and a dotted key
    (``"tracker.maintenance.max_tracks"``) reach the cell's TrackerConfig; the case's mount
    and the frame period fill what they leave; a flat key still works and warns with the new
    key."""
    from harness.cell.components import tracker_config
    f = tmp_path / "s.toml"
    f.write_text(textwrap.dedent("""
        scenarios = ["a"]
        [base.tracker.gating]
        gate_mahalanobis = 20.0
        [vary]
        "tracker.maintenance.max_tracks" = [9]
    """))
    v = load_sweep(f, check_scenarios=False).variants[0]
    assert v.tracker == {"gating": {"gate_mahalanobis": 20.0}, "maintenance.max_tracks": 9}
    cfg = tracker_config(v.tracker, {"x_m": -1.0, "y_m": 0.5, "yaw_deg": 135.0}, [0.0, 0.1])
    assert (cfg.gating.gate_mahalanobis, cfg.maintenance.max_tracks) == (20.0, 9)
    assert (cfg.mount.mount_x_m, cfg.mount.mount_yaw_deg, cfg.motion.frame_period_s) == \
        (-1.0, 135.0, 0.1)
    assert tracker_config({"mount.mount_x_m": 2.0}, {"x_m": -1.0}).mount.mount_x_m == 2.0
    with pytest.warns(DeprecationWarning, match=r"use 'gating\.gate_mahalanobis'"):
        assert tracker_config({"gate_mahalanobis": 20.0}).gating.gate_mahalanobis == 20.0


@pytest.mark.parametrize("text,match", [
    ('scenarios = ["a"]\nbogus = 1', "unknown key"),
    ('scenarios = ["a"]\n[vary]\n"radar.not_a_field" = [1]', "unknown radar field"),
    ('scenarios = ["a"]\n[vary]\n"radar.waveform.n_tx" = [1]', "unknown radar field"),
    ('scenarios = ["a"]\n[base.radar.waveform]\nbogus = 1', "unknown radar field"),
    ('scenarios = ["a"]\n[vary]\n"sonar.x" = [1]', "unknown section"),
    ('scenarios = ["a"]\n[vary]\n"tracker.gating.bogus" = [1]', r"gating holds"),
    ('scenarios = ["a"]\n[base.tracker.gating]\ngate_width_m = 0.0', r"gate_width_m=0\.0"),
    ('scenarios = ["a"]\n[vary]\n"radar.phase_noise_deg_rms" = []', "non-empty list"),
    ('scenarios = ["a"]\nseeds = [-1]', "seeds"),
    ('scenarios = ["a"]\nframe_stride = 0', "frame_stride"),
    ('scenarios = [\n', "malformed TOML"),
    ('scenarios = ["a"]\nschemes = ["ddma", "fdma"]', r"unknown scheme\(s\) \['fdma'\]"),
    ('scenarios = ["a"]\nschemes = "ddma"', r"schemes='ddma' must be a list"),
    ('scenarios = ["a"]\nbaseline_scheme = "fdma"', r"baseline_scheme='fdma' is not one of"),
])
def test_load_sweep_rejects_bad_files(tmp_path, text, match):
    f = tmp_path / "bad.toml"
    f.write_text(text)
    with pytest.raises(ValueError, match=match):
        load_sweep(f, check_scenarios=False)


def test_serial_sweep_resume_and_error(tmp_path):
    spec = small_spec(scenarios=("fast", "boom", "slow"))
    out = tmp_path / "r"
    o1 = run_sweep(spec, out, components=FAKE, progress=False)
    assert (o1.n_ok, o1.n_error, o1.n_skipped) == (4, 2, 0)
    assert "scenario exploded" in next(iter(o1.errors.values()))
    summary = pd.read_parquet(out / "summary.parquet")
    err = summary[summary["error"] != ""]
    assert list(err["scenario"]) == ["boom", "boom"]
    manifest = json.loads((out / "manifest.json").read_text())
    assert manifest["n_ok"] == 4 and manifest["n_error"] == 2
    assert {"numpy", "pandas", "pyarrow"} <= set(manifest["versions"])
    assert "commit" in manifest["git"] and manifest["seeds"] == [0, 1]
    stamp = {p: p.stat().st_mtime_ns for p in (out / "cells").glob("*/summary.parquet")}
    # Rerun: the 4 completed cells are skipped (files untouched), the 2 errored are retried.
    o2 = run_sweep(spec, out, components=FAKE, progress=False)
    assert (o2.n_skipped, o2.n_ok, o2.n_error) == (4, 0, 2)
    assert stamp == {p: p.stat().st_mtime_ns for p in (out / "cells").glob("*/summary.parquet")}
    assert not list((out / "cells").glob(".tmp-*"))


def test_pool_equals_serial_and_dask(tmp_path):
    spec = small_spec()
    run_sweep(spec, tmp_path / "serial", components=FAKE, progress=False)
    run_sweep(spec, tmp_path / "pool", workers=2, components=FAKE, progress=False)
    assert_same_tables(tmp_path / "serial", tmp_path / "pool")
    import distributed
    with distributed.LocalCluster(n_workers=1, threads_per_worker=2, processes=False,
                                  dashboard_address=None) as cluster:
        o = run_sweep(spec, tmp_path / "dask", scheduler=cluster.scheduler_address,
                      components=FAKE, progress=False)
    assert o.n_ok == 4
    assert_same_tables(tmp_path / "serial", tmp_path / "dask")


@pytest.mark.parametrize("workers, cores, expected", [
    (2, 2, [1, 1, 1, 2, 2]),   # the last `workers` cells: a core idles when the queue empties
    (3, 2, [1, 1, 2, 2, 2]),
    (1, 1, [1, 1, 1, 1, 2]),   # one core, one worker: only the last cell has a core to spare
    (1, 2, [2, 2, 2, 2, 2]),   # one worker on two cores: the other core is free all along
])
def test_cells_run_one_frame_thread_while_cells_queue_behind_them(workers, cores, expected):
    assert FRAME_THREADS == 2
    n = len(expected)
    assert [cell_frame_threads(n - 1 - i, workers, cores) for i in range(n)] == expected


def test_the_serial_sweep_passes_each_cell_its_frame_threads(tmp_path, monkeypatch):
    """On one core the cells of a serial sweep run one frame thread, the last one two (it has
    no cell behind it); the tables do not depend on it (`test_runner.py`)."""
    got = []

    def recording(spec, out, comps=None, plugins=(), frame_threads=0):
        got.append(frame_threads)
        return execute_cell(spec, out, comps, plugins, frame_threads)
    monkeypatch.setattr(schedule, "execute_cell", recording)
    monkeypatch.setattr(cellrun.os, "cpu_count", lambda: 1)
    run_sweep(small_spec(), tmp_path / "r", components=FAKE, progress=False)
    assert got == [1, 1, 1, 2]


def test_killed_worker_loses_no_completed_cell_and_rerun_resumes(tmp_path):
    out = tmp_path / "r"
    spec = SweepSpec(name="t", scenarios=("fast", "slow", "mid"), seeds=(0, 1), duration_s=0.4)
    cells = spec.cells()
    # A real pool sweep in a process of its own (forked: no second interpreter start-up).
    pid = fork_sweep(spec, out, report=tmp_path / "report.json",
                     env={"FAKE_PROCESS_DELAY_S": "0.02"})  # ~0.5 s per cell
    # Kill a worker once a first cell is on disk. The deadline only guards against a hang: on a
    # loaded machine the pool may take well over 30 s to start (the test failed that way).
    try:
        deadline = time.monotonic() + 300
        while not completed_cells(out, cells) and time.monotonic() < deadline:
            time.sleep(0.05)
        assert completed_cells(out, cells), "no cell completed within 300 s"
        workers = forked_children(pid)
        assert workers, "no worker process found"
        os.kill(workers[0], signal.SIGKILL)
    except BaseException:
        os.kill(pid, signal.SIGKILL)  # no sweep left running behind a failed test
        os.waitpid(pid, 0)
        raise
    assert wait_exit(pid, 60) == 0
    report = json.loads((tmp_path / "report.json").read_text())
    done = completed_cells(out, cells)
    assert report["interrupted"] >= 1 and len(done) >= 1
    assert len(done) < len(cells)
    # Completed cells are intact; the rerun runs only the missing ones.
    o = run_sweep(spec, out, components=FAKE, progress=False)
    assert o.n_skipped == len(done) and o.n_ok == len(cells) - len(done)
    run_sweep(spec, tmp_path / "clean", components=FAKE, progress=False)
    assert_same_tables(out, tmp_path / "clean")


def test_sweep_scheme_keys_reach_the_cells_and_manifest(tmp_path):
    f = tmp_path / "s.toml"
    f.write_text('scenarios = ["fast"]\nduration_s = 0.5\nschemes = ["tdma_raw", "ddma"]\n'
                 'baseline_scheme = "ddma"\n')
    spec = load_sweep(f, check_scenarios=False)
    assert spec.schemes == ("tdma_raw", "ddma") and spec.baseline_scheme == "ddma"
    assert spec.cells()[0].schemes == ("tdma_raw", "ddma")
    assert spec.run_id != dataclasses.replace(spec, schemes=("ddma",)).run_id
    run_sweep(spec, tmp_path / "r", components=FAKE, progress=False)
    s = pd.read_parquet(tmp_path / "r" / "summary.parquet")
    assert list(s["scheme"]) == ["tdma_raw", "ddma"]
    man = json.loads((tmp_path / "r" / "manifest.json").read_text())
    assert man["schemes"] == ["tdma_raw", "ddma"] and man["baseline_scheme"] == "ddma"
    assert list(man["radar_presets"]) == ["tdma", "ddma"]


def test_shipped_scheme_comparison_sweep_loads():
    spec = load_sweep(SCHEMES_SWEEP_PATH)
    assert set(radarsim.MIMO_SCHEMES) <= set(spec.schemes) and spec.baseline_scheme == "tdma"


def test_variants_reach_the_cells(tmp_path):
    spec = small_spec(scenarios=("fast",), seeds=(0,),
                      variants=(Variant(name="a"), Variant(name="b",
                                                           radar={"phase_noise_deg_rms": 2.0})))
    run_sweep(spec, tmp_path, components=FAKE, progress=False)
    s = pd.read_parquet(tmp_path / "summary.parquet")
    assert sorted(s["variant"].unique()) == ["a", "b"]


@pytest.mark.parametrize("text, match", [
    ('scenarios = ["a"]\nspeed_kmh = 3', r"speed_kmh: unknown key; known: \["),
    ('scenarios = ["a"]\n[[variants]]\nname = "x"\ncolour = 1',
     r"variants\[0\]\.colour: unknown key; known: \["),
    ('scenarios = ["a"]\n[[variants]]\n[variants.radar]\nn_tx = 2',
     r"variants\[0\]\.name: required key missing"),
])
def test_sweep_file_messages_follow_the_shared_file_policy(tmp_path, text, match):
    """Same message shape as case files and gates: file, key with its position, what is wrong."""
    from harness.sweep.file import load_sweep
    p = tmp_path / "s.toml"
    p.write_text(text)
    with pytest.raises(ValueError, match=rf"s\.toml: {match}"):
        load_sweep(p, check_scenarios=False)


def test_processing_keys_address_nested_fields_and_flat_ones_warn(tmp_path):
    """``processing.cfar.pfa`` names the nested field; ``processing.cfar_mode`` (the flat key
    of the previous release) still works and warns with the new key."""
    from harness.sweep.file import load_sweep
    path = tmp_path / "s.toml"
    path.write_text('name = "t"\nscenarios = ["r79_motorcycle_rear"]\nseeds = [0]\n[vary]\n'
                    '"processing.cfar.pfa" = [1e-5]\n"processing.cfar_mode" = ["ca"]\n')
    with pytest.warns(DeprecationWarning, match=r"'cfar_mode' is deprecated: use 'cfar.mode' "
                                                r"\(sweep files: 'processing.cfar.mode'\)"):
        spec = load_sweep(path)
    (cell,) = spec.cells()
    assert cell.processing == {"cfar.pfa": 1e-5, "cfar_mode": "ca"}
    import pipeline
    with pytest.warns(DeprecationWarning):
        proc = pipeline.ProcessingConfig().replace(**cell.processing)
    assert (proc.cfar.pfa, proc.cfar.mode) == (1e-5, "ca")
