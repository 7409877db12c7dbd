"""The bad-input probe kit: the `Probe` record, `classify`, and the files, folders and faults
the probes prepare (`tests.harness.probes` gathers the probe set from `probes_inputs` and
`probes_outputs`).

The bad-input probe set: what a new user, a full disk or a supervisor does to every
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
``python -m tests.harness.probe_survey`` counts the classes (the closing note that added the
probe set has the counts before and after). The probes use only public APIs and the CLI, so
the same set runs against an older checkout.
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


class Hang(BaseException):
    pass


@contextlib.contextmanager
def _time_limit(seconds: float):
    """SIGALRM-based limit in the main thread (a blocking open/read is interrupted too)."""
    def handler(signum, frame):
        raise Hang()
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
    except Hang:
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


def directory(p: Path) -> Path:
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
    "directory": (directory, r"directory"),
    "socket": (_socket, r"socket|not a regular file"),
}

OK_SWEEP = 'name = "p"\nscenarios = ["head_on_aliasing"]\nduration_s = 0.2\n'


def special_file(kind: str, path: Path) -> Path:
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


def write_file(tmp: Path, name: str, text: str) -> Path:
    p = tmp / name
    p.write_text(text)
    return p


# ----------------------------------------------------------------------------- the probes
def special_file_probes() -> list[Probe]:
    out = []
    for kind, (_, what) in SPECIAL.items():
        out += [
            Probe("special_files", f"sweep_file_{kind}",
                  lambda t, k=kind: ["sweep", special_file(k, t / "s.toml"), "--out", t / "r",
                                     "--workers", "1"], what),
            Probe("special_files", f"thresholds_{kind}",
                  lambda t, k=kind: ["gate", fake_results(t), "--thresholds",
                                     special_file(k, t / "g.toml"), "--markdown", t / "g.md"],
                  what),
            Probe("special_files", f"case_file_{kind}",
                  lambda t, k=kind: ["show", special_file(k, t / "c.toml"), "--out", t / "v"],
                  what),
            Probe("special_files", f"capture_{kind}",
                  lambda t, k=kind: ["process", special_file(k, t / "a.bin"), "--cfg",
                                     profile_file(t), "--out", t / "o.csv"], what),
            Probe("special_files", f"profile_{kind}",
                  lambda t, k=kind: ["process", capture_file(t), "--cfg",
                                     special_file(k, t / "p.cfg"),
                                     "--out", t / "o.csv"], what),
            Probe("special_files", f"regroup_profile_{kind}",
                  lambda t, k=kind: ["process", capture_file(t), "--cfg",
                                     special_file(k, t / "p.cfg"),
                                     "--regroup-frames", "2", "--out", t / "o.csv"], what),
            Probe("special_files", f"advanced_capture_{kind}",
                  lambda t, k=kind: ["process", special_file(k, t / "a.bin"), "--cfg",
                                     advanced_profile_file(t), "--out", t / "o.csv"], what),
            Probe("special_files", f"security_{kind}",
                  lambda t, k=kind: ["sweep", write_file(t, "s.toml", OK_SWEEP), "--out", t / "r",
                                     "--scheduler", "tls://127.0.0.1:1", "--security",
                                     special_file(k, t / "sec.toml")], what),
            Probe("special_files", f"manifest_{kind}",
                  lambda t, k=kind: ["report", results_with(t, "manifest.json", k),
                                     "--no-maps"], what),
        ]
    return out


def results_with(tmp: Path, name: str, kind: str) -> Path:
    src = fake_results(tmp)
    d = tmp / "res2"
    d.mkdir()
    for f in src.glob("*.parquet"):
        (d / f.name).write_bytes(f.read_bytes())
    special_file(kind, d / name)
    return d


def profile_file(tmp: Path) -> Path:
    """A small TDMA profile (xWR16xx demo syntax) and its RadarConfig's capture."""
    p = tmp / "small.cfg"
    if not p.exists():
        repo = Path(__file__).resolve().parents[1] / "radarsim" / "profiles"
        p.write_text((repo / "xwr18_small.cfg").read_text())
    return p


def advanced_profile_file(tmp: Path) -> Path:
    """A shipped test profile with advanced (sub-)frames."""
    p = tmp / "adv.cfg"
    p.write_text((Path(__file__).resolve().parents[1] / "radarsim" / "profiles"
                  / "xwr68_advanced_subframes.cfg").read_text())
    return p


def ti_reader():
    """`parse_ti_cfg` (radarsim.ti since the TI bridge split, radarsim.ti_cfg before)."""
    try:
        from radarsim.ti import parse_ti_cfg
    except ImportError:
        from radarsim.ti_cfg import parse_ti_cfg
    return parse_ti_cfg


def capture_file(tmp: Path) -> Path:
    """A one-frame capture of `_profile` written with the harness's own writer."""
    from radarsim.capture import write_capture
    parse_ti_cfg = ti_reader()
    cap = tmp / "cap.bin"
    if not cap.exists():
        cfg = parse_ti_cfg(profile_file(tmp)).radar
        shape = (cfg.n_chirps, cfg.n_rx, cfg.n_samples)
        frame = np.zeros(shape, dtype=np.complex64 if cfg.is_complex else np.int16)
        write_capture(cap, [frame], cfg=cfg)
    return cap


def vary(counts: dict[str, int]) -> str:
    """A [vary] table with `counts[key]` distinct values per key."""
    lines = []
    for key, n in counts.items():
        lines.append(f'"{key}" = [' + ", ".join(f"{10 + i / n:.9f}" for i in range(n)) + "]")
    return "[vary]\n" + "\n".join(lines) + "\n"


@contextlib.contextmanager
def readonly(root: Path):
    with failing_writes(errno.EROFS, root):
        yield


def readonly_dir(d: Path):
    d.mkdir(exist_ok=True)
    return readonly(d)


