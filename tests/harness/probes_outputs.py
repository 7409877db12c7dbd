"""The probe set, outputs and runs: full disks and read-only folders under every writer,
results folders out of step with the code, TI profiles, stop signals and schemes
(`tests.harness.probe_kit`)."""
from __future__ import annotations

import contextlib
import errno
from pathlib import Path

import numpy as np

from tests.harness.probe_kit import (
    GATES,
    OK_SWEEP,
    Hang,
    Probe,
    capture_file,
    failing_writes,
    fake_results,
    profile_file,
    readonly_dir,
    special_file,
    write_file,
)


def write_probes() -> list[Probe]:
    def gate(err):
        def call(t):
            res = fake_results(t)
            return (["gate", res, "--thresholds", write_file(t, "g.toml", GATES)],
                    failing_writes(err, res))
        return call

    def report(err):
        def call(t):
            res = fake_results(t)
            return (["report", res, "--no-maps"], failing_writes(err, res))
        return call

    def sweep_disk(t):
        out = t / "r"
        return (["sweep", write_file(t, "s.toml", OK_SWEEP), "--out", out, "--workers", "1"],
                _after_probe(failing_writes(errno.ENOSPC, out, writers=("parquet",))))

    def show(t):
        return (["show", "head_on_aliasing", "--out", t / "v"],
                failing_writes(errno.EROFS, t / "v", writers=("savefig", "open")))

    def simulate_disk(t):
        argv = ["simulate", "head_on_aliasing", "--cfg", profile_file(t),
                "--out", t / "o" / "c.bin", "--frames", "1"]
        faults = failing_writes(errno.ENOSPC, t / "o", writers=("open",))
        return argv, _after_probe(faults, mkdir=t / "o")

    def junit(t):
        res = fake_results(t)
        return (["gate", res, "--thresholds", write_file(t, "g.toml", GATES), "--junit",
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
                         readonly_dir(t / "ro")), r"(?i)ro.*read-only"),
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


def consistency_probes() -> list[Probe]:
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
                               ["--thresholds", write_file(t, "g.toml", GATES)])
        return call
    return [
        Probe("consistency", "report_damaged_manifest", damaged('{"run_id": x}'),
              r"manifest\.json: damaged manifest"),
        Probe("consistency", "report_manifest_list", damaged("[1, 2]"),
              r"manifest\.json: damaged manifest"),
        Probe("consistency", "gate_damaged_manifest",
              lambda t: ["gate", damaged("{")(t)[1], "--thresholds",
                         write_file(t, "g.toml", GATES)],
              r"manifest\.json: damaged manifest"),
        Probe("consistency", "gate_old_code_version", old_version("gate"),
              r"computed by code version 0123456789abcdef .*not today's", code=0),
        Probe("consistency", "report_old_code_version", old_version("report"),
              r"computed by code version 0123456789abcdef .*not today's", code=0),
    ]


def profile_probes() -> list[Probe]:
    """TI-profile probes (hw-a's area): surveyed, asserted by hw-a's tests."""
    def prof(text, name="p.cfg"):
        """`text`: bytes, str, or a callable giving either (built when the probe runs: the
        50 MB one cost 0.45 s CPU at every `probes_of` call, nine per collecting process)."""
        def call(t):
            p = t / name
            body = text() if callable(text) else text
            p.write_bytes(body if isinstance(body, bytes) else body.encode())
            return ["process", capture_file(t), "--cfg", p, "--out", t / "o.csv"]
        return call

    def dup(cmd):
        def call(t):
            lines = profile_file(t).read_text().splitlines()
            extra = [ln for ln in lines if ln.startswith(cmd)]
            p = t / "dup.cfg"
            p.write_text("\n".join(lines[:-1] + extra + lines[-1:]) + "\n")
            return ["process", capture_file(t), "--cfg", p, "--out", t / "o.csv"]
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


def signal_probes() -> list[Probe]:
    def sigterm(t):
        """SIGTERM to the main pid of `sweep --workers 2`: no process may remain."""
        import subprocess
        import sys
        import time

        import psutil
        f = write_file(t, "s.toml", 'name = "sig"\nscenarios = ["dense_highway", '
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
            raise Hang()
        raise ValueError(f"exit {p.returncode}, nothing left behind")
    return [Probe("signals", "sigterm_pool_sweep", cli=False, call=sigterm,
                  match=r"exit 143, nothing left behind", time_factor=4.0)]


def scheme_probes() -> list[Probe]:
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
            prof = special_file(kind, t / "p.cfg")
            return ["sweep", write_file(t, "s.toml", head + f'[vary]\n"radar.profile" = '
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


