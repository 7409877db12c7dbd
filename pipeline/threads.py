"""Data parallelism inside one frame's chain: independent parts of a pass on the machine's cores.

The floor a chain is measured against runs its FFTs on every core (`scipy.fft`, ``workers=-1``)
and so do the chains' own FFTs; the other passes (EGE, the azimuth GEMM, the CFAR) run on one
core unless the chain splits them. numpy's ufuncs and BLAS calls, scipy's FFTs and the numba
kernels (``nogil=True``) release the GIL, so a pass split into independent parts (rows of a
GEMM, azimuth rows of a map, chirps of a cube) runs on threads. Every part computes exactly what
the whole pass computes at its indices and the results are assembled in index order, so the
output is the same bits whatever the number of parts (tests/pipeline/test_threads.py runs every
chain with one and with two parts).

A sweep already keeps the cores busy (worker processes, `harness.cell.run` frame threads); the
parts then queue for the one helper thread and the caller runs its own part meanwhile, so
nothing waits on an idle core and nothing deadlocks (a part never submits parts itself).
"""
from __future__ import annotations

import os
import threading
from collections.abc import Callable, Iterator, Sequence
from concurrent.futures import Future, ThreadPoolExecutor
from contextlib import contextmanager
from typing import TypeVar

__all__ = ["n_parts", "fft_workers", "spans", "run_parts", "inline"]

T = TypeVar("T")

_LOCK = threading.Lock()
_POOL: list[ThreadPoolExecutor] = []

#: Parts a pass is split into: the machine's cores, at most 2 (the harness's 2-core target;
#: more parts cost hand-offs for little gain on these frame sizes). 1 runs everything inline.
N_PARTS = max(1, min(2, os.cpu_count() or 1))


#: Per thread: its chains run every pass whole (`inline`).
_LOCAL = threading.local()


def n_parts() -> int:
    """Parts a pass is split into: `N_PARTS`, or 1 on a thread inside `inline`."""
    return 1 if getattr(_LOCAL, "inline", False) else N_PARTS


def fft_workers() -> int:
    """``workers`` for a chain's `scipy.fft` calls: every core (-1) where passes are split, 1
    on a thread inside `inline` (a sweep cell's frames already keep the cores busy, so the
    transform's threads would only queue for a core). pocketfft computes every 1-D transform
    alone whatever the thread count: the same bits either way."""
    return -1 if n_parts() > 1 else 1


@contextmanager
def inline() -> Iterator[None]:
    """Within the block the calling thread's chains split no pass (`n_parts` is 1 there).

    For callers that already keep every core busy with whole frames (a sweep cell runs two
    frames at a time): parts would only add hand-offs. Measured on a quiet 2-core machine, a
    cell of r79_motorcycle_rear took 11 % less CPU and 10 % less wall time with its frames'
    chains inline. The bits do not depend on it (parts compute exactly the whole pass).
    """
    before = getattr(_LOCAL, "inline", False)
    _LOCAL.inline = True
    try:
        yield
    finally:
        _LOCAL.inline = before


def spans(n: int, parts: int | None = None, multiple: int = 1) -> list[tuple[int, int]]:
    """`parts` (default `n_parts()`) contiguous (lo, hi) index ranges covering 0..n, every
    boundary a multiple of `multiple`; fewer ranges when n is too small (never an empty one).

    Examples
    --------
    >>> spans(48, 2)
    [(0, 24), (24, 48)]
    >>> spans(10, 2, multiple=4)
    [(0, 4), (4, 10)]
    >>> spans(3, 2, multiple=4)
    [(0, 3)]
    """
    parts = n_parts() if parts is None else parts
    cuts = sorted({min(n, (n * i // parts) // multiple * multiple) for i in range(1, parts)})
    bounds = [0] + [c for c in cuts if 0 < c < n] + [n]
    return list(zip(bounds[:-1], bounds[1:]))


def _forget_pool_after_fork() -> None:
    """A forked child (a `ProcessPoolExecutor` sweep worker) has no copy of the parent's
    helper thread: it must not submit to the parent's executor (its parts would never run),
    so it starts without one and makes its own on first use."""
    global _LOCK
    _LOCK = threading.Lock()
    _POOL.clear()


if hasattr(os, "register_at_fork"):
    os.register_at_fork(after_in_child=_forget_pool_after_fork)


def _pool() -> ThreadPoolExecutor:
    with _LOCK:
        if not _POOL:
            _POOL.append(ThreadPoolExecutor(max_workers=max(1, N_PARTS - 1),
                                            thread_name_prefix="pipeline-part"))
        return _POOL[0]


def run_parts(calls: Sequence[Callable[[], T]]) -> list[T]:
    """Run independent zero-argument calls, the first on the calling thread and the others on
    the helper thread(s); return their results in order. A part the helper has not started by
    the time the caller is done with its own (the helper busy with another frame's part, or no
    free core) is taken back and run by the caller, so a busy machine costs no waiting. Every
    call has finished when this returns or raises (the first exception is raised). Where
    `n_parts` is 1 (inside `inline`, or a one-core machine) every call runs on the calling
    thread, in order, whatever the caller split: the calls are independent by contract."""
    if len(calls) <= 1 or n_parts() == 1:
        return [c() for c in calls]
    futures: list[Future] = [_pool().submit(c) for c in calls[1:]]
    try:
        first = calls[0]()
    except BaseException:
        for f in futures:
            if not f.cancel():
                f.exception()  # wait for a running part, whatever happened here
        raise
    results = [first]
    for call, f in zip(calls[1:], futures):
        results.append(call() if f.cancel() else f.result())
    return results
