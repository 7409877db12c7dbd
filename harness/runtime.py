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

References
----------
.. [1] glibc manual, "Memory Allocation Tunables" (M_MMAP_THRESHOLD, M_TRIM_THRESHOLD,
       M_TOP_PAD); mallopt(3).
"""
from __future__ import annotations

import ctypes
import ctypes.util

__all__ = ["tune_allocator", "single_thread_blas", "prepare_process"]

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
    """What every harness process applies before computing: one BLAS thread and the
    allocator tuning."""
    single_thread_blas()
    tune_allocator()
