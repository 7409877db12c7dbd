"""A stand-in sweep, or any call, in a child process forked from the test's own process.

Tests that kill a sweep's processes need the sweep in a process of its own. A fresh
interpreter (``python -c ...``) spends ~2 s CPU importing the harness before the sweep
starts; a fork of the test process has everything imported already and runs the same
`run_sweep` with a real process pool (the pool forks its workers from the child, as the CLI's
pool forks them from the CLI process).
"""
from __future__ import annotations

import contextlib
import json
import os
import signal
import sys
import tempfile
import time
import traceback
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from pathlib import Path


def fork_sweep(spec, out: Path, report: Path | None = None, env: dict | None = None,
               own_group: bool = False) -> int:
    """Fork a child that runs ``run_sweep(spec, out, workers=2)`` with the stand-in components
    and exits; return its pid.

    `env` is added to the child's environment before the pool starts (its workers inherit it).
    `report`: the child writes ``{"ok": n_ok, "interrupted": n_interrupted}`` there. `own_group`:
    the child leads a process group of its own (its pool workers join it), so
    ``os.killpg(pid, ...)`` reaches the whole sweep and nothing else.
    """
    pid = os.fork()
    if pid == 0:  # the child: never returns into the test runner
        code = 1
        try:
            if own_group:
                os.setpgid(0, 0)
            os.environ.update(env or {})
            from harness.sweep.schedule import run_sweep
            from tests.harness.fakes import FAKE
            o = run_sweep(spec, out, workers=2, components=FAKE, progress=False)
            if report is not None:
                report.write_text(json.dumps({"ok": o.n_ok, "interrupted": o.n_interrupted}))
            code = 0
        except BaseException:  # noqa: BLE001 - reported on stderr, exit status 1
            traceback.print_exc()
            sys.stderr.flush()
        finally:
            os._exit(code)
    if own_group:
        try:  # both sides set it: the group exists as soon as either has run
            os.setpgid(pid, pid)
        except OSError:  # the child did it first, or has already exited
            pass
    return pid


@dataclass(frozen=True)
class Ran:
    """What a forked call did: its exit status and what it printed (as `subprocess.run`'s)."""
    returncode: int
    stdout: str
    stderr: str


def fork_call(func: Callable[..., int | None], *args, stdout: Path, stderr: Path,
              sys_path=()) -> int:
    """Fork a child that calls ``func(*args)`` and exits; return its pid.

    The child's stdout and stderr (Python's and the file descriptors) go to the files
    `stdout` and `stderr`; `sys_path` is put in front of its ``sys.path`` (as ``PYTHONPATH``
    would be). Exit status: what `func` returns (None is 0), ``SystemExit``'s code, or 1
    after an exception (traceback on stderr).
    """
    pid = os.fork()
    if pid == 0:  # the child: never returns into the test runner
        code = 1
        try:
            sys.stdout, sys.stderr = open(stdout, "w"), open(stderr, "w")
            os.dup2(sys.stdout.fileno(), 1)
            os.dup2(sys.stderr.fileno(), 2)
            sys.path[:0] = [str(p) for p in sys_path]
            code = func(*args) or 0
        except SystemExit as exc:
            code = exc.code if isinstance(exc.code, int) else (exc.code is not None)
        except BaseException:  # noqa: BLE001 - reported on stderr, exit status 1
            traceback.print_exc()
        finally:
            sys.stdout.flush()
            sys.stderr.flush()
            os._exit(code)
    return pid


def run_forked(func: Callable[..., int | None], *args, sys_path=(), timeout_s: float = 300.0
               ) -> Ran:
    """`fork_call` and wait for the child: its exit status and what it printed.

    For a command that must not leave state in the test process (a plugin it loads stays
    loaded: registries, code version) but need not start a fresh interpreter (~2.5 s CPU of
    imports): the child has everything imported already.
    """
    with tempfile.TemporaryDirectory() as tmp:
        out, err = Path(tmp) / "stdout", Path(tmp) / "stderr"
        pid = fork_call(func, *args, stdout=out, stderr=err, sys_path=sys_path)
        code = wait_exit(pid, timeout_s)
        return Ran(code, out.read_text(), err.read_text())


def wait_exit(pid: int, timeout_s: float) -> int:
    """Wait for the forked child `pid`; its exit status (-signal if a signal ended it).
    Raises TimeoutError (after killing it) if it is still running after `timeout_s`."""
    deadline = time.monotonic() + timeout_s
    while True:
        done, status = os.waitpid(pid, os.WNOHANG)
        if done:
            return os.waitstatus_to_exitcode(status)
        if time.monotonic() > deadline:
            os.kill(pid, 9)
            os.waitpid(pid, 0)
            raise TimeoutError(f"forked sweep {pid} still running after {timeout_s} s")
        time.sleep(0.02)


def wait_group_gone(pgid: int, timeout_s: float) -> None:
    """Wait until no process of group `pgid` runs any more: each is gone or a zombie (a
    killed sweep's pool workers outlive their parent as zombies until init reaps them, which
    a container's PID 1 may never do; the cell store takes a zombie for a dead writer)."""
    deadline = time.monotonic() + timeout_s
    while _running_in_group(pgid):
        if time.monotonic() > deadline:
            raise TimeoutError(f"process group {pgid} still running after {timeout_s} s")
        time.sleep(0.02)


def _running_in_group(pgid: int) -> bool:
    """Whether a process of group `pgid` exists that is not a zombie (Linux /proc/<pid>/stat:
    state, then the group two fields on, after "pid (comm) ", proc(5)); where there is no
    procfs, whether the group exists at all."""
    if not Path("/proc/self/stat").exists():
        try:
            os.killpg(pgid, 0)
        except ProcessLookupError:
            return False
        return True
    for stat in Path("/proc").glob("[0-9]*/stat"):
        try:
            fields = stat.read_text()
        except OSError:  # gone meanwhile
            continue
        state, _, group = fields[fields.rfind(")") + 2:].split()[:3]
        if int(group) == pgid and state != "Z":
            return True
    return False


def forked_children(pid: int) -> list[int]:
    """Children of `pid` running its own executable: forked pool workers, not `git`."""
    try:
        exe = os.readlink(f"/proc/{pid}/exe")
        kids = Path(f"/proc/{pid}/task/{pid}/children").read_text().split()
    except OSError:  # the sweep has exited
        return []
    out = []
    for k in kids:
        try:
            if os.readlink(f"/proc/{k}/exe") == exe:
                out.append(int(k))
        except OSError:  # gone meanwhile
            pass
    return out


_FORK_SIGNAL = {"armed": False, "registered": False}


@contextlib.contextmanager
def ctrl_c_at_the_next_fork() -> Iterator[dict]:
    """Within the block, SIGINT is handled as in a terminal (KeyboardInterrupt) and this
    process sends itself SIGINT from inside its next ``os.fork()`` (a pool worker's start):
    Python runs the handler at the first bytecode it meets, in the at-fork hooks, as for a
    Ctrl-C that lands while a pool forks its workers under load. Yields a dict whose "fired"
    says, after the block, whether the signal was sent (a test that never forked tests
    nothing)."""
    if not _FORK_SIGNAL["registered"]:
        def before() -> None:
            if _FORK_SIGNAL["armed"]:
                _FORK_SIGNAL["armed"] = False
                os.kill(os.getpid(), signal.SIGINT)
        os.register_at_fork(before=before)  # permanent: inert while disarmed
        _FORK_SIGNAL["registered"] = True
    state = {"fired": False}
    old = signal.signal(signal.SIGINT, signal.default_int_handler)
    _FORK_SIGNAL["armed"] = True
    try:
        yield state
    finally:
        state["fired"] = not _FORK_SIGNAL["armed"]
        _FORK_SIGNAL["armed"] = False
        signal.signal(signal.SIGINT, old)
