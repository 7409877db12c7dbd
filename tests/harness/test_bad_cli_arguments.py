"""Bad command-line arguments: exit code 2 and one line naming the option and the value.

Before these checks, `--duration-s 1e9` hung run/simulate/sweep, `--duration-s inf` failed deep
inside, `--out` pointing at a file or an unwritable place and a dead scheduler address gave
tracebacks (the latter after 30 s of silence), `report --max-cases -1` silently dropped a case.
Every duration, count and size is bounded at parse time.
"""
from __future__ import annotations

import re
import time

import pytest

from harness.cli import main
from harness.sweep import spec as sweepspec
from radarsim.ti import r79_cfg_path

CI = str(sweepspec.CI_SWEEP_PATH)
CFG = str(r79_cfg_path())


def _cases(tmp):
    afile = tmp / "afile"
    afile.write_text("x")
    adir = tmp / "adir"
    adir.mkdir()
    return {
        # durations, counts, sizes
        "sweep_duration_1e9": (["sweep", "--duration-s", "1e9"],
                               r"--duration-s: 1e9 is outside \(0, 120\] s"),
        "sweep_duration_inf": (["sweep", "--duration-s", "inf"], r"--duration-s: inf is outside"),
        "sweep_duration_nan": (["sweep", "--duration-s", "nan"], r"--duration-s: nan is outside"),
        "sweep_duration_negative": (["sweep", "--duration-s", "-1"], r"--duration-s: -1 is"),
        "sweep_duration_text": (["sweep", "--duration-s", "long"],
                                r"--duration-s: 'long' is not a number"),
        "run_duration_1e9": (["run", "head_on_aliasing", "--duration-s", "1e9"],
                             r"--duration-s: 1e9 is outside"),
        "run_duration_inf": (["run", "head_on_aliasing", "--duration-s", "inf"],
                             r"--duration-s: inf is outside"),
        "simulate_duration_1e9": (["simulate", "head_on_aliasing", "--cfg", CFG, "--out",
                                   str(tmp / "x.bin"), "--duration-s", "1e9"],
                                  r"--duration-s: 1e9 is outside"),
        "simulate_frames_zero": (["simulate", "head_on_aliasing", "--cfg", CFG, "--out",
                                  str(tmp / "x.bin"), "--frames", "0"],
                                 r"--frames: 0 is outside 1\.\.100000"),
        "process_frames_negative": (["process", str(afile), "--cfg", CFG, "--frames", "-1"],
                                    r"--frames: -1 is outside"),
        "workers_zero": (["sweep", "--workers", "0"], r"--workers: 0 is outside 1\.\.256"),
        "workers_huge": (["sweep", "--workers", "1000000"], r"--workers: 1000000 is outside"),
        "workers_text": (["sweep", "--workers", "two"], r"--workers: 'two' is not an integer"),
        "frame_stride_zero": (["sweep", "--frame-stride", "0"], r"--frame-stride: 0 is outside"),
        "frame_stride_huge": (["run", "head_on_aliasing", "--frame-stride", "1000000000000"],
                              r"--frame-stride: 1000000000000 is outside"),
        "seed_negative": (["run", "head_on_aliasing", "--seed", "-1"],
                          r"--seed: -1 is outside 0\.\.4294967295"),
        "seed_huge": (["sweep", "--seeds", "99999999999999999999"], r"--seeds: 9+ is outside"),
        "seed_float": (["frame", "--seed", "1.5"], r"--seed: '1\.5' is not an integer"),
        "seeds_duplicate": (["sweep", CI, "--seeds", "1", "1", "--out", str(tmp / "d")],
                            r"seeds=\[1, 1\]: duplicate seed"),
        "max_cases_negative": (["report", str(tmp), "--max-cases", "-1"],
                               r"--max-cases: -1 is outside 1\.\.10000"),
        "max_cases_zero": (["report", str(tmp), "--max-cases", "0"], r"--max-cases: 0 is"),
        "scheduler_timeout_zero": (["sweep", "--scheduler-timeout-s", "0"],
                                   r"--scheduler-timeout-s: 0 is outside"),
        # names
        "unknown_case_run": (["run", "nope"], r"unknown case\(s\) \['nope'\]"),
        "unknown_case_sweep": (["sweep", "--scenarios", "nope"], r"unknown case\(s\) \['nope'\]"),
        "unknown_case_simulate": (["simulate", "nope", "--cfg", CFG, "--out",
                                   str(tmp / "x.bin"), "--frames", "1"],
                                  r"unknown scenario 'nope'"),
        "unknown_mimo": (["frame", "--mimo", "fdma"], r"--mimo: invalid choice: 'fdma'"),
        "unknown_layout": (["process", str(afile), "--cfg", CFG, "--layout", "planar"],
                           r"--layout: invalid choice: 'planar'"),
        "unknown_command": (["bogus"], r"invalid choice: 'bogus'"),
        "no_command": ([], r"required: command"),
        "duplicate_scenarios": (["sweep", "--scenarios", "head_on_aliasing", "head_on_aliasing"],
                                r"scenarios: duplicate case\(s\) \['head_on_aliasing'\]"),
        # outputs
        "show_out_is_file": (["show", "head_on_aliasing", "--out", str(afile)],
                             r"--out '.*afile' is a file"),
        "sweep_out_is_file": (["sweep", CI, "--out", str(afile)],
                              r"--out '.*afile': exists and is not a directory"),
        "sweep_out_under_file": (["sweep", CI, "--out", str(afile / "x")],
                                 r"--out '.*afile/x': cannot create or write"),
        "sweep_out_unwritable": (["sweep", CI, "--out", "/proc/radar"],
                                 r"--out '/proc/radar': cannot create or write"),
        "run_out_is_file": (["run", "head_on_aliasing", "--out", str(afile)],
                            r"--out '.*afile': exists and is not a directory"),
        "simulate_out_is_dir": (["simulate", "head_on_aliasing", "--cfg", CFG, "--out",
                                 str(adir)], r"--out '.*adir' is a directory"),
        "simulate_out_no_folder": (["simulate", "head_on_aliasing", "--cfg", CFG, "--out",
                                    str(tmp / "no" / "x.bin")], r"folder '.*/no' does not exist"),
        "process_out_suffix": (["process", str(afile), "--cfg", CFG, "--out", str(tmp / "p.txt")],
                               r"suffix '\.txt' is not one of"),
        "gate_junit_is_dir": (["gate", str(tmp), "--junit", str(adir)],
                              r"--junit '.*adir' is a directory"),
        "report_out_is_dir": (["report", str(tmp), "--out", str(adir)],
                              r"--out '.*adir' is a directory"),
        # schedulers
        "scheduler_without_protocol": (["sweep", CI, "--scheduler", "127.0.0.1:9", "--out",
                                        str(tmp / "s1")], r"give a protocol"),
        "tls_without_security": (["sweep", CI, "--scheduler", "tls://127.0.0.1:9", "--out",
                                  str(tmp / "s2")], r"tls:// needs --security FILE"),
        "security_file_missing": (["sweep", CI, "--scheduler", "tls://127.0.0.1:9",
                                   "--security", str(tmp / "nope.toml"), "--out",
                                   str(tmp / "s3")], r"--security '.*nope\.toml': cannot read"),
        "security_file_keys": (["sweep", CI, "--scheduler", "tls://127.0.0.1:9", "--security",
                                str(afile), "--out", str(tmp / "s4")],
                               r"--security '.*afile'"),
    }



def _ids():
    import tempfile
    from pathlib import Path
    with tempfile.TemporaryDirectory() as d:
        return list(_cases(Path(d)))


@pytest.mark.parametrize("kind", _ids())
def test_bad_argument_exits_2_with_one_line(tmp_path, capsys, kind):
    argv, match = _cases(tmp_path)[kind]
    t0 = time.monotonic()
    assert main(argv) == 2
    assert time.monotonic() - t0 < 20  # parse-time errors, never a run
    err = [ln for ln in capsys.readouterr().err.splitlines() if ln.strip()]
    assert err and err[-1].startswith("radar-harness"), err
    assert "Traceback" not in "\n".join(err)
    assert re.search(match, err[-1]), err[-1]


def test_dead_scheduler_fails_within_the_timeout(tmp_path, capsys):
    # 1 s: the whole wait is the timeout (nothing listens on port 9), and the bound below is
    # far above it either way.
    t0 = time.monotonic()
    assert main(["sweep", CI, "--scheduler", "tcp://127.0.0.1:9", "--scheduler-timeout-s", "1",
                 "--out", str(tmp_path / "r")]) == 2
    assert time.monotonic() - t0 < 15
    last = capsys.readouterr().err.strip().splitlines()[-1]
    assert re.search(r"--scheduler 'tcp://127\.0\.0\.1:9': no Dask scheduler answered within "
                     r"1 s", last)


N_KINDS = len(_ids()) + 1
