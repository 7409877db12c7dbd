"""Bad-input probes of the surfaces added after the second round (`tests.harness.probes` has
the `Probe` record, `classify` and the first rounds' probes): damaged results folders under
gate and report, what a report must say is missing, board calibration lines under process,
calibrate on a bad capture, mmWave Studio setup files, a lab's chip / board / repair-method
records and the registration calls, full disks under process and simulate, a nohup'ed pool
sweep's hang-up, OpenSCENARIO files, case keys and the export command.

Like the first rounds' probes they use only the CLI and public APIs; each builds its inputs
under the probe's temporary folder. ``python -m tests.harness.probe_survey`` counts them with
the rest; `tests/harness/test_probes_surfaces.py` asserts that every one is clear.
"""
from __future__ import annotations

import contextlib
import copy
import dataclasses
import errno
import json
import os
import re
import shutil
import signal
import time
from pathlib import Path

import numpy as np
import pandas as pd

from tests.harness.probe_kit import Probe, failing_writes, fake_results

__all__ = ["surface_probes", "probes_of", "SURFACES", "FullDisk"]

PROFILES = Path(__file__).resolve().parents[1] / "radarsim" / "profiles"
GATES = '[[gate]]\nname = "ghosts"\nmetric = "ghost_rate"\nmax = 1.0\n'


def write(tmp: Path, name: str, text: str) -> Path:
    p = tmp / name
    p.write_text(text)
    return p


# ----------------------------------------------------------------------------- results folders
def results_copy(tmp: Path) -> Path:
    """A copy of the stand-in sweep's results folder (tables and manifest) under `tmp`."""
    d = tmp / "res"
    if not d.exists():
        shutil.copytree(fake_results(tmp), d, ignore=shutil.ignore_patterns("cells", "*.html",
                                                                            "*.md"))
    return d


def with_manifest(**fields):
    def change(d: Path) -> None:
        man = json.loads((d / "manifest.json").read_text())
        man.update(fields)
        (d / "manifest.json").write_text(json.dumps(man))
    return change


def dropping(table: str, column: str):
    def change(d: Path) -> None:
        f = d / f"{table}.parquet"
        pd.read_parquet(f).drop(columns=column).to_parquet(f)
    return change


def summary_with(fn):
    def change(d: Path) -> None:
        f = d / "summary.parquet"
        fn(pd.read_parquet(f)).to_parquet(f)
    return change


#: Damaged manifests and tables -> what the one line must name.
DAMAGES = {
    "cells_string": (with_manifest(cells="abc"), r"manifest\.json: damaged manifest \(cells="),
    "cells_numbers": (with_manifest(cells=[1, 2]), r"manifest\.json: .*cells\[0\]=1"),
    "cell_without_id": (with_manifest(cells=[{"status": "ok"}]), r"cells\[0\]\.cell_id"),
    "git_string": (with_manifest(git="abc"), r"manifest\.json: .*git='abc'"),
    "baseline_number": (with_manifest(baseline_scheme=5), r"baseline_scheme=5"),
    "n_ok_string": (with_manifest(n_ok="x"), r"n_ok='x'"),
    "n_ok_true": (with_manifest(n_ok=True), r"n_ok=True"),
    "sweep_list": (with_manifest(sweep=[1]), r"sweep=\[1\]"),
    "nested_200000": (lambda d: (d / "manifest.json").write_text("[" * 200_000 + "]" * 200_000),
                      r"manifest\.json: damaged manifest \(nested deeper"),
    "actors_without_detected": (dropping("actors", "detected"),
                                r"actors\.parquet: .*\['detected'\]"),
    "summary_without_seed": (dropping("summary", "seed"), r"summary\.parquet: .*\['seed'\]"),
    "truth_without_actor_id": (dropping("truth", "actor_id"), r"truth\.parquet: .*actor_id"),
    "detections_missing": (lambda d: (d / "detections.parquet").unlink(),
                           r"detections\.parquet: missing"),
    "frames_torn": (lambda d: (d / "actors.parquet").write_bytes(b"PAR1 torn"),
                    r"actors\.parquet: not a readable Parquet"),
}
#: Of these, the ones `gate` reads too (it reads the manifest and the summary only).
GATE_READS = ("cells_string", "cells_numbers", "cell_without_id", "git_string",
              "baseline_number", "n_ok_string", "n_ok_true", "sweep_list", "nested_200000")

#: What a report must say the results lack (exit 0, a warning on stderr and in the page).
GAPS = {
    "baseline_not_run": (with_manifest(baseline_scheme="bpm"),
                         r"warning: baseline scheme 'bpm' was not run"),
    "n_ok_nan": (with_manifest(n_ok=float("nan")), r"warning: .*records no n_ok \(nan\)"),
    "metric_column_missing": (summary_with(lambda s: s.drop(columns=["n_ghost"])),
                              r"warning: summary\.parquet has no column\(s\) \['n_ghost'\]"),
    "metric_column_all_nan": (summary_with(lambda s: s.assign(ghost_rate=np.nan)),
                              r"warning: .*\['ghost_rate'\] hold no finite value"),
}


def damaged(kind: str, cmd: str, table: dict):
    def call(t: Path):
        d = results_copy(t)
        table[kind][0](d)
        return [cmd, d] + (["--no-maps"] if cmd == "report" else
                           ["--thresholds", write(t, "g.toml", GATES), "--markdown", t / "g.md"])
    return call


def results_probes() -> list[Probe]:
    out = [Probe("results", f"{cmd}_{k}", damaged(k, cmd, DAMAGES), DAMAGES[k][1])
           for k in DAMAGES for cmd in ("gate", "report") if cmd == "report" or k in GATE_READS]
    out += [Probe("report_gaps", k, damaged(k, "report", GAPS), GAPS[k][1], code=0)
            for k in GAPS]
    return out


# ----------------------------------------------------------------------------- TI profiles
def zero_capture(tmp: Path, profile: Path) -> Path:
    """A one-frame all-zero capture of `profile`'s radar."""
    from radarsim.capture import write_capture
    from radarsim.ti import parse_setup
    cap = tmp / f"{profile.stem}.bin"
    if not cap.exists():
        cfg = parse_setup(profile).radar
        dtype = np.complex64 if cfg.is_complex else np.int16
        write_capture(cap, [np.zeros((cfg.n_chirps, cfg.n_rx, cfg.n_samples), dtype)], cfg=cfg)
    return cap


def process_with(profile: str, old: str, new: str):
    """`process` of a zero capture with a line of a shipped profile replaced."""
    def call(t: Path):
        src = PROFILES / f"{profile}.cfg"
        text = src.read_text()
        if old not in text:
            raise AssertionError(f"{old!r} not in {src.name}")
        return ["process", zero_capture(t, src), "--cfg", write(t, "p.cfg", text.replace(old, new)),
                "--out", t / "o.csv"]
    return call


COMP = "compRangeBiasAndRxChanPhase 0.0 " + " ".join(["1 0"] * 12)
ACAL = "antennaCalibParams " + " ".join(["0 1"] * 16)


def calibration_line_probes() -> list[Probe]:
    def comp(name, new, match):
        return Probe("board_calibration", name, process_with("xwr18_visualizer", COMP, new),
                     match)
    return [
        comp("range_bias_1e300", COMP.replace(" 0.0 ", " 1e300 "),
             r"compRangeBiasAndRxChanPhase\): rangeBias = 1e\+300 m is outside \+/-10 m"),
        comp("range_bias_-1e6", COMP.replace(" 0.0 ", " -1e6 "), r"rangeBias = -1e\+06 m"),
        comp("range_bias_11", COMP.replace(" 0.0 ", " 11 "), r"rangeBias = 11 m is outside"),
        comp("range_bias_nan", COMP.replace(" 0.0 ", " nan "), r"rangeBias"),
        comp("coefficients_all_zero", "compRangeBiasAndRxChanPhase 0.0 " + " ".join(["0 0"] * 12),
             r"every coefficient is 0 \+ 0j"),
        comp("coefficient_one_zero", "compRangeBiasAndRxChanPhase 0.0 0 0 " +
             " ".join(["1 0"] * 11), r"chip Tx1 Rx1 is 0 \+ 0j"),
        Probe("board_calibration", "antenna_calib_all_zero",
              process_with("awr2944p_ddm", ACAL, "antennaCalibParams " + " ".join(["0 0"] * 16)),
              r"antennaCalibParams\): every coefficient is 0 \+ 0j"),
        Probe("board_calibration", "processing_range_bias_1e300", cli=False,
              call=lambda t: __import__("pipeline").ProcessingConfig().replace(
                  **{"calibration.range_bias_m": 1e300}),
              match=r"range_bias_m=1e\+300 is outside \+/-10 m"),
    ]


# ----------------------------------------------------------------------------- calibrate
CAL_PROFILE = PROFILES / "xwr68_aop.cfg"


def reflector_capture(tmp: Path, rcs: tuple, offsets_bins: tuple) -> tuple[Path, float]:
    """A 2-frame capture of static reflectors (RCS m^2) at 40 bins + offsets on boresight."""
    import warnings

    import radarsim
    from radarsim.capture import write_capture
    from radarsim.ti import parse_ti_cfg
    cfg = parse_ti_cfg(CAL_PROFILE).radar
    r = 40 * cfg.range_resolution_m
    rr = np.array([r + k * cfg.range_resolution_m for k in offsets_bins])
    n = len(rr)
    sc = radarsim.Scatterers.from_spherical(rr, np.zeros(n), np.zeros(n), np.zeros(n),
                                            np.array(rcs))
    rng = np.random.default_rng(1)
    cap = tmp / "reflector.bin"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", radarsim.ADCSaturationWarning)
        write_capture(cap, [radarsim.simulate_frame(cfg, sc, rng) for _ in range(2)], cfg=cfg)
    return cap, r


def calibrate(rcs=(1e-4,), offsets=(0.0,), write_to=None):
    def call(t: Path):
        cap, r = reflector_capture(t, rcs, offsets)
        prof = write(t, "p.cfg", CAL_PROFILE.read_text())
        target = {"capture": cap, "profile": prof, None: None}[write_to]
        return ["calibrate", cap, "--cfg", prof, "--target-range-m", f"{r}"] + \
            (["--write", target] if target is not None else [])
    return call


def calibrate_probes() -> list[Probe]:
    return [
        Probe("calibrate", "clipped_capture", calibrate(rcs=(1e6,)),
              r"the capture is clipped: 2 of 2 frame\(s\)"),
        Probe("calibrate", "two_equal_reflectors_1.5_bins", calibrate((1e-4, 1e-4), (0.0, 1.5)),
              r"ambiguous reflector: a second return at"),
        Probe("calibrate", "two_equal_reflectors_3_bins", calibrate((1e-4, 1e-4), (0.0, 3.0)),
              r"ambiguous reflector"),
        Probe("calibrate", "write_over_capture", calibrate(write_to="capture"),
              r"--write .* is the CAPTURE file being read"),
        Probe("calibrate", "write_over_profile", calibrate(write_to="profile"),
              r"--write .* is the --cfg file being read"),
    ]


# ----------------------------------------------------------------------------- Studio setups
STUDIO_JSON = PROFILES / "awr1243_studio_setup.mmwave.json"
STUDIO_LOG = PROFILES / "awr2243_studio_LogFile.txt"
_RF = ("mmWaveDevices", 0, "rfConfig")
_INT = r"must be an integer"


def json_setup(path: tuple, value):
    """`process` with the setup JSON's value at `path` replaced (the capture is never read:
    the setup is refused first)."""
    def call(t: Path):
        data = json.loads(STUDIO_JSON.read_text())
        obj = data
        for key in path[:-1]:
            obj = obj[key]
        obj[path[-1]] = copy.deepcopy(value)
        setup = write(t, "setup.mmwave.json", json.dumps(data))
        return ["process", write(t, "c.bin", ""), "--cfg", setup, "--out", t / "o.csv"]
    return call


def log_setup(transform):
    def call(t: Path):
        setup = write(t, "LogFile.txt", transform(STUDIO_LOG.read_text()))
        return ["process", write(t, "c.bin", ""), "--cfg", setup, "--out", t / "o.csv"]
    return call


def studio_probes() -> list[Probe]:
    frame, prof = _RF + ("rlFrameCfg_t",), _RF + ("rlProfiles", 0, "rlProfileCfg_t")
    cases = {
        "numLoops_null": (frame + ("numLoops",), None, r"numLoops=None " + _INT),
        "numLoops_list": (frame + ("numLoops",), [128], r"numLoops=\[128\] " + _INT),
        "numLoops_64.7": (frame + ("numLoops",), 64.7, r"numLoops=64\.7 " + _INT),
        "numLoops_true": (frame + ("numLoops",), True, r"numLoops=True " + _INT),
        "numLoops_abc": (frame + ("numLoops",), "abc", r"numLoops='abc' " + _INT),
        "start_freq_abc": (prof + ("startFreqConst_GHz",), "abc",
                           r"startFreqConst_GHz='abc' must be a finite number"),
        "start_freq_null": (prof + ("startFreqConst_GHz",), None, r"startFreqConst_GHz=None"),
        "sample_rate_9999.9": (prof + ("digOutSampleRate",), 9999.9,
                               r"digOutSampleRate=9999\.9 " + _INT),
        "rx_mask_true": (_RF + ("rlChanCfg_t", "rxChannelEn"), True, r"rxChannelEn=True"),
        "profiles_null": (_RF + ("rlProfiles",), None, r"rlProfiles=None must be a list"),
        "chirps_string": (_RF + ("rlChirps",), "abc", r"rlChirps='abc' must be a list"),
        "unknown_device": (("mmWaveDevices", 0, "mmWaveDevice"), "AWR9999",
                           r"mmWaveDevice: chip 'AWR9999' is not one the harness knows"),
    }
    out = [Probe("studio_setups", k, json_setup(p, v), m) for k, (p, v, m) in cases.items()]
    out += [
        Probe("studio_setups", "log_unknown_chip",
              log_setup(lambda s: s.replace("select_chip_version,AWR2243",
                                            "select_chip_version,AWR9999")),
              r"API:select_chip_version\): chip 'AWR9999' is not one the harness knows"),
        Probe("studio_setups", "log_without_profile_config",
              log_setup(lambda s: "\n".join(ln for ln in s.splitlines()
                                            if "API:ProfileConfig" not in ln) + "\n"),
              r"LogFile: .* has no API:ProfileConfig call"),
        Probe("studio_setups", "log_empty", log_setup(lambda s: ""), r"LogFile\.txt' is empty"),
        Probe("studio_setups", "log_loops_float",
              log_setup(lambda s: re.sub(r"(API:FrameConfig,0,1,100,)128,", r"\g<1>64.7,", s)),
              r"API:FrameConfig\): .* is not a list of integers"),
    ]
    return out


# ----------------------------------------------------------------------------- registrations
def chip(**kw):
    from radarsim.chips import CHIPS
    return dataclasses.replace(CHIPS["AWR2944"], name="PROBE_CHIP", **kw)


def limits(rate):
    from radarsim.chips import AdcLimits
    return chip(adc={"real": AdcLimits(rate)})


def board(**kw):
    from radarsim.boards import BOARDS
    return dataclasses.replace(BOARDS["AWR2944EVM"], name="PROBE_BOARD", **kw)


def repair(kind: str = "lowrank", **kw):
    """A repair method of the registered kind of `kind` (its class, new parameters)."""
    from pipeline.interference import MITIGATIONS
    return type(MITIGATIONS[kind])(name="probe", description="", **kw)


def registration_probes() -> list[Probe]:
    def api(name, fn, match):
        return Probe("registrations", name, cli=False, call=lambda t: fn(), match=match)
    far = ((0.0, 0.0), (1e300, 0.8), (2.0, 0.0), (4.0, 0.0))
    return [
        api("chip_adc_rate_nan", lambda: limits(float("nan")), r"adc\['real'\].*finite number"),
        api("chip_adc_rate_string", lambda: limits("fast"), r"adc\['real'\].*finite number"),
        api("chip_adc_rate_-1", lambda: limits(-1.0), r"adc\['real'\].*> 0"),
        api("chip_adc_mode_float", lambda: chip(adc={"real": 37.5e6}), r"must be AdcLimits"),
        api("chip_max_loops_1e9", lambda: chip(max_loops=10**9), r"max_loops=1000000000 exceeds"),
        api("chip_chirp_defs_1e6", lambda: chip(max_chirp_defs=10**6), r"max_chirp_defs="),
        api("board_element_1e300", lambda: board(tx_positions_wl=far),
            r"element coordinate 1e\+300 wavelengths"),
        api("config_element_1e300",
            lambda: __import__("radarsim").presets.r79_ddma(**{"array.tx_positions_wl": far}),
            r"tx_positions_wl: element coordinate 1e\+300"),
        api("repair_rank_gate_1e300", lambda: repair(rank_snr_gate_db=1e300),
            r"rank_snr_gate_db=1e\+300 exceeds 150"),
        api("repair_ar_order_1e6", lambda: repair("ar", ar_order=10**6),
            r"ar_order=1000000 exceeds 512"),
        api("repair_grow_sigma_1e9", lambda: repair(grow_sigma=1e9), r"grow_sigma=.* exceeds"),
        api("repair_taper_1e7", lambda: repair("windowed_zero", taper_samples=10**7),
            r"taper_samples=.* exceeds"),
        api("register_chip_string", lambda: __import__("radarsim").register_chip("AWR2944"),
            r"chip must be a Chip, got str"),
        api("register_board_dict", lambda: __import__("radarsim").register_board({"name": "x"}),
            r"board must be a Board, got dict"),
        api("register_scheme_none", lambda: __import__("radarsim").register_scheme(None),
            r"scheme must be a MimoScheme, got NoneType"),
        api("register_chain_object", lambda: chain_registration(object()),
            r"chain must be a MimoChain, got object"),
        api("register_report_section_object", lambda: section_registration(object()),
            r"report section must be a ReportSection, got object"),
        api("register_chip_replace_string",
            lambda: __import__("radarsim").register_chip(chip(), replace="yes"),
            r"replace='yes' must be true or false"),
    ]


def chain_registration(obj):
    from pipeline.mimo.base import register_chain
    return register_chain(obj)


def section_registration(obj):
    from harness.report.sections import register_report_section
    return register_report_section(obj)


# ----------------------------------------------------------------------------- full disks
class FullDisk:
    """A file opened for writing on a full disk: the open succeeds, the first write raises
    ENOSPC without a file name, as write(2) does."""

    def __init__(self, path, mode="r", *a, **k):
        self.fh = open(path, mode, *a, **k)

    def write(self, data):
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.fh.close()


@contextlib.contextmanager
def patched(obj, name: str, value):
    old = getattr(obj, name, None)
    setattr(obj, name, value)
    try:
        yield
    finally:
        if old is None:
            delattr(obj, name)
        else:
            setattr(obj, name, old)


def full_disk_probes() -> list[Probe]:
    def simulate(t: Path):
        from radarsim.capture import dca1000  # the module that writes a capture
        (t / "o").mkdir()
        return (["simulate", "head_on_aliasing", "--cfg", PROFILES / "xwr18_visualizer.cfg",
                 "--out", t / "o" / "c.bin", "--frames", "1"],
                patched(dca1000, "open", FullDisk))

    def process(t: Path):
        prof = PROFILES / "xwr18_visualizer.cfg"

        def no_space(df, *a, **k):
            raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))
        return (["process", zero_capture(t, prof), "--cfg", prof, "--out", t / "o.csv",
                 "--no-track"], patched(pd.DataFrame, "to_csv", no_space))
    return [
        Probe("writes", "simulate_full_disk_on_write", simulate,
              r"--out: cannot write '.*c\.bin': no space left"),
        Probe("writes", "process_full_disk_on_write", process,
              r"--out: cannot write '.*o\.csv': no space left"),
    ]


# ----------------------------------------------------------------------------- hang-up
def nohup_sweep(t: Path) -> None:
    """A pool sweep started with SIGHUP ignored (nohup), then SIGHUP to its process group:
    the clear answer is that it finishes every cell."""
    import subprocess
    import sys
    f = write(t, "s.toml", 'name = "hup"\nscenarios = ["head_on_aliasing", "dense_highway"]\n'
                           'seeds = [0]\nduration_s = 0.5\n')
    p = subprocess.Popen([sys.executable, "-m", "harness.cli", "sweep", str(f), "--out",
                          str(t / "r"), "--workers", "2", "--no-progress"],
                         stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True,
                         start_new_session=True,
                         preexec_fn=lambda: signal.signal(signal.SIGHUP, signal.SIG_IGN))
    import psutil
    deadline = time.monotonic() + 60
    while len(psutil.Process(p.pid).children()) < 2 and time.monotonic() < deadline:
        time.sleep(0.05)
    time.sleep(0.5)
    os.killpg(p.pid, signal.SIGHUP)
    _, err = p.communicate(timeout=300)
    raise ValueError(f"exit {p.returncode}: {err.strip().splitlines()[-1:] if err else ''}")


def signal_probes() -> list[Probe]:
    return [Probe("signals", "nohup_pool_sweep_sighup", cli=False, call=nohup_sweep,
                  match=r"exit 0: ", time_factor=6.0)]


def surface_probes() -> list[Probe]:
    return (results_probes() + calibration_line_probes() + calibrate_probes()
            + studio_probes() + registration_probes() + full_disk_probes() + signal_probes()
            + openscenario_probes())


#: Surfaces of this module's probes (the writes and signals surfaces are shared).
SURFACES = ("results", "report_gaps", "board_calibration", "calibrate", "studio_setups",
            "registrations", "writes", "signals", "openscenario")


def probes_of(surface: str) -> list[Probe]:
    return [p for p in surface_probes() if p.surface == surface]


# ----------------------------------------------------------------------------- OpenSCENARIO
OSC_DATA = Path(__file__).resolve().parents[1] / "data" / "openscenario"
#: Nested entities expanding to 34 x 10^8 characters ("billion laughs").
_BOMB = ('<?xml version="1.0"?>\n<!DOCTYPE r [<!ENTITY a "' + "a" * 34 + '">'
         + "".join(f'<!ENTITY {c} "' + f"&{p};" * 10 + '">'
                   for p, c in zip("abcdefgh", "bcdefghi"))
         + ']>\n<OpenSCENARIO>&i;</OpenSCENARIO>\n')


def xosc_case(tmp: Path, text: str | None = None, name: str = "s.xosc") -> Path:
    """A copy of the ELK test file (and its road) under `tmp`, or `text` written as `name`."""
    for f in OSC_DATA.glob("*"):
        if not (tmp / f.name).exists():
            shutil.copy(f, tmp / f.name)
    if text is None:
        return tmp / "elk_overtaking_motorbike.xosc"
    return write(tmp, name, text)


def openscenario_probes() -> list[Probe]:
    def show(make):
        return lambda t: ["show", make(t), "--out", t / "v"]

    def toml(body):
        return show(lambda t: (xosc_case(t), write(t, "c.toml", body))[1])
    def export_denied(err):
        return lambda t: (["export", "head_on_aliasing", "--format", "xosc", "--out", t / "x"],
                          _denied(t / "x", err))
    ro, full = export_denied(errno.EROFS), export_denied(errno.ENOSPC)
    return [
        Probe("openscenario", "export_out_is_a_file",
              lambda t: ["export", "head_on_aliasing", "--format", "xosc", "--out",
                         write(t, "f", "x")], r"--out '.*f': exists and is not a folder"),
        Probe("openscenario", "export_unknown_format",
              lambda t: ["export", "head_on_aliasing", "--format", "pdf", "--out", t / "x"],
              r"invalid choice: 'pdf'"),
        Probe("openscenario", "export_read_only", ro, r"read-only"),
        Probe("openscenario", "export_full_disk", full, r"no space left"),
        Probe("openscenario", "xosc_not_xml", show(lambda t: xosc_case(t, "not xml\n")),
              r"s\.xosc"),
        Probe("openscenario", "xosc_empty", show(lambda t: xosc_case(t, "")), r"s\.xosc"),
        Probe("openscenario", "xosc_entity_bomb", show(lambda t: xosc_case(t, _BOMB)),
              r"s\.xosc"),
        Probe("openscenario", "xosc_deep_nesting",
              show(lambda t: xosc_case(t, "<a>" * 100_000 + "</a>" * 100_000)), r"s\.xosc"),
        Probe("openscenario", "xosc_is_a_directory",
              show(lambda t: (t / "d.xosc").mkdir() or t / "d.xosc"), r"directory"),
        Probe("openscenario", "toml_xosc_missing", toml('xosc = "missing.xosc"\n'),
              r"missing\.xosc"),
        Probe("openscenario", "toml_xosc_number", toml("xosc = 5\n"), r"xosc"),
        Probe("openscenario", "toml_ego_unknown",
              toml('xosc = "elk_overtaking_motorbike.xosc"\nego = "Nobody"\n'), r"Nobody"),
        Probe("openscenario", "toml_duration_nan",
              toml('xosc = "elk_overtaking_motorbike.xosc"\nduration_s = nan\n'),
              r"duration_s"),
        Probe("openscenario", "sweep_export_xosc_is_a_file",
              lambda t: ["sweep", write(t, "s.toml", 'name = "p"\nscenarios = '
                                                    '["head_on_aliasing"]\nduration_s = 0.2\n'),
                         "--out", t / "r", "--workers", "1", "--export-xosc", write(t, "f", "x")],
              r"--export-xosc '.*f': exists and is not a folder"),
    ]


@contextlib.contextmanager
def _denied(folder: Path, err: int):
    """Writes under `folder` fail with `err` once it exists (`tests.harness.probe_kit`)."""
    folder.mkdir(exist_ok=True)
    with failing_writes(err, folder):
        yield
