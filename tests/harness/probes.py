"""The bad-input probe set (issue 25): what a new user, a full disk or a supervisor does to every
surface of the harness, and what a clear answer looks like.

A `Probe` is one bad input on one surface: either a command line (``cli``: the probe's `call`
prepares files under a temporary folder and returns the argv, optionally with a context
manager that makes writers fail as a full disk or a read-only folder would) or a Python API
call (`call` runs it). Its `match` is what the one-line answer must say (the field, the value,
the limit, the file and what it is). `classify` runs a probe under a time limit and sorts the
outcome into the survey's classes:

clear
    CLI: the expected exit code (2 unless stated) and, for exit 2, exactly one stderr line that
    matches; API: a ValueError whose message matches.
unclear
    Refused, but the message does not say what `match` asks (e.g. an internal table index
    instead of the option name).
silent
    Accepted (exit 0/1 or a return value): garbage results, a wrong verdict, a vanished
    interferer.
crash
    A traceback: any other exception (MemoryError, OSError, TypeError, ...).
hang
    Still running after the time limit (a FIFO read, a runaway allocation).

`tests/harness/test_probes_*.py` assert that every probe of this project's areas is clear;
``python -m tests.harness.probe_survey`` counts the classes (the closing note of issue 25 has
the counts before and after). The probes use only public APIs and the CLI, so the same set runs
against an older checkout.
"""
from __future__ import annotations

import contextlib
import errno
import io
import os
import re
import signal
import socket
from pathlib import Path
from typing import Any, Callable, NamedTuple

import numpy as np

#: Classes of the survey, best first.
CLASSES = ("clear", "unclear", "silent", "crash", "hang")


class Probe(NamedTuple):
    """One bad input. `owner` is the helper whose area the surface is (the survey counts every
    probe; the tests of this module's owner assert only theirs)."""

    surface: str
    name: str
    call: Callable[[Path], Any]
    match: str
    cli: bool = True
    code: int = 2
    owner: str = "reliability"
    time_factor: float = 1.0  # the survey's time limit is multiplied by it (a subprocess run)

    @property
    def id(self) -> str:
        return f"{self.surface}/{self.name}"


class _Hang(BaseException):
    pass


@contextlib.contextmanager
def _time_limit(seconds: float):
    """SIGALRM-based limit in the main thread (a blocking open/read is interrupted too)."""
    def handler(signum, frame):
        raise _Hang()
    old = signal.signal(signal.SIGALRM, handler)
    signal.setitimer(signal.ITIMER_REAL, seconds)
    try:
        yield
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, old)


def classify(probe: Probe, tmp: Path, time_limit_s: float = 60.0) -> tuple[str, str]:
    """(class, detail) of one probe run in this process under `time_limit_s`."""
    from harness.cli import main
    err = io.StringIO()
    try:
        with _time_limit(time_limit_s):
            if probe.cli:
                prepared = probe.call(tmp)
                argv, ctx = (prepared if isinstance(prepared, tuple)
                             else (prepared, contextlib.nullcontext()))
                with ctx, contextlib.redirect_stderr(err), \
                        contextlib.redirect_stdout(io.StringIO()):
                    rc = main([str(a) for a in argv])
            else:
                probe.call(tmp)
                return "silent", "accepted"
    except _Hang:
        return "hang", f"still running after {time_limit_s:g} s"
    except ValueError as exc:
        if probe.cli:
            return "crash", f"{type(exc).__name__}: {exc}"
        msg = str(exc)
        return ("clear" if re.search(probe.match, msg) else "unclear"), msg
    except Exception as exc:  # noqa: BLE001 - a probe's outcome, classified
        return "crash", f"{type(exc).__name__}: {exc}"[:300]
    lines = [ln for ln in err.getvalue().splitlines() if ln.strip()]
    text = " | ".join(lines)
    if any(ln.startswith("Traceback") for ln in lines):
        return "crash", text[-300:]
    if rc != probe.code:
        return ("silent" if rc in (0, 1) else "crash" if rc != 2 else "unclear"), \
            f"exit {rc}: {text[-300:]}"
    if not re.search(probe.match, text):  # refused without saying it, or accepted unwarned
        return ("unclear" if rc == 2 else "silent"), f"exit {rc}: {text[-300:]}"
    errors = [ln for ln in lines if ": error: " in ln]
    if rc == 2 and len(errors) != 1:  # progress lines (a sweep's header) may precede it
        return "unclear", f"{len(errors)} error lines: {text[-300:]}"
    return "clear", text


# ----------------------------------------------------------------------------- file kinds
def _fifo(p: Path) -> Path:
    os.mkfifo(p)
    return p


def _loop(p: Path) -> Path:
    a = p.with_name(p.name + ".loop")
    os.symlink(a, p)
    os.symlink(p, a)
    return p


def _dir(p: Path) -> Path:
    p.mkdir()
    return p


def _socket(p: Path) -> Path:
    s = socket.socket(socket.AF_UNIX)
    s.bind(str(p))  # left bound: the file stays a socket for the probe's duration
    _SOCKETS.append(s)
    return p


_SOCKETS: list = []

#: Special files and what the one-line answer must call them.
SPECIAL = {
    "fifo": (_fifo, r"FIFO"),
    "dev_zero": (lambda p: (os.symlink("/dev/zero", p), p)[1], r"character device"),
    "symlink_loop": (_loop, r"symbolic link loop"),
    "directory": (_dir, r"directory"),
    "socket": (_socket, r"socket|not a regular file"),
}

OK_SWEEP = 'name = "p"\nscenarios = ["head_on_aliasing"]\nduration_s = 0.2\n'


def _special(kind: str, path: Path) -> Path:
    return SPECIAL[kind][0](path)


# ----------------------------------------------------------------------------- write faults
@contextlib.contextmanager
def failing_writes(err: int, under: Path, *, writers=("text", "bytes", "parquet", "savefig",
                                                      "open")):
    """Make writers fail with OSError(`err`) for paths under `under` (a full disk: ENOSPC, a
    read-only folder: EROFS): Path.write_text / write_bytes, DataFrame.to_parquet,
    Figure.savefig, builtin open for writing."""
    import builtins

    import pandas as pd
    from matplotlib.figure import Figure

    root = str(Path(under).resolve())

    def hit(path) -> bool:
        try:
            return str(Path(os.fspath(path)).resolve()).startswith(root)
        except TypeError:
            return False

    def boom(path):
        raise OSError(err, os.strerror(err), os.fspath(path))

    saved = (Path.write_text, Path.write_bytes, pd.DataFrame.to_parquet, Figure.savefig,
             builtins.open)

    def write_text(self, *a, **k):
        return boom(self) if hit(self) else saved[0](self, *a, **k)

    def write_bytes(self, *a, **k):
        return boom(self) if hit(self) else saved[1](self, *a, **k)

    def to_parquet(self, path=None, *a, **k):
        return boom(path) if path is not None and hit(path) else saved[2](self, path, *a, **k)

    def savefig(self, fname, *a, **k):
        return boom(fname) if hit(fname) else saved[3](self, fname, *a, **k)

    def open_(file, mode="r", *a, **k):
        if isinstance(file, (str, os.PathLike)) and any(c in mode for c in "wxa") and hit(file):
            boom(file)
        return saved[4](file, mode, *a, **k)

    patches = {"text": (Path, "write_text", write_text),
               "bytes": (Path, "write_bytes", write_bytes),
               "parquet": (pd.DataFrame, "to_parquet", to_parquet),
               "savefig": (Figure, "savefig", savefig), "open": (builtins, "open", open_)}
    olds = []
    try:
        for w in writers:
            obj, name, new = patches[w]
            olds.append((obj, name, getattr(obj, name)))
            setattr(obj, name, new)
        yield
    finally:
        for obj, name, old in reversed(olds):
            setattr(obj, name, old)


_FAKE_RESULTS: list[Path] = []


def fake_results(tmp: Path) -> Path:
    """A small results folder of the stand-in sweep (fast, no real cell), built once per
    process and copied under `tmp`."""
    import shutil
    import tempfile

    try:
        from harness.sweep.schedule import run_sweep
        from harness.sweep.spec import SweepSpec
    except ImportError:  # before the sweep module was split
        from harness.sweep import SweepSpec, run_sweep
    from tests.harness.fakes import FAKE
    if not _FAKE_RESULTS:
        src = Path(tempfile.mkdtemp(prefix="probe-results-")) / "results"
        run_sweep(SweepSpec(name="fake", scenarios=("fast",), seeds=(0,), duration_s=0.5),
                  src, components=FAKE, progress=False)
        _FAKE_RESULTS.append(src)
    out = tmp / "results"
    if not out.exists():
        shutil.copytree(_FAKE_RESULTS[0], out)
    return out


GATES = '[[gate]]\nname = "ghosts"\nmetric = "ghost_rate"\nmax = 1.0\n'


def _write(tmp: Path, name: str, text: str) -> Path:
    p = tmp / name
    p.write_text(text)
    return p


# ----------------------------------------------------------------------------- the probes
def _special_file_probes() -> list[Probe]:
    out = []
    for kind, (_, what) in SPECIAL.items():
        out += [
            Probe("special_files", f"sweep_file_{kind}",
                  lambda t, k=kind: ["sweep", _special(k, t / "s.toml"), "--out", t / "r",
                                     "--workers", "1"], what),
            Probe("special_files", f"thresholds_{kind}",
                  lambda t, k=kind: ["gate", fake_results(t), "--thresholds",
                                     _special(k, t / "g.toml"), "--markdown", t / "g.md"], what),
            Probe("special_files", f"case_file_{kind}",
                  lambda t, k=kind: ["show", _special(k, t / "c.toml"), "--out", t / "v"], what),
            Probe("special_files", f"capture_{kind}",
                  lambda t, k=kind: ["process", _special(k, t / "a.bin"), "--cfg",
                                     _profile(t), "--out", t / "o.csv"], what),
            Probe("special_files", f"profile_{kind}",
                  lambda t, k=kind: ["process", _capture(t), "--cfg", _special(k, t / "p.cfg"),
                                     "--out", t / "o.csv"], what),
            Probe("special_files", f"regroup_profile_{kind}",
                  lambda t, k=kind: ["process", _capture(t), "--cfg", _special(k, t / "p.cfg"),
                                     "--regroup-frames", "2", "--out", t / "o.csv"], what),
            Probe("special_files", f"advanced_capture_{kind}",
                  lambda t, k=kind: ["process", _special(k, t / "a.bin"), "--cfg",
                                     _advanced_profile(t), "--out", t / "o.csv"], what),
            Probe("special_files", f"security_{kind}",
                  lambda t, k=kind: ["sweep", _write(t, "s.toml", OK_SWEEP), "--out", t / "r",
                                     "--scheduler", "tls://127.0.0.1:1", "--security",
                                     _special(k, t / "sec.toml")], what),
            Probe("special_files", f"manifest_{kind}",
                  lambda t, k=kind: ["report", _results_with(t, "manifest.json", k),
                                     "--no-maps"], what),
        ]
    return out


def _results_with(tmp: Path, name: str, kind: str) -> Path:
    src = fake_results(tmp)
    d = tmp / "res2"
    d.mkdir()
    for f in src.glob("*.parquet"):
        (d / f.name).write_bytes(f.read_bytes())
    _special(kind, d / name)
    return d


def _profile(tmp: Path) -> Path:
    """A small TDMA profile (xWR16xx demo syntax) and its RadarConfig's capture."""
    p = tmp / "small.cfg"
    if not p.exists():
        repo = Path(__file__).resolve().parents[1] / "radarsim" / "profiles"
        p.write_text((repo / "xwr18_small.cfg").read_text())
    return p


def _advanced_profile(tmp: Path) -> Path:
    """A shipped test profile with advanced (sub-)frames."""
    p = tmp / "adv.cfg"
    p.write_text((Path(__file__).resolve().parents[1] / "radarsim" / "profiles"
                  / "xwr68_advanced_subframes.cfg").read_text())
    return p


def _ti_reader():
    """`parse_ti_cfg` (radarsim.ti since the TI bridge split, radarsim.ti_cfg before)."""
    try:
        from radarsim.ti import parse_ti_cfg
    except ImportError:
        from radarsim.ti_cfg import parse_ti_cfg
    return parse_ti_cfg


def _capture(tmp: Path) -> Path:
    """A one-frame capture of `_profile` written with the harness's own writer."""
    from radarsim.capture import write_capture
    parse_ti_cfg = _ti_reader()
    cap = tmp / "cap.bin"
    if not cap.exists():
        cfg = parse_ti_cfg(_profile(tmp)).radar
        shape = (cfg.n_chirps, cfg.n_rx, cfg.n_samples)
        frame = np.zeros(shape, dtype=np.complex64 if cfg.is_complex else np.int16)
        write_capture(cap, [frame], cfg=cfg)
    return cap


def _vary(counts: dict[str, int]) -> str:
    """A [vary] table with `counts[key]` distinct values per key."""
    lines = []
    for key, n in counts.items():
        lines.append(f'"{key}" = [' + ", ".join(f"{10 + i / n:.9f}" for i in range(n)) + "]")
    return "[vary]\n" + "\n".join(lines) + "\n"


def _sweep_probes() -> list[Probe]:
    head = 'name = "p"\nscenarios = ["head_on_aliasing"]\nduration_s = 0.2\n'
    big_vary = head + _vary({"processing.cfar_threshold_db": 100,
                             "radar.phase_noise_deg_rms": 100, "radar.tx_power_dbm": 100})
    huge_vary = head + _vary({"processing.cfar_threshold_db": 1000,
                              "radar.phase_noise_deg_rms": 1000, "radar.tx_power_dbm": 1000,
                              "radar.noise_figure_db": 1000})

    def sweep(text, *extra):
        return lambda t: ["sweep", _write(t, "s.toml", text), "--out", t / "r", "--workers",
                          "1", *extra]
    return [
        Probe("sweeps", "vary_product_1e6", sweep(big_vary),
              r"1000000 variants .* limit 10000 cells"),
        Probe("sweeps", "vary_product_1e12", sweep(huge_vary),
              r"1000000000000 variants .* limit 10000 cells"),
        Probe("sweeps", "baseline_not_run_file",
              sweep(head + 'schemes = ["ddma", "bpm"]\nbaseline_scheme = "tdma"\n'),
              r"baseline_scheme='tdma' is not among the schemes run \['ddma', 'bpm'\]"),
        Probe("sweeps", "baseline_not_run_cli",
              sweep(head, "--schemes", "ddma", "bpm", "--baseline-scheme", "tdma"),
              r"--baseline-scheme tdma is not among the schemes run \['ddma', 'bpm'\]"),
        Probe("sweeps", "run_baseline_not_run",
              lambda t: ["run", "head_on_aliasing", "--duration-s", "0.2", "--schemes", "ddma",
                         "bpm", "--baseline-scheme", "tdma"],
              r"--baseline-scheme tdma is not among the schemes run"),
        Probe("sweeps", "unknown_scheme",
              lambda t: ["run", "head_on_aliasing", "--schemes", "ddma", "nope"],
              r"unknown scheme\(s\) \['nope'\]"),
        Probe("sweeps", "seed_true", sweep(head + "seeds = [true]\n"), r"seeds=\[True\]"),
        Probe("sweeps", "radar_seed_true_in_table",
              sweep(head + '[base.radar]\nshifter_phase_error_deg = {distribution = "inl_dnl", '
                           'rms = 2.0, seed = true}\n'), r"seed=True"),
        Probe("sweeps", "rms_true",
              sweep(head + '[base.radar]\nshifter_phase_error_deg = {distribution = "inl_dnl", '
                           'rms = true, seed = 0}\n'), r"rms=True"),
        Probe("sweeps", "calibration_on_noise",
              sweep(head + '[base.radar]\nphase_quantization = "round"\n'
                           'shifter_calibration_deg = {seed = 0, range_m = 1e5}\n'),
              r"calibration.*SNR.*-?\d+(\.\d)? dB.*below"),
        Probe("sweeps", "calibration_n_repeats_1e8",
              sweep(head + '[base.radar]\nphase_quantization = "round"\n'
                           'shifter_calibration_deg = {seed = 0, n_repeats = 100000000}\n'),
              r"n_repeats=100000000 .*4096"),
        Probe("sweeps", "radar_tx_channels_float",
              sweep(head + "[base.radar]\ntx_channels = [1.7, 3.9, 2.0, 4.0]\n"),
              r"tx_channels=.*1\.7.*integer"),
        Probe("sweeps", "radar_tx_order_string",
              sweep(head + '[base.radar]\ntx_order = "1342"\n'),
              r"tx_order='1342'.*(tuple|sequence|list)"),
        Probe("sweeps", "duration_nan", sweep(head.replace("0.2", "nan")), r"duration_s=nan"),
        Probe("sweeps", "out_is_a_file",
              lambda t: ["sweep", _write(t, "s.toml", head), "--out",
                         _write(t, "f", "x"), "--workers", "1"], r"not a directory"),
        Probe("sweeps", "tls_garbage_certificate",
              lambda t: ["sweep", _write(t, "s.toml", head), "--out", t / "r", "--scheduler",
                         "tls://127.0.0.1:9", "--scheduler-timeout-s", "2", "--security",
                         _tls_files(t, garbage=True)],
              r"ca_file = 'ca\.pem' is not a PEM CA certificate"),
        Probe("sweeps", "tls_key_mismatch_missing",
              lambda t: ["sweep", _write(t, "s.toml", head), "--out", t / "r", "--scheduler",
                         "tls://127.0.0.1:9", "--security", _tls_files(t, garbage=False,
                                                                        drop="key")],
              r"missing key\(s\) \['key'\]"),
    ]


def _tls_files(tmp: Path, garbage: bool, drop: str | None = None) -> Path:
    for name in ("ca.pem", "cert.pem", "key.pem"):
        (tmp / name).write_text("this is not a certificate\n" if garbage else "")
    keys = {"ca_file": "ca.pem", "cert": "cert.pem", "key": "key.pem"}
    if drop:
        del keys[drop]
    return _write(tmp, "sec.toml", "".join(f'{k} = "{v}"\n' for k, v in keys.items()))


def _shifter_probes() -> list[Probe]:
    def sh(*a):
        return lambda t: ["shifter", *a]
    return [
        Probe("shifter", "n_chirps_1e12", sh("--n-chirps", "1000000000000"),
              r"--n-chirps.*1000000000000.*\.\.16384"),
        Probe("shifter", "n_chirps_float", sh("--n-chirps", "1e12"), r"--n-chirps"),
        Probe("shifter", "error_rms_huge", sh("--error-deg-rms", "1e9"),
              r"--error-deg-rms.*1e\+?0?9.*outside"),
        Probe("shifter", "gain_rms_negative", sh("--gain-error-db-rms", "-1"),
              r"--gain-error-db-rms.*-1.*outside"),
        Probe("shifter", "skew_huge", sh("--quadrature-skew-deg", "1e9"),
              r"--quadrature-skew-deg.*outside"),
        Probe("shifter", "step_nan", sh("--step-deg", "nan"), r"--step-deg.*nan"),
        Probe("shifter", "step_not_divisor", sh("--step-deg", "7"), r"--step-deg.*7"),
        Probe("shifter", "tx_7", sh("--tx", "7"), r"--tx.*7.*1\.\.4"),
        Probe("shifter", "range_negative", sh("--range-m", "-1"), r"--range-m.*-1.*outside"),
        Probe("shifter", "range_far_noise", sh("--range-m", "200", "--n-chirps", "64"),
              r"calibration.*SNR.*below"),
        Probe("shifter", "seed_negative", sh("--seed", "-1"), r"--seed.*-1"),
        Probe("shifter", "plot_read_only",
              lambda t: (["shifter", "--n-chirps", "64", "--plot", t / "ro" / "x.png"],
                         _readonly_dir(t / "ro")), r"--plot.*read-only"),
        Probe("shifter", "plot_is_dir",
              lambda t: ["shifter", "--n-chirps", "64", "--plot", _dir(t / "d")],
              r"--plot.*directory"),
        Probe("shifter", "calibrate_n_repeats_1e8", cli=False,
              call=lambda t: _calibrate(n_repeats=100_000_000), match=r"n_repeats=100000000"),
        Probe("shifter", "calibrate_n_repeats_true", cli=False,
              call=lambda t: _calibrate(n_repeats=True), match=r"n_repeats=True"),
        Probe("shifter", "calibrate_far_below_snr", cli=False,
              call=lambda t: _calibrate(range_m=1e5),
              match=r"SNR -\d+\.\d dB .*below the \d+\.\d dB"),
        Probe("shifter", "config_calibration_on_noise", cli=False,
              call=lambda t: _calibration_request({"seed": 0, "range_m": 1e5}),
              match=r"SNR.*below"),
        Probe("shifter", "table_rms_true", cli=False,
              call=lambda t: _radar(shifter_phase_error_deg={"distribution": "inl_dnl",
                                                             "rms": True, "seed": 0}),
              match=r"rms=True"),
        Probe("shifter", "table_seed_true", cli=False,
              call=lambda t: _radar(shifter_phase_error_deg={"distribution": "inl_dnl",
                                                             "rms": 2.0, "seed": True}),
              match=r"seed=True"),
        Probe("shifter", "calibration_seed_true", cli=False,
              call=lambda t: _calibration_request({"seed": True}),
              match=r"seed=True"),
        Probe("shifter", "calibration_request_in_config", cli=False,
              call=lambda t: _radar(phase_quantization="round",
                                    shifter_calibration_deg={"seed": 0}),
              match=r"is a calibration request, not a measured table"),
    ]


@contextlib.contextmanager
def _readonly(root: Path):
    with failing_writes(errno.EROFS, root):
        yield


def _readonly_dir(d: Path):
    d.mkdir(exist_ok=True)
    return _readonly(d)


def _radar(**kw):
    import radarsim
    return radarsim.RadarConfig.from_fields(**kw)


def _calibration_request(request):
    """A sweep's calibration request, resolved as the harness resolves it (a config itself
    never measures)."""
    import radarsim
    cfg = radarsim.presets.r79_ddma(phase_quantization="round")
    return radarsim.resolve_calibration(cfg, request)


def _calibrate(**kw):
    import radarsim
    cfg = radarsim.presets.r79_ddma(phase_quantization="round")
    return radarsim.calibrate_shifters(cfg, rng=np.random.default_rng(0), **kw)


def _config_probes() -> list[Probe]:
    def cfg(name, match, **kw):
        return Probe("chips_boards", name, cli=False, call=lambda t: _radar(**kw), match=match)
    return [
        cfg("tx_channels_float", r"tx_channels=\(1\.7, 3\.9\).*integer", n_tx=2,
            tx_channels=(1.7, 3.9)),
        cfg("tx_order_string", r"tx_order='1342'", tx_order="1342"),
        cfg("rx_channels_float", r"rx_channels=.*2\.5.*integer", rx_channels=(1, 2.5, 3, 4)),
        cfg("tx_order_float", r"tx_order=.*1\.5", tx_order=(1.5, 3, 4, 2)),
        cfg("unknown_chip", r"chip='AWR9999'.*not one of|unknown.*AWR9999", chip="AWR9999"),
        cfg("board_of_other_chip", r"board=.*carries", chip="AWR1843", board="AWR2944EVM"),
        cfg("n_tx_over_chip", r"n_tx=5", n_tx=5),
        cfg("phase_noise_true", r"phase_noise_deg_rms=True", phase_noise_deg_rms=True),
        cfg("adc_mode_unknown", r"adc_mode='complex3x'", adc_mode="complex3x"),
        cfg("unknown_board", r"board='NOPE'", board="NOPE"),
        cfg("n_chirps_huge", r"n_chirps=", n_chirps=10**9),
        cfg("mimo_unknown", r"mimo='fdma'", mimo="fdma"),
    ]


def _adc_probes() -> list[Probe]:
    def frame(kind: str):
        import pipeline
        cfg = _ti_reader()(Path(__file__).resolve().parents[1] / "radarsim" / "profiles"
                           / "xwr16_lab.cfg").radar
        assert cfg.is_complex
        adc = np.zeros((cfg.n_chirps, cfg.n_rx, cfg.n_samples), np.complex64)
        if kind == "nan":
            adc[:] = np.nan
        elif kind == "one_inf":
            adc[3, 1, 7] = np.inf
        elif kind == "over_full_scale":
            adc[:, :, 5] = 1e9 + 1e9j
            pc = pipeline.process_frame(cfg, adc)
            sat = pc.attrs.get("saturation", {})
            if sat.get("saturated") and (len(pc) == 0 or pc["saturated"].all()):
                raise ValueError("saturated: flagged (the clear answer)")
            return pc
        return pipeline.process_frame(cfg, adc)

    def real(kind):
        import pipeline
        import radarsim
        cfg = radarsim.presets.r79_ddma()
        adc = np.zeros((cfg.n_chirps, cfg.n_rx, cfg.n_samples), np.float32)
        adc[0, 0, 0] = np.nan
        return pipeline.process_frame(cfg, adc if kind == "float" else adc.astype(np.int32))

    return [
        Probe("complex_adc", "complex_nan", cli=False, call=lambda t: frame("nan"),
              match=r"frame .*non-finite.*\b\d+\b"),
        Probe("complex_adc", "complex_one_inf", cli=False, call=lambda t: frame("one_inf"),
              match=r"1 non-finite sample.*chirp 3, Rx 1, sample 7"),
        Probe("complex_adc", "complex_beyond_full_scale", cli=False,
              call=lambda t: frame("over_full_scale"), match=r"saturated: flagged"),
        Probe("complex_adc", "real_float_frame", cli=False, call=lambda t: real("float"),
              match=r"int16"),
        Probe("complex_adc", "real_int32_frame", cli=False, call=lambda t: real("int32"),
              match=r"int16"),
    ]


def _interference_probes() -> list[Probe]:
    base = dict(position_m=[[30.0, 0.0, 0.0]], radial_velocity_mps=[0.0], tx_gain_dbi=[10.0],
                start_freq_hz=[77e9], slope_hz_per_s=[20e12], chirp_period_s=[40e-6],
                ramp_time_s=[30e-6], chirp_offset_s=[1e-6], tx_power_dbm=[12.0])

    def itf(**kw):
        import radarsim
        from radarsim.interference import Interferers
        i = Interferers(**{**base, **kw})
        cfg = radarsim.presets.r79_ddma()
        return radarsim.simulate_frame(cfg, radarsim.Scatterers(
            position_m=np.zeros((0, 3)), velocity_mps=np.zeros((0, 3)), rcs_m2=np.zeros(0)),
            rng=np.random.default_rng(0), interferers=i)

    def eq(**kw):
        from scenarios.equipment import RadarEquipment
        return RadarEquipment(**kw)

    case = (Path(__file__).resolve().parents[2] / "scenarios" / "cases"
            / "interference_same_slope_ghosts.toml").read_text()
    assert "chirp_offset_s = 0.3e-6\n" in case and "tx_power_dbm = 12.0\n" in case

    def case_probe(name, old, new, match):
        return Probe("interference", name,
                     lambda t: ["show", _write(t, "c.toml", case.replace(old, new)), "--out",
                                t / "v"], match)
    out = [
        Probe("interference", "period_1e-15", cli=False,
              call=lambda t: itf(chirp_period_s=[1e-15], ramp_time_s=[1e-16]),
              match=r"chirp_period_s=.*1e-15.*\[1e-06, 0\.01\]"),
        Probe("interference", "offset_1e300", cli=False, call=lambda t: itf(chirp_offset_s=[1e300]),
              match=r"chirp_offset_s=.*1e\+300.*\[-1, 1\] s"),
        Probe("interference", "offset_nan", cli=False,
              call=lambda t: itf(chirp_offset_s=[float("nan")]), match=r"chirp_offset_s.*finite"),
        Probe("interference", "power_-1e300", cli=False,
              call=lambda t: itf(tx_power_dbm=[-1e300]), match=r"tx_power_dbm=.*-1e\+300"),
        Probe("interference", "power_1e3", cli=False, call=lambda t: itf(tx_power_dbm=[1e3]),
              match=r"tx_power_dbm=.*1000"),
        Probe("interference", "gain_1e300", cli=False, call=lambda t: itf(tx_gain_dbi=[1e300]),
              match=r"tx_gain_dbi="),
        Probe("interference", "slope_1e300", cli=False,
              call=lambda t: itf(slope_hz_per_s=[1e300]), match=r"slope_hz_per_s="),
        Probe("interference", "start_freq_1e30", cli=False,
              call=lambda t: itf(start_freq_hz=[1e30]), match=r"start_freq_hz="),
        Probe("interference", "speed_1e300", cli=False,
              call=lambda t: itf(radial_velocity_mps=[1e300]), match=r"radial_velocity_mps="),
        Probe("interference", "range_1e300", cli=False,
              call=lambda t: itf(position_m=[[1e300, 0.0, 0.0]]), match=r"position_m|range"),
        Probe("interference", "equipment_offset_1e300", cli=False,
              call=lambda t: eq(chirp_offset_s=1e300), match=r"chirp_offset_s=1e\+300"),
        Probe("interference", "equipment_offset_nan", cli=False,
              call=lambda t: eq(chirp_offset_s=float("nan")), match=r"chirp_offset_s=nan"),
        Probe("interference", "equipment_power_-1e300", cli=False,
              call=lambda t: eq(tx_power_dbm=-1e300), match=r"tx_power_dbm=-1e\+300"),
        Probe("interference", "equipment_gain_-1e300", cli=False,
              call=lambda t: eq(antenna_gain_dbi=-1e300), match=r"antenna_gain_dbi=-1e\+300"),
        Probe("interference", "equipment_phase_1e300", cli=False,
              call=lambda t: eq(phase_rad=1e300), match=r"phase_rad=1e\+300"),
        Probe("interference", "equipment_exponent_1e300", cli=False,
              call=lambda t: eq(pattern_exponent_az=1e300), match=r"pattern_exponent_az"),
        case_probe("case_offset_1e300", "chirp_offset_s = 0.3e-6", "chirp_offset_s = 1e300",
                   r"radars\[0\].*chirp_offset_s=1e\+300"),
        case_probe("case_offset_nan", "chirp_offset_s = 0.3e-6", "chirp_offset_s = nan",
                   r"radars\[0\].*chirp_offset_s"),
        case_probe("case_power_-1e300", "tx_power_dbm = 12.0", "tx_power_dbm = -1e300",
                   r"radars\[0\].*tx_power_dbm=-1e\+300"),
        case_probe("case_offset_string", "chirp_offset_s = 0.3e-6", 'chirp_offset_s = "1 us"',
                   r"radars\[0\]\.chirp_offset_s"),
    ]
    return out


def _write_probes() -> list[Probe]:
    def gate(err):
        def call(t):
            res = fake_results(t)
            return (["gate", res, "--thresholds", _write(t, "g.toml", GATES)],
                    failing_writes(err, res))
        return call

    def report(err):
        def call(t):
            res = fake_results(t)
            return (["report", res, "--no-maps"], failing_writes(err, res))
        return call

    def sweep_disk(t):
        out = t / "r"
        return (["sweep", _write(t, "s.toml", OK_SWEEP), "--out", out, "--workers", "1"],
                _after_probe(failing_writes(errno.ENOSPC, out, writers=("parquet",))))

    def show(t):
        return (["show", "head_on_aliasing", "--out", t / "v"],
                failing_writes(errno.EROFS, t / "v", writers=("savefig", "open")))

    def simulate_disk(t):
        return (["simulate", "head_on_aliasing", "--cfg", _profile(t), "--out", t / "o" / "c.bin",
                 "--frames", "1"], _after_probe(failing_writes(errno.ENOSPC, t / "o",
                                                               writers=("open",)),
                                                mkdir=t / "o"))

    def junit(t):
        res = fake_results(t)
        return (["gate", res, "--thresholds", _write(t, "g.toml", GATES), "--junit",
                 t / "j" / "g.xml", "--markdown", t / "g.md"],
                _after_probe(failing_writes(errno.ENOSPC, t / "j"), mkdir=t / "j"))
    return [
        Probe("writes", "gate_read_only_results", gate(errno.EROFS),
              r"cannot write .*gates\.md.*read-only.*verdict \(pass\) stands", code=0),
        Probe("writes", "gate_full_disk", gate(errno.ENOSPC),
              r"cannot write .*gates\.md.*no space.*verdict \(pass\) stands", code=0),
        Probe("writes", "gate_junit_full_disk", junit,
              r"g\.xml.*no space.*verdict \(pass\) stands", code=0),
        Probe("writes", "report_full_disk", report(errno.ENOSPC),
              r"report\.html.*no space left"),
        Probe("writes", "report_read_only", report(errno.EROFS), r"report\.html.*read-only"),
        Probe("writes", "sweep_full_disk", sweep_disk,
              r"cannot write .*(no space left|No space left).*cells written so far are kept"),
        Probe("writes", "show_read_only", show, r"v.*read-only"),
        Probe("writes", "simulate_full_disk", simulate_disk, r"c\.bin.*(no space|No space)"),
        Probe("writes", "rcs_plot_full_disk",
              lambda t: (["rcs", "car", "--plot", "--out", t / "o" / "x.png", "--draws", "2"],
                         _after_probe(failing_writes(errno.ENOSPC, t / "o",
                                                     writers=("savefig",)), mkdir=t / "o")),
              r"x\.png.*(no space|No space)"),
        Probe("writes", "run_out_read_only",
              lambda t: (["run", "head_on_aliasing", "--duration-s", "0.2", "--out", t / "ro"],
                         _readonly_dir(t / "ro")), r"(?i)ro.*read-only"),
    ]


@contextlib.contextmanager
def _after_probe(ctx, mkdir: Path | None = None):
    """`ctx` entered after the command's own writability probe would pass: the folder exists,
    the fault hits the real writes (a disk that fills during the run)."""
    if mkdir is not None:
        mkdir.mkdir(parents=True, exist_ok=True)
    import core.checks  # noqa: F401  (imports before the fault)
    try:
        from core import fileio
        probe_dir = fileio.check_output_dir
    except ImportError:
        fileio = None
    if fileio is not None:
        fileio.check_output_dir = lambda folder, *a, **k: Path(folder)
    try:
        with ctx:
            yield
    finally:
        if fileio is not None:
            fileio.check_output_dir = probe_dir


def _consistency_probes() -> list[Probe]:
    def damaged(text):
        def call(t):
            res = fake_results(t)
            d = t / "dm"
            d.mkdir()
            for f in res.glob("*.parquet"):
                (d / f.name).write_bytes(f.read_bytes())
            (d / "manifest.json").write_text(text)
            return ["report", d, "--no-maps"]
        return call

    def old_version(cmd):
        def call(t):
            import json
            res = fake_results(t)
            d = t / "old"
            d.mkdir()
            for f in res.glob("*.parquet"):
                (d / f.name).write_bytes(f.read_bytes())
            man = json.loads((res / "manifest.json").read_text())
            man["code_version"] = "0123456789abcdef"
            (d / "manifest.json").write_text(json.dumps(man))
            return [cmd, d] + (["--no-maps"] if cmd == "report" else
                               ["--thresholds", _write(t, "g.toml", GATES)])
        return call
    return [
        Probe("consistency", "report_damaged_manifest", damaged('{"run_id": x}'),
              r"manifest\.json: damaged manifest"),
        Probe("consistency", "report_manifest_list", damaged("[1, 2]"),
              r"manifest\.json: damaged manifest"),
        Probe("consistency", "gate_damaged_manifest",
              lambda t: ["gate", damaged("{")(t)[1], "--thresholds", _write(t, "g.toml", GATES)],
              r"manifest\.json: damaged manifest"),
        Probe("consistency", "gate_old_code_version", old_version("gate"),
              r"computed by code version 0123456789abcdef .*not today's", code=0),
        Probe("consistency", "report_old_code_version", old_version("report"),
              r"computed by code version 0123456789abcdef .*not today's", code=0),
    ]


def _profile_probes() -> list[Probe]:
    """TI-profile probes (hw-a's area): surveyed, asserted by hw-a's tests."""
    def prof(text, name="p.cfg"):
        """`text`: bytes, str, or a callable giving either (built when the probe runs: the
        50 MB one cost 0.45 s CPU at every `probes_of` call, nine per collecting process)."""
        def call(t):
            p = t / name
            body = text() if callable(text) else text
            p.write_bytes(body if isinstance(body, bytes) else body.encode())
            return ["process", _capture(t), "--cfg", p, "--out", t / "o.csv"]
        return call

    def dup(cmd):
        def call(t):
            lines = _profile(t).read_text().splitlines()
            extra = [ln for ln in lines if ln.startswith(cmd)]
            p = t / "dup.cfg"
            p.write_text("\n".join(lines[:-1] + extra + lines[-1:]) + "\n")
            return ["process", _capture(t), "--cfg", p, "--out", t / "o.csv"]
        return call
    return [
        Probe("ti_profiles", "non_utf8", prof(b"sensorStop\n\xff\xfe profileCfg\n"),
              r"UTF-8|text", owner="hw-a"),
        Probe("ti_profiles", "dup_channelCfg", dup("channelCfg"), r"channelCfg", owner="hw-a"),
        Probe("ti_profiles", "dup_frameCfg", dup("frameCfg"), r"frameCfg", owner="hw-a"),
        Probe("ti_profiles", "50MB_unknown",
              prof(lambda: "".join(f"fooCmd{i} 1 2 3\n" for i in range(2_500_000))),
              r"unknown|limit|large", owner="hw-a"),
    ]


def _signal_probes() -> list[Probe]:
    def sigterm(t):
        """SIGTERM to the main pid of `sweep --workers 2`: no process may remain."""
        import subprocess
        import sys
        import time

        import psutil
        f = _write(t, "s.toml", 'name = "sig"\nscenarios = ["dense_highway", '
                                '"head_on_aliasing"]\nseeds = [0, 1]\nduration_s = 2.0\n')
        p = subprocess.Popen([sys.executable, "-m", "harness.cli", "sweep", str(f), "--out",
                              str(t / "r"), "--workers", "2", "--no-progress"],
                             stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        kids: list = []
        t_end = time.monotonic() + 60
        while len(kids) < 2 and time.monotonic() < t_end:
            kids = psutil.Process(p.pid).children(recursive=True)
            time.sleep(0.1)
        time.sleep(1.0)
        p.terminate()
        p.wait(timeout=30)  # not communicate(): orphaned workers would hold its pipes
        _, alive = psutil.wait_procs(kids, timeout=10)
        for k in alive:
            k.kill()
        if alive:  # left running for good: counted as a hang
            raise _Hang()
        raise ValueError(f"exit {p.returncode}, nothing left behind")
    return [Probe("signals", "sigterm_pool_sweep", cli=False, call=sigterm,
                  match=r"exit 143, nothing left behind", time_factor=4.0)]


def _scheme_probes() -> list[Probe]:
    """Schemes, scatterers and frames: the first round's surfaces, kept in the set."""
    def api(name, fn, match):
        return Probe("schemes", name, cli=False, call=fn, match=match)

    def scatterers(**kw):
        import radarsim
        base = dict(position_m=[[10.0, 0.0, 0.0]], velocity_mps=[[0.0, 0.0, 0.0]],
                    rcs_m2=[1.0])
        return radarsim.Scatterers(**{**base, **kw})

    def frame(adc):
        import pipeline
        import radarsim
        return pipeline.process_frame(radarsim.presets.r79_ddma(), adc)

    head = 'name = "p"\nscenarios = ["head_on_aliasing"]\nduration_s = 0.2\n'

    def sweep_profile(kind):
        def call(t):
            prof = _special(kind, t / "p.cfg")
            return ["sweep", _write(t, "s.toml", head + f'[vary]\n"radar.profile" = '
                                                        f'["{prof}"]\n'),
                    "--out", t / "r", "--workers", "1"]
        return call
    return [
        api("r79_unknown_scheme", lambda t: __import__("radarsim").presets.r79("nope"),
            r"mimo='nope' is not one of"),
        api("scatterer_nan", lambda t: scatterers(position_m=[[float("nan"), 0, 0]]),
            r"position_m.*non-finite"),
        api("frame_wrong_shape", lambda t: frame(np.zeros((2, 4, 384), np.int16)),
            r"adc shape \(2, 4, 384\) does not match"),
        api("frame_list", lambda t: frame([[0]]), r"numpy\.ndarray"),
        Probe("schemes", "frame_cli_unknown_mimo", lambda t: ["frame", "--mimo", "fdma"],
              r"invalid choice: 'fdma'"),
        Probe("schemes", "sweep_profile_fifo", sweep_profile("fifo"), r"radar\.profile"),
        Probe("schemes", "sweep_profile_directory", sweep_profile("directory"),
              r"radar\.profile"),
    ]


def all_probes() -> list[Probe]:
    return (_special_file_probes() + _sweep_probes() + _shifter_probes() + _config_probes()
            + _adc_probes() + _interference_probes() + _write_probes()
            + _consistency_probes() + _scheme_probes() + _profile_probes()
            + _signal_probes())


def probes_of(surface: str, owner: str = "reliability") -> list[Probe]:
    return [p for p in all_probes() if p.surface == surface and p.owner == owner]

