"""Signals: SIGTERM and SIGHUP take Ctrl-C's path, and pool workers die with their
parent. Before: ``kill <main pid>`` of ``sweep --workers 2`` left both workers alive for good."""
from __future__ import annotations

import contextlib
import os
import signal
import subprocess
import sys
import textwrap
import time

import psutil
import pytest

from harness import cli, runtime
from harness.cli import main
from tests.harness.forked import fork_call, wait_exit

SWEEP = textwrap.dedent("""\
    name = "sig"
    scenarios = ["r79_motorcycle_rear", "blind_spot_overtaking", "head_on_aliasing",
                 "dense_highway"]
    seeds = [0, 1]
    duration_s = 2.0
    """)


def _children_when_running(proc: psutil.Process, n: int, timeout_s: float) -> list:
    t_end = time.monotonic() + timeout_s
    while time.monotonic() < t_end:
        kids = proc.children(recursive=True)
        if len(kids) >= n:
            return kids
        time.sleep(0.1)
    raise AssertionError(f"the sweep did not start {n} workers within {timeout_s} s")


@pytest.mark.slow  # a real pool sweep: 10-20 s (the in-process and death-signal tests are fast)
@pytest.mark.parametrize("sig", [signal.SIGTERM, signal.SIGHUP], ids=["SIGTERM", "SIGHUP"])
def test_signal_to_main_pid_of_a_pool_sweep_leaves_no_process(tmp_path, sig):
    f = tmp_path / "s.toml"
    f.write_text(SWEEP)
    out = tmp_path / "r"
    p = subprocess.Popen([sys.executable, "-m", "harness.cli", "sweep", str(f), "--out",
                          str(out), "--workers", "2", "--no-progress"],
                         stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        kids = _children_when_running(psutil.Process(p.pid), 2, 120.0)
        time.sleep(1.0)  # let the workers start their cells
        p.send_signal(sig)
        _, err = p.communicate(timeout=60)
    finally:
        if p.poll() is None:
            p.kill()
    assert p.returncode == 128 + sig, err
    assert "rerun the same command to resume" in err.strip().splitlines()[-1]
    gone, alive = psutil.wait_procs(kids, timeout=10)
    assert not alive, f"left behind: {[k.pid for k in alive]}"


@pytest.mark.slow
def test_sigkill_of_the_main_pid_takes_the_pool_workers_along(tmp_path):
    """No handler runs on SIGKILL: the workers' PR_SET_PDEATHSIG (or watchdog) ends them."""
    f = tmp_path / "s.toml"
    f.write_text(SWEEP)
    p = subprocess.Popen([sys.executable, "-m", "harness.cli", "sweep", str(f), "--out",
                          str(tmp_path / "r"), "--workers", "2", "--no-progress"],
                         stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    try:
        kids = _children_when_running(psutil.Process(p.pid), 2, 120.0)
        p.kill()
        p.wait(timeout=30)
    finally:
        if p.poll() is None:
            p.kill()
    _, alive = psutil.wait_procs(kids, timeout=10)
    assert not alive, f"left behind: {[k.pid for k in alive]}"


def _parent_of_an_armed_child(pid_file) -> None:
    """Fork a child armed with `exit_with_parent`, which writes its pid to `pid_file`; both
    then sleep."""
    parent = os.getpid()
    if os.fork() == 0:
        runtime.exit_with_parent(parent)
        pid_file.write_text(str(os.getpid()))
        time.sleep(60)
        os._exit(0)
    time.sleep(60)


def test_worker_dies_with_its_parent(tmp_path):
    """A child armed with `exit_with_parent` dies when its parent is SIGKILLed (no handler in
    the parent can run): PR_SET_PDEATHSIG on Linux, the watchdog elsewhere. The parent is
    forked from the test process (a fresh interpreter only adds its imports)."""
    pid_file = tmp_path / "child.pid"
    pid = fork_call(_parent_of_an_armed_child, pid_file, stdout=tmp_path / "out",
                    stderr=tmp_path / "err")
    try:
        t_end = time.monotonic() + 20
        while not (pid_file.exists() and pid_file.read_text()) and time.monotonic() < t_end:
            time.sleep(0.02)
        child = psutil.Process(int(pid_file.read_text()))
        os.kill(pid, signal.SIGKILL)
        wait_exit(pid, 10)
        gone, alive = psutil.wait_procs([child], timeout=5)
        assert not alive
    finally:
        with contextlib.suppress(OSError):  # nothing left running behind a failed test
            os.kill(pid, signal.SIGKILL)
            os.waitpid(pid, 0)


def test_exit_with_parent_arms_prctl_on_linux():
    if not sys.platform.startswith("linux"):
        pytest.skip("PR_SET_PDEATHSIG is Linux only; elsewhere the watchdog is used")
    code = ("import os; from harness.runtime import exit_with_parent; "
            "print(exit_with_parent(os.getppid()))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         timeout=30)
    assert out.stdout.strip() == "prctl", out.stderr


@pytest.mark.parametrize("sig", [signal.SIGTERM, signal.SIGHUP], ids=["SIGTERM", "SIGHUP"])
def test_stop_signal_takes_the_ctrl_c_path(monkeypatch, capsys, sig):
    """In process: the signal becomes `Terminated` (a KeyboardInterrupt) inside the command;
    main exits 128 + signum with the resume hint and restores the previous handlers."""
    import harness.cli.cmd_scenarios as cs

    def run(args):
        os.kill(os.getpid(), sig)
        time.sleep(5)  # the handler raises before this ends
        return 0

    monkeypatch.setattr(cs, "run_scenarios", run)
    with _handler(sig, _noop) as before:  # not ignored on entry (as under nohup)
        assert main(["scenarios"]) == 128 + sig
        err = capsys.readouterr().err.strip().splitlines()
        assert err == [f"radar-harness scenarios: stopped by {signal.Signals(sig).name}: rerun "
                       "the same command to resume"]
        assert signal.getsignal(sig) == before


def _noop(signum, frame):
    pass


@contextlib.contextmanager
def _handler(sig, handler):
    old = signal.signal(sig, handler)
    try:
        yield handler
    finally:
        signal.signal(sig, old)


@pytest.mark.parametrize("sig", [signal.SIGINT, signal.SIGTERM, signal.SIGHUP],
                         ids=["SIGINT", "SIGTERM", "SIGHUP"])
def test_a_signal_ignored_on_entry_stays_ignored(sig):
    """``nohup`` starts a run with SIGHUP ignored, a script's ``cmd &`` with SIGINT ignored:
    neither block takes that back (a closed terminal used to stop a nohup'ed sweep)."""
    with _handler(sig, signal.SIG_IGN):
        with runtime.terminate_on_signals():
            assert signal.getsignal(sig) is signal.SIG_IGN
            with runtime.stop_signals_recorded() as stops:
                assert signal.getsignal(sig) is signal.SIG_IGN
                os.kill(os.getpid(), sig)
                stops.check()
                assert stops.received == []


@pytest.mark.parametrize("sig", [signal.SIGTERM, signal.SIGHUP], ids=["SIGTERM", "SIGHUP"])
def test_a_pool_worker_keeps_a_stop_signal_its_parent_ignored(sig):
    """`prepare_worker` in a forked child that inherited `sig` ignored (and SIGINT handled):
    the ignored one stays ignored, the other stop signal is reset to its default."""
    other = signal.SIGHUP if sig == signal.SIGTERM else signal.SIGTERM
    with _handler(sig, signal.SIG_IGN), _handler(other, _noop):
        pid = os.fork()
        if pid == 0:
            code = 1
            try:
                runtime.prepare_worker(os.getppid())
                code = 0 if (signal.getsignal(sig) is signal.SIG_IGN and
                             signal.getsignal(other) is signal.SIG_DFL) else 3
            finally:
                os._exit(code)
    _, status = os.waitpid(pid, 0)
    assert os.waitstatus_to_exitcode(status) == 0


@pytest.mark.slow  # a stand-in pool sweep in a forked child, ~3 s; the worker set-up test is fast
@pytest.mark.parametrize("sig", [signal.SIGTERM, signal.SIGHUP], ids=["SIGTERM", "SIGHUP"])
def test_a_pool_sweep_started_ignoring_a_stop_signal_survives_it(tmp_path, sig):
    """``nohup radar-harness sweep ... &`` and the terminal closes: SIGHUP reaches the whole
    process group. The pool workers reset SIGHUP to its default (against the parent's inherited
    handlers), so a hang-up killed them and the run ended with "2 of 2 cells are missing (a
    worker died ...)"; they now keep ignoring what their parent ignored on entry."""
    import json

    from harness.sweep.spec import SweepSpec
    from tests.harness.forked import fork_sweep, forked_children, wait_exit
    spec = SweepSpec(name="nohup", scenarios=("slow", "fast"), seeds=(0,), duration_s=1.0)
    report = tmp_path / "report.json"
    with _handler(sig, signal.SIG_IGN):  # what nohup (SIGHUP) leaves the sweep with
        pid = fork_sweep(spec, tmp_path / "r", report=report, own_group=True)
    try:
        deadline = time.monotonic() + 60
        while len(forked_children(pid)) < 2 and time.monotonic() < deadline:
            time.sleep(0.02)
        assert len(forked_children(pid)) == 2, "the pool did not start its 2 workers"
        os.killpg(pid, sig)
        assert wait_exit(pid, 120) == 0
    finally:
        with contextlib.suppress(ProcessLookupError):
            os.killpg(pid, signal.SIGKILL)
    assert json.loads(report.read_text()) == {"ok": 2, "interrupted": 0}


@pytest.mark.parametrize("sig", [signal.SIGTERM, signal.SIGHUP], ids=["SIGTERM", "SIGHUP"])
def test_a_recorded_stop_signal_reaches_its_own_handler_when_the_block_ends(sig):
    """Inside `stop_signals_recorded` the signal is only recorded; `check` leaves the block,
    whose end delivers it to `terminate_on_signals`' handler: `Terminated`, not the check's
    exception."""
    reached = []
    with _handler(sig, _noop), _handler(signal.SIGINT, signal.default_int_handler):
        with runtime.terminate_on_signals():
            with pytest.raises(runtime.Terminated) as info:
                with runtime.stop_signals_recorded() as stops:
                    os.kill(os.getpid(), sig)
                    reached.append(list(stops.received))  # not raised where it landed
                    stops.check()
                    reached.append("after check")
            assert signal.getsignal(signal.SIGINT) is signal.default_int_handler
        assert reached == [[sig]]
        assert info.value.signum == sig


def test_terminated_is_a_keyboard_interrupt():
    exc = runtime.Terminated(signal.SIGTERM)
    assert isinstance(exc, KeyboardInterrupt) and exc.signum == signal.SIGTERM


class _ImportInterrupted:
    """Stands in for `importlib` in `harness.cli`: a Ctrl-C while the commands' modules
    (pandas, scipy, the pipeline: most of a second) import, before a command is known."""

    @staticmethod
    def import_module(name):
        raise KeyboardInterrupt


def test_ctrl_c_while_the_commands_import_gives_the_one_line(monkeypatch, capsys):
    monkeypatch.setattr(cli, "importlib", _ImportInterrupted)
    assert main(["scenarios"]) == 130
    assert capsys.readouterr().err.strip().splitlines() == [
        "radar-harness: interrupted: rerun the same command to resume"]


def test_ctrl_c_during_start_up_gives_the_one_line(monkeypatch, capsys):
    def interrupted():
        raise KeyboardInterrupt
    monkeypatch.setattr(cli, "prepare_process", interrupted)
    assert main(["scenarios"]) == 130
    assert capsys.readouterr().err.strip().splitlines() == [
        "radar-harness: interrupted: rerun the same command to resume"]
