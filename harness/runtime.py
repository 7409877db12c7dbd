"""Process-level runtime tuning for the harness's own processes (CLI, sweep workers, benches).

The signal chain allocates tens of MB of short-lived arrays per frame. With glibc's defaults,
blocks this size are mmap-ed and returned to the kernel on every free (and the heap top is
trimmed), so every frame page-faults its working set back in: about a fifth of the DDMA chain's
time (29 -> 23 ms per R79 frame measured here). Keeping freed memory in the heap is a standard
setting for real-time DSP processes. It is applied by the application entry points, never on
import of a library package.

BLAS threads: a multithreaded GEMM splits its sums differently from a single-threaded one, so
the front end's ADC samples can differ by one LSB between a process with 1 BLAS thread and one
with several. Every path that computes numbers (`run`, `simulate`, `process`, the report's maps,
a serial sweep, pool and Dask workers) therefore runs with one BLAS thread
(`single_thread_blas`): same seed, same bits, whatever the worker count or scheduler. It is
also the fast setting here: with one worker per core, BLAS threads only oversubscribe the cores.

numba: the kernels' disk cache is shared by every process of a sweep, so `prepare_process`
also puts numba's cache index under a file lock (`core.numba_cache.install_cache_lock`), an
explicit call here rather than a patch made by importing the pipeline.

Signals: a supervisor, ``Popen.terminate()`` or a batch system stops a run with SIGTERM (a
closed terminal sends SIGHUP), to the main process only. `terminate_on_signals` turns both
into `Terminated`, a KeyboardInterrupt, so they take Ctrl-C's path (pool workers stopped, cells
written so far kept, exit with the resume hint). Pool workers (`prepare_worker`) also die with
their parent, even a parent killed by SIGKILL: Linux's PR_SET_PDEATHSIG [2]_, or a watchdog
thread on ``os.getppid()`` where prctl is missing. While a process pool starts and runs, the
parent only records stop signals and raises them where it polls (`stop_signals_recorded`):
Python drops an exception a signal raises inside os.fork's at-fork hooks, which a Ctrl-C that
lands while the pool forks its workers did. A signal ignored on entry (SIGINT of a job a
script started with ``&``, SIGHUP under ``nohup``) stays ignored, as POSIX shells expect [3]_.

References
----------
.. [1] glibc manual, "Memory Allocation Tunables" (M_MMAP_THRESHOLD, M_TRIM_THRESHOLD,
       M_TOP_PAD); mallopt(3).
.. [2] prctl(2), PR_SET_PDEATHSIG: "the signal that the calling process will get when its
       parent dies"; the parent is the thread that created it.
.. [3] POSIX.1-2017, Shell Command Language, 2.11 "Signals and Error Handling": the commands of
       an asynchronous list inherit SIGINT and SIGQUIT ignored; Python keeps SIGINT ignored
       when it starts with it ignored (`signal` module documentation).
"""
from __future__ import annotations

import concurrent.futures as cf
import contextlib
import ctypes
import ctypes.util
import os
import signal
import sys
import threading
from collections.abc import Iterator
from typing import NamedTuple

from core.numba_cache import install_cache_lock

__all__ = ["tune_allocator", "single_thread_blas", "prepare_process", "exit_with_parent",
           "prepare_worker", "Terminated", "terminate_on_signals", "StopSignals",
           "stop_signals_recorded", "STOP_POLL_S", "stop_pool", "stoppable_pool",
           "StoppablePool"]

_M_TRIM_THRESHOLD, _M_TOP_PAD, _M_MMAP_THRESHOLD = -1, -2, -3
_MMAP_THRESHOLD_BYTES = 32 << 20  # glibc's maximum on 64-bit: blocks below come from the heap
_TRIM_THRESHOLD_BYTES = 1 << 30
_TOP_PAD_BYTES = 64 << 20


def tune_allocator() -> bool:
    """Keep freed large blocks in the heap (glibc mallopt). Returns True if applied, False on a
    platform without glibc's mallopt (nothing changes there)."""
    name = ctypes.util.find_library("c")
    try:
        libc = ctypes.CDLL(name)
        mallopt = libc.mallopt
    except (OSError, AttributeError, TypeError):
        return False
    return all(mallopt(opt, value) == 1 for opt, value in (
        (_M_MMAP_THRESHOLD, _MMAP_THRESHOLD_BYTES), (_M_TRIM_THRESHOLD, _TRIM_THRESHOLD_BYTES),
        (_M_TOP_PAD, _TOP_PAD_BYTES)))


def single_thread_blas() -> None:
    """Limit BLAS to one thread in this process (threadpoolctl), for bit-identical results on
    every execution path (module docstring). Process-wide and permanent: entry points and
    workers call it once; calling it again is harmless.

    threadpoolctl limits only the BLAS libraries already loaded, and scipy ships its own
    OpenBLAS, loaded with `scipy.linalg`: it is imported first, and the OpenBLAS / OpenMP
    thread variables are set for any library loaded later (without this, `radar-harness run`,
    which limits before importing the chain, differed from a sweep cell in the last bits).
    """
    import os

    import scipy.linalg  # noqa: F401  (loads scipy's OpenBLAS so that the limit reaches it)
    from threadpoolctl import threadpool_limits
    for var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
        os.environ[var] = "1"
    threadpool_limits(limits=1, user_api="blas")


def prepare_process() -> None:
    """What every harness process applies before computing: one BLAS thread, the allocator
    tuning and the lock around numba's cache index (`core.numba_cache.install_cache_lock`:
    the harness's processes compile kernels beside each other)."""
    single_thread_blas()
    tune_allocator()
    install_cache_lock()


_PR_SET_PDEATHSIG = 1
#: How often the fallback watchdog looks at the parent pid, s.
_WATCHDOG_PERIOD_S = 0.5


def exit_with_parent(parent_pid: int) -> str:
    """Make this process die when its parent `parent_pid` dies.

    Linux: PR_SET_PDEATHSIG with SIGKILL (nothing in a worker needs to run after its parent is
    gone: an unfinished cell is lost whole and redone on resume). Elsewhere: a daemon thread
    that exits the process once ``os.getppid()`` is no longer `parent_pid`. Either way, a
    parent that died before this call is caught by comparing the parent pid once now.

    Returns
    -------
    str
        "prctl" or "watchdog" (which mechanism is armed).
    """
    how = "watchdog"
    if sys.platform.startswith("linux"):
        try:
            libc = ctypes.CDLL(ctypes.util.find_library("c"), use_errno=True)
            if libc.prctl(_PR_SET_PDEATHSIG, int(signal.SIGKILL), 0, 0, 0) == 0:
                how = "prctl"
        except (OSError, AttributeError, TypeError):
            pass
    if os.getppid() != parent_pid:  # the parent died before the death signal was armed
        os._exit(1)
    if how == "watchdog":
        def watch() -> None:
            while os.getppid() == parent_pid:
                threading.Event().wait(_WATCHDOG_PERIOD_S)
            os._exit(1)
        threading.Thread(target=watch, name="parent-watchdog", daemon=True).start()
    return how


def prepare_worker(parent_pid: int) -> None:
    """Set up a pool worker process: die with the parent (`exit_with_parent`), leave SIGINT to
    the parent (a Ctrl-C lets the parent stop the pool), SIGTERM and SIGHUP at their default
    (a forked worker inherits the parent's `terminate_on_signals` or `stop_signals_recorded`
    handlers, which would turn the pool's own ``terminate()`` into an exception the worker
    survives, or into nothing), then `prepare_process`.

    A stop signal the worker inherits ignored stays ignored: neither block installs a handler
    for a signal ignored on entry, so an inherited SIG_IGN is the run's own (SIGHUP under
    ``nohup``), and a hang-up sent to the process group must not kill the workers of a run
    started to survive it."""
    exit_with_parent(parent_pid)
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    for sig in _STOP_SIGNALS:
        if signal.getsignal(sig) is not signal.SIG_IGN:
            signal.signal(sig, signal.SIG_DFL)
    prepare_process()


class Terminated(KeyboardInterrupt):
    """SIGTERM or SIGHUP received: handled like Ctrl-C. ``signum`` is the signal."""

    def __init__(self, signum: int) -> None:
        super().__init__(signal.Signals(signum).name)
        self.signum = signum


_STOP_SIGNALS = tuple(getattr(signal, name) for name in ("SIGTERM", "SIGHUP")
                      if hasattr(signal, name))


@contextlib.contextmanager
def terminate_on_signals():
    """Within the block, SIGTERM and SIGHUP raise `Terminated` in the main thread (the
    previous handlers come back on exit). The first signal also ignores further ones, so a
    supervisor's repeated SIGTERM cannot interrupt the clean-up it asked for (SIGKILL still
    can). Outside the main thread this does nothing."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return

    def handler(signum, frame):
        for sig in _STOP_SIGNALS:
            signal.signal(sig, signal.SIG_IGN)
        raise Terminated(signum)

    previous = {sig: signal.signal(sig, handler) for sig in _STOP_SIGNALS
                if signal.getsignal(sig) is not signal.SIG_IGN}  # nohup's SIGHUP stays ignored
    try:
        yield
    finally:
        for sig, old in previous.items():
            signal.signal(sig, old)


#: How often a sweep's main thread looks for a recorded stop signal while it waits, s.
STOP_POLL_S = 0.1


class _StopRequested(KeyboardInterrupt):
    """Raised by `StopSignals.check` to leave the block; the block's exit then delivers the
    recorded signal again, to the handler it was meant for."""


class StopSignals:
    """The stop signals recorded in a `stop_signals_recorded` block (signal numbers, in order
    of arrival)."""

    def __init__(self) -> None:
        self.received: list[int] = []

    def check(self) -> None:
        """Raise (a KeyboardInterrupt) if a stop signal was recorded; the block's exit turns it
        into what the signal's own handler does."""
        if self.received:
            raise _StopRequested(signal.Signals(self.received[0]).name)


@contextlib.contextmanager
def stop_signals_recorded():
    """Within the block, SIGINT, SIGTERM and SIGHUP are only recorded (`StopSignals`); the
    block calls `StopSignals.check` where stopping is safe (at most `STOP_POLL_S` apart while
    it waits). On exit the handlers of before the block come back and the first recorded
    signal is delivered to them again (``signal.raise_signal``): KeyboardInterrupt for
    Ctrl-C, `Terminated` inside `terminate_on_signals`, the default action elsewhere.

    Why: Python raises a signal's exception at whatever bytecode the main thread runs next.
    In a callback whose exceptions Python only prints ("Exception ignored in ..."), the signal
    is lost: os.fork runs the at-fork hooks of the modules loaded (logging's are Python
    functions), so a Ctrl-C that landed while a process pool forked its workers (likeliest
    under load) let the sweep run to its end and exit 0. Signals ignored on entry stay
    ignored. Outside the main thread nothing is recorded and `StopSignals.check` never raises.

    Examples
    --------
    >>> import signal
    >>> old = signal.signal(signal.SIGINT, signal.default_int_handler)  # a terminal's Ctrl-C
    >>> try:
    ...     with stop_signals_recorded() as stops:
    ...         signal.raise_signal(signal.SIGINT)  # recorded, not raised here
    ...         print(stops.received == [signal.SIGINT])
    ... except KeyboardInterrupt:
    ...     print("raised when the block ends")
    ... finally:
    ...     _ = signal.signal(signal.SIGINT, old)
    True
    raised when the block ends
    """
    stops = StopSignals()
    previous = {}
    if threading.current_thread() is threading.main_thread():
        def record(signum, frame):
            stops.received.append(signum)
        for sig in (signal.SIGINT, *_STOP_SIGNALS):
            if signal.getsignal(sig) not in (signal.SIG_IGN, None):  # None: not Python's
                previous[sig] = signal.signal(sig, record)
    try:
        yield stops
    finally:
        for sig, old in previous.items():
            signal.signal(sig, old)
        if stops.received:
            signal.raise_signal(stops.received[0])


class StoppablePool(NamedTuple):
    """A process pool inside `stoppable_pool`: its `executor` and the stop signals recorded."""

    executor: cf.ProcessPoolExecutor
    stops: StopSignals

    def completed(self, futures) -> Iterator[cf.Future]:
        """`futures` as they complete (``concurrent.futures.as_completed``), a recorded stop
        signal raised between them, at most `STOP_POLL_S` apart."""
        waiting = set(futures)
        while waiting:
            self.stops.check()
            done, waiting = cf.wait(waiting, timeout=STOP_POLL_S, return_when=cf.FIRST_COMPLETED)
            yield from done


@contextlib.contextmanager
def stoppable_pool(workers: int, initializer, initargs: tuple) -> Iterator[StoppablePool]:
    """A process pool that a stop signal (Ctrl-C, SIGTERM, SIGHUP) stops at any moment, its
    start included: the signals are recorded (`stop_signals_recorded`) and raised where the
    user waits (`StoppablePool.completed`), not where they land (one landing inside os.fork's
    at-fork hooks, while the pool forks its workers, would be dropped). On any escape from
    the block the pool is stopped and its workers reaped (`stop_pool`) before the exception
    goes on; otherwise the block's end waits for the pool to shut down."""
    with stop_signals_recorded() as stops:
        ex = cf.ProcessPoolExecutor(max_workers=workers, initializer=initializer,
                                    initargs=initargs)
        try:
            yield StoppablePool(ex, stops)
        except BaseException:
            stop_pool(ex)
            raise
        ex.shutdown(wait=True)


def stop_pool(ex: cf.ProcessPoolExecutor, join_timeout_s: float = 5.0) -> None:
    """Stop a process pool now: terminate its workers, cancel what has not started and reap
    every worker (killed if it outlives `join_timeout_s`), so none outlives the caller.

    For the ``except BaseException`` of a pool's user (a stop signal, or any escape): running
    tasks are lost whole, which is what a sweep's cell store and a report expect.
    """
    # The executor's own worker table (private, stable since Python 3.2; None once shut down).
    procs = list((getattr(ex, "_processes", None) or {}).values())
    for proc in procs:
        proc.terminate()
    ex.shutdown(wait=False, cancel_futures=True)
    for proc in procs:
        proc.join(timeout=join_timeout_s)
        if proc.is_alive():
            proc.kill()
