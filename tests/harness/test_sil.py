"""Software-in-the-loop chains: the ``[[external_chains]]`` table, every failure mode of a
call (a recorded failure with the command's last stderr lines), point files in both formats,
the reproduction of the built-in chain by an external one that runs `radar-harness process`,
and a sweep in which one external cell fails and the others go on and resume."""
from __future__ import annotations

import json
import os
import sys
import textwrap
import time
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

import pipeline
import radarsim
from harness.sil import ExternalCellRun, ExternalChain, ExternalChainError
from harness.sil.spec import external_chains_from_toml

ROOT = Path(__file__).resolve().parents[2]
SIL_EXAMPLE = ROOT / "examples" / "sil"


def _chain(tmp_path: Path, body: str, **kw) -> ExternalChain:
    """An external chain running a Python script with `body` (``cfg``, ``adc``, ``out``: the
    paths it is given)."""
    script = tmp_path / "chain.py"
    script.write_text("import sys\ncfg, adc, out = sys.argv[1:4]\n" + textwrap.dedent(body))
    return ExternalChain(name="ext", scheme=kw.pop("scheme", "tdma"),
                         command=("{python}", str(script), "{cfg}", "{adc}", "{points}"),
                         **{"timeout_s": 30.0, **kw})


def _run(chain: ExternalChain, n_frames: int = 1, adc=None):
    cfg = radarsim.presets.r79(chain.scheme)
    frames = [adc if adc is not None else
              np.zeros((cfg.n_chirps, cfg.n_rx, cfg.n_samples), cfg.adc_dtype)] * n_frames
    run = ExternalCellRun(chain, cfg, pipeline.ProcessingConfig(), 0.05)
    try:
        for f, a in enumerate(frames):
            run.add_frame(10 + f, a)
        return run.run([10 + f for f in range(n_frames)]), run
    finally:
        run.close()


def _points(r: float, snr: float, frame: int | None = None) -> str:
    """A chain body writing one point (10 deg, -3 m/s) as the CSV text pandas' ``to_csv``
    writes (a NaN as an empty field), without importing pandas (~0.5 s per call)."""
    cols = {"range_m": r, "azimuth_deg": 10.0, "radial_velocity_mps": -3.0,
            **({} if frame is None else {"frame": frame}), "snr_db": snr}
    row = ",".join("" if v != v else str(v) for v in cols.values())
    return f"open(out, 'w').write({','.join(cols) + chr(10) + row + chr(10)!r})\n"


# ------------------------------------------------------------------ the sweep-file table
@pytest.mark.parametrize("table, message", [
    ({"name": "my dsp"}, r"name='my dsp' must be an identifier"),
    ({"command": "my_dsp {points}"}, r"command='my_dsp \{points\}' must be a non-empty list"),
    ({"command": []}, r"command=\[\] must be a non-empty list"),
    ({"command": ["my_dsp", ""]}, r"must be a non-empty list of non-empty strings"),
    ({"command": ["my_dsp", "{adc}"]}, r"must name the point file it writes: \{points\}"),
    ({"command": ["my_dsp", "{points}", "{frames}"]}, r"unknown placeholder\(s\) \['frames'\]"),
    ({"command": ["my_dsp", "{points", "x"]}, r"command argument '\{points'"),
    ({"timeout_s": 0}, r"timeout_s=0 must be a number in \(0, 3600\] s"),
    ({"timeout_s": float("inf")}, r"timeout_s=inf must be a number"),
    ({"timeout_s": True}, r"timeout_s=True must be a number"),
    ({"frames_per_call": 0}, r"frames_per_call=0 must be an integer in 1\.\.100000 or \"cell\""),
    ({"frames_per_call": "all"}, r"frames_per_call='all' must be"),
    ({"points": "points.txt"}, r"points='points\.txt' must be a file name ending in \.csv"),
    ({"points": "../points.csv"}, r"points='\.\./points\.csv' must be a file name"),
    ({"frames": 3}, r"external_chains\[0\]\.frames"),
    ({"scheme": None}, r"scheme=None must be a MIMO scheme name"),
], ids=["name", "command_str", "command_empty", "command_empty_arg", "no_points",
        "unknown_placeholder", "bad_format", "timeout_zero", "timeout_inf", "timeout_bool",
        "frames_zero", "frames_word", "points_suffix", "points_path", "unknown_key",
        "scheme_none"])
def test_bad_external_chain_table(tmp_path, table, message):
    base = {"name": "my_dsp", "scheme": "tdma", "command": ["my_dsp", "{points}"]}
    with pytest.raises(ValueError, match=message):
        external_chains_from_toml("s.toml", [{**base, **table}], tmp_path)


def test_external_chain_table_structure(tmp_path):
    with pytest.raises(ValueError, match=r"external_chains\[0\]\.command: required key"):
        external_chains_from_toml("s.toml", [{"name": "a", "scheme": "tdma"}], tmp_path)
    with pytest.raises(ValueError, match=r"must be an array of \[\[external_chains\]\]"):
        external_chains_from_toml("s.toml", {"name": "a"}, tmp_path)
    one = {"name": "a", "scheme": "tdma", "command": ["x", "{points}"]}
    with pytest.raises(ValueError, match=r"duplicate name\(s\) \['a'\]"):
        external_chains_from_toml("s.toml", [one, one], tmp_path)


@pytest.mark.parametrize("name, scheme, message", [
    ("tdma_raw", "tdma", r"name='tdma_raw' is already a registered scheme"),
    ("mine", "fdma", r"external_chains 'mine': mimo='fdma' is not one of"),
], ids=["name_taken", "unknown_scheme"])
def test_external_chain_names_are_checked_against_the_registries(tmp_path, name, scheme,
                                                                 message):
    f = tmp_path / "s.toml"
    f.write_text(f'name = "s"\nscenarios = ["head_on_aliasing"]\n[[external_chains]]\n'
                 f'name = "{name}"\nscheme = "{scheme}"\ncommand = ["x", "{{points}}"]\n')
    from harness.sweep.file import load_sweep
    with pytest.raises(ValueError, match=message):
        load_sweep(f)


def test_the_program_path_resolves_against_the_sweep_folder_and_its_file_is_hashed(tmp_path):
    (tmp_path / "dsp").write_text("v1")
    t = {"name": "a", "scheme": "tdma", "command": ["./dsp", "{cfg}", "{points}"]}
    (c1,) = external_chains_from_toml("s.toml", [t], tmp_path)
    assert c1.argv("P", "A", "O")[0] == str((tmp_path / "dsp").resolve())
    (tmp_path / "dsp").write_text("v2")
    (c2,) = external_chains_from_toml("s.toml", [t], tmp_path)
    assert c1.files_sha256 != c2.files_sha256  # an edited program recomputes its cells


# ------------------------------------------------------------------ failure modes of a call
FAILURES = {
    "exit_code": ("sys.stderr.write('loading model\\nsegfault in cfar\\n'); sys.exit(3)",
                  r"exited with status 3; last stderr: loading model \| segfault in cfar"),
    "no_output": ("sys.stderr.write('nothing to say\\n')",
                  r"wrote no point file 'points\.csv'; last stderr: nothing to say"),
    "empty_file": ("open(out, 'w').close()", r"wrote no point file"),
    "garbage": ("open(out, 'wb').write(bytes(range(256)) * 4)", r"does not parse"),
    "wrong_columns": ("open(out, 'w').write('r,az\\n1,2\\n')",
                      r"lacks column\(s\) \['range_m', 'azimuth_deg', 'radial_velocity_mps', "
                      r"'snr_db'\]"),
    "text_column": ("open(out, 'w').write('range_m,azimuth_deg,radial_velocity_mps,snr_db\\n"
                    "near,1,2,3\\n')", r"column 'range_m' is not numeric"),
    "nan": (_points(12.0, float("nan")),
            r"column 'snr_db' holds non-finite value nan \(row 0\)"),
    "out_of_range": (_points(1e6, 20.0),
                     r"column 'range_m' value 1e\+06 \(row 0\) is outside \[0, 25"),
}


@pytest.mark.parametrize("item", list(FAILURES))
def test_every_failure_of_a_call_names_the_chain_the_call_and_the_cause(tmp_path, item):
    body, message = FAILURES[item]
    with pytest.raises(ExternalChainError, match=r"external chain 'ext' call 1/1 \(frames "
                                                 rf"10\.\.10\): .*{message}"):
        _run(_chain(tmp_path, body))


def test_a_frame_outside_the_call_is_refused(tmp_path):
    body = _points(12.0, 20.0, frame=2)
    with pytest.raises(ExternalChainError, match=r"column 'frame' value 2 .* outside \[0, 1\]"):
        _run(_chain(tmp_path, body, frames_per_call="cell"), n_frames=2)


def _state(pid: int) -> str:
    try:
        return Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[0]
    except OSError:
        return "gone"


def test_a_timeout_kills_the_whole_process_group(tmp_path):
    pid_file = tmp_path / "child.pid"
    body = f"""
        import subprocess, time
        child = subprocess.Popen([sys.executable, "-c", "import signal, time; "
                                  "signal.signal(signal.SIGTERM, signal.SIG_IGN); "
                                  "time.sleep(120)"])
        open({str(pid_file)!r}, "w").write(str(child.pid))
        sys.stderr.write("waiting for the DSP\\n"); sys.stderr.flush()
        time.sleep(120)
    """
    t0 = time.monotonic()
    with pytest.raises(ExternalChainError, match=r"no result within timeout_s=2 s \(its "
                                                 r"process group was killed\); last stderr: "
                                                 r"waiting for the DSP"):
        _run(_chain(tmp_path, body, timeout_s=2.0))
    assert time.monotonic() - t0 < 60
    pid = int(pid_file.read_text())
    for _ in range(50):  # SIGKILL is asynchronous: the child is dead (or a zombie) shortly
        if _state(pid) in ("gone", "Z"):
            break
        time.sleep(0.1)
    assert _state(pid) in ("gone", "Z"), "the child that ignores SIGTERM survived"


def test_a_program_that_cannot_start_is_named(tmp_path):
    chain = ExternalChain(name="ext", scheme="tdma", command=(str(tmp_path / "nope"),
                                                              "{points}"))
    with pytest.raises(ExternalChainError, match=r"cannot start '.*nope'"):
        _run(chain)


# ------------------------------------------------------------------ point files
def test_csv_points_of_one_frame_become_its_point_cloud(tmp_path):
    (cloud,), run = _run(_chain(tmp_path, _points(12.0, 20.0)))
    assert list(cloud.columns) == pipeline.POINT_CLOUD_COLUMNS
    row = cloud.iloc[0]
    assert row["range_m"] == 12.0 and row["elevation_deg"] == 0.0
    assert row["x_m"] == pytest.approx(12.0 * np.cos(np.radians(10.0)))
    assert row["y_m"] == pytest.approx(12.0 * np.sin(np.radians(10.0)))
    assert run.n_calls == 1 and run.elapsed_s > 0


def test_parquet_points_of_a_whole_cell_are_split_by_frame(tmp_path):
    body = """
        import pandas as pd
        assert open(adc, "rb").read(1)  # the capture of the call's frames
        pd.DataFrame({"frame": [0, 2, 2], "range_m": [5.0, 6.0, 7.0],
                      "azimuth_deg": [0.0, 1.0, 2.0], "elevation_deg": [0.0, 0.0, 3.0],
                      "radial_velocity_mps": [1.0, 2.0, 3.0],
                      "snr_db": [10.0, 11.0, 12.0]}).to_parquet(out)
    """
    clouds, run = _run(_chain(tmp_path, body, frames_per_call="cell",
                              points="points.parquet"), n_frames=3)
    assert [len(c) for c in clouds] == [1, 0, 2] and run.n_calls == 1
    assert clouds[2]["elevation_deg"].tolist() == [0.0, 3.0]


def test_frames_per_call_splits_the_capture(tmp_path):
    cfg = radarsim.presets.r79("tdma")
    frame_bytes = cfg.n_chirps * cfg.n_rx * cfg.n_samples * 2
    body = f"""
        import os
        n = os.path.getsize(adc) // {frame_bytes}
        sys.stderr.write(f"{{n}} frames\\n")
        open(out, "w").write("frame,range_m,azimuth_deg,radial_velocity_mps,snr_db\\n" +
                             "".join(f"{{k}},{{n}}.0,0,0,10\\n" for k in range(n)))
    """
    clouds, run = _run(_chain(tmp_path, body, frames_per_call=2), n_frames=3)
    assert run.n_calls == 2
    assert [c["range_m"].tolist() for c in clouds] == [[2.0], [2.0], [1.0]]


# ------------------------------------------------------------------ reproduction
def test_an_external_chain_running_process_reproduces_the_built_in_chain(tmp_path):
    from harness.testing import two_target_scene
    cfg = radarsim.presets.r79("ddma")
    adc = radarsim.simulate_frame(cfg, two_target_scene(), np.random.default_rng(3))
    chain = ExternalChain(name="ext", scheme="ddma", points="points.parquet",
                          command=("{python}", str(SIL_EXAMPLE / "process_chain.py"),
                                   "--cfg", "{cfg}", "--adc", "{adc}", "--out", "{points}"),
                          timeout_s=300.0)
    (ext,), run = _run(chain, adc=adc)
    # What the profile cannot carry: the Pfa design (written as the threshold it gives).
    assert [d.split(":")[0] for d in run.profile.differences] == ["cfar.pfa",
                                                                  "cfar.threshold_db"]
    own = pipeline.process_frame(cfg, adc)
    assert len(own) >= 2
    for c in ("range_m", "azimuth_deg", "elevation_deg", "radial_velocity_mps", "snr_db"):
        np.testing.assert_array_equal(ext[c].to_numpy(), own[c].to_numpy(dtype=np.float64))


def _sweep(tmp_path: Path, name: str, body: str, extra: str = "") -> Path:
    script = tmp_path / "chain.py"
    script.write_text("import sys\ncfg, adc, out = sys.argv[1:4]\n" + textwrap.dedent(body))
    f = tmp_path / f"{name}.toml"
    f.write_text(textwrap.dedent(f"""
        name = "{name}"
        scenarios = ["blind_spot_overtaking"]
        duration_s = 0.1
        schemes = ["tdma"]
        {extra}
        [[external_chains]]
        name = "ext"
        scheme = "tdma"
        command = ["{{python}}", "{{here}}/chain.py", "{{cfg}}", "{{adc}}", "{{points}}"]
        timeout_s = 120
    """))
    return f


def test_a_failing_external_cell_is_recorded_and_the_sweep_goes_on_and_resumes(tmp_path):
    from harness.cli import main
    body = """
        text = open(cfg).read()
        if "extendedMaxVelocity -1 0" in text:
            sys.stderr.write("unsupported: no velocity extension\\n")
            sys.exit(4)
        open(out, "w").write("range_m,azimuth_deg,radial_velocity_mps,snr_db\\n")
    """
    f = _sweep(tmp_path, "fails", body, '[vary]\n"processing.velocity.tdma_disambiguation" = '
                                         '[true, false]')
    out = tmp_path / "out"
    assert main(["sweep", str(f), "--workers", "1", "--out", str(out)]) == 1
    summary = pd.read_parquet(out / "summary.parquet")
    err = summary[summary["error"] != ""]
    assert len(err) == 1 and "tdma_disambiguation=False" in err["variant"].iloc[0]
    assert "ExternalChainError: external chain 'ext' call 1/2" in err["error"].iloc[0]
    assert "exited with status 4; last stderr: unsupported: no velocity extension" \
        in err["error"].iloc[0]
    ok = summary[summary["error"] == ""]
    assert sorted(ok["scheme"]) == ["ext", "tdma"]
    assert ok.set_index("scheme").loc["ext", "external_call_s_per_frame"] > 0
    assert np.isnan(ok.set_index("scheme").loc["tdma", "external_call_s_per_frame"])
    assert ok.set_index("scheme").loc["ext", "detections_per_frame"] == 0
    manifest = json.loads((out / "manifest.json").read_text())
    assert [c["status"] for c in manifest["cells"]] == ["ok", "error"]
    # Rerun: the completed cell is resumed, the failed one retried (and fails again).
    assert main(["sweep", str(f), "--workers", "1", "--out", str(out)]) == 1
    manifest = json.loads((out / "manifest.json").read_text())
    assert [c["origin"] for c in manifest["cells"]] == ["resumed", "error"]


@pytest.mark.slow
def test_the_sil_example_reproduces_the_built_in_summary_row(tmp_path):
    from harness.cli import main
    out = tmp_path / "sil"
    assert main(["sweep", str(SIL_EXAMPLE / "sweep.toml"), "--duration-s", "0.5",
                 "--workers", "1", "--out", str(out)]) == 0
    s = pd.read_parquet(out / "summary.parquet").set_index("scheme")
    # The external row's own columns: its timing and its SNR gain over the built-in (0 dB,
    # same detections); x/y are recomputed from the file's degrees (last-bit differences).
    own = {"external_call_s_per_frame", "error"} | {c for c in s if c.startswith("snr_gain")}
    for c in s.columns.difference(sorted(own)):
        a, b = s.loc["ddma", c], s.loc["sil_ddma", c]
        if isinstance(a, (float, np.floating)):
            assert a == pytest.approx(b, rel=1e-12, abs=1e-12, nan_ok=True), c
        else:
            assert a == b, c
    assert s.loc["sil_ddma", "snr_gain_median_db"] == 0.0
    det = pd.read_parquet(out / "detections.parquet")
    cols = ["frame", "range_m", "azimuth_deg", "radial_velocity_mps", "snr_db", "label"]
    pd.testing.assert_frame_equal(
        det[det["scheme"] == "ddma"][cols].reset_index(drop=True),
        det[det["scheme"] == "sil_ddma"][cols].reset_index(drop=True), check_dtype=False)
    assert os.path.isfile(out / "manifest.json") and sys.executable
