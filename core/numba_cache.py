"""A file lock around numba's on-disk cache index, so concurrent processes cannot cross entries.

The pipeline's kernels are ``numba.njit(cache=True)``. numba keeps one index file per function
(signature -> data file ``<name>.<n>.nbc``) and updates it without a lock, so two processes
compiling different signatures of one kernel at once (two sweep or Dask workers on a fresh
install) can both take data file 1, and the index can end up naming the other process's code
for a signature: a later process runs a kernel compiled for other argument types (a segfault
or wrong numbers). `install_cache_lock` serialises numba's index updates with ``flock``.

It patches numba's private cache class, so nothing does it at import time: a process that may
compile kernels beside other processes calls it once, before its first kernel call. The
harness does in `harness.runtime.prepare_process` (the CLI and every pool worker) and in
`harness.worker.execute_cell` (Dask workers), the test suite in ``tests/conftest.py``,
``python -m benchmarks`` at its start; a program of its own that runs the pipeline in several
processes calls ``core.numba_cache.install_cache_lock()`` (also ``pipeline.install_cache_lock``)
in each. One process alone needs nothing.
"""
from __future__ import annotations

import contextlib
import functools
import time

try:
    import fcntl
except ImportError:  # not POSIX (Windows): numba's cache stays as it is
    fcntl = None

#: Marks numba methods this module has wrapped (so installing twice wraps once).
_MARK = "_pipeline_cache_lock"

#: Longest wait for another process's cache step, s. numba's index and data writes take
#: milliseconds; a holder stalled longer (a stopped process, a hung file system) is passed by,
#: the step then running unlocked as numba's own does, rather than stalling every worker.
LOCK_WAIT_S = 30.0


def _flock(f, mode: int) -> bool:
    """``flock(mode)`` on `f`, polling for at most `LOCK_WAIT_S`; False if not taken."""
    deadline = time.monotonic() + LOCK_WAIT_S
    while True:
        try:
            fcntl.flock(f, mode | fcntl.LOCK_NB)
            return True
        except BlockingIOError:  # held by another process
            if time.monotonic() >= deadline:
                return False
            time.sleep(0.002)
        except OSError:  # a file system without flock
            return False


def _open_lock_file(path: str):
    """The lock file, created if need be; read-only if another user created it (flock needs
    no write access); None if it cannot be opened at all."""
    for mode in ("a", "r"):
        try:
            return open(path, mode)
        except OSError:
            continue
    return None


@contextlib.contextmanager
def _index_lock(index_path: str, mode: int):
    """Hold ``flock(mode)`` on ``<index_path>.lock`` (created beside the index) for the block.

    Where the lock file cannot be opened or locked (a read-only cache directory, a file system
    without ``flock``, a holder stalled for `LOCK_WAIT_S`), the block runs unlocked: numba's
    own behaviour, never an error."""
    f = _open_lock_file(index_path + ".lock")
    if f is None:
        yield
        return
    with f:
        locked = _flock(f, mode)
        try:
            yield
        finally:
            if locked:
                fcntl.flock(f, fcntl.LOCK_UN)


def _locked(method, mode: int):
    """`method` of ``IndexDataCacheFile`` run under the lock of the instance's index file."""
    @functools.wraps(method)
    def wrapper(self, *args, **kwargs):
        index_path = getattr(self, "_index_path", None)
        if not isinstance(index_path, str):  # not the class this module was written for
            return method(self, *args, **kwargs)
        with _index_lock(index_path, mode):
            return method(self, *args, **kwargs)
    setattr(wrapper, _MARK, True)
    return wrapper


def install_cache_lock() -> bool:
    """Make numba's disk cache safe for concurrent processes (idempotent, process-wide).

    Wraps ``numba.core.caching.IndexDataCacheFile.save`` in an exclusive ``flock`` and
    ``IndexDataCacheFile.load`` in a shared one, both on a lock file beside the function's
    index (``<name>.nbi.lock``). A writer then loads the index, picks a free data-file number,
    saves the index and the data as one step, so a second writer sees the first one's entry
    and takes the next number; a reader never sees an index entry whose data file is not yet
    written.

    Returns
    -------
    bool
        True if the lock is in place (now or from an earlier call); False if numba was left
        as it is: no ``fcntl`` (not POSIX), or numba's caching module lacks what is wrapped.

    Notes
    -----
    Read in numba 0.68.1, ``numba/core/caching.py``: ``IndexDataCacheFile.save`` (lines
    578-595) calls ``_load_index`` (611), takes the first ``<name>.<n>.nbc`` the loaded index
    does not use, then ``_save_index`` (636) and ``_save_data`` (652); each file is written
    to a temporary name and renamed (``_open_for_write``, 668), so a file is never torn, but
    nothing stops two processes interleaving these steps. Both can pick ``.1.nbc``; the last
    index writer wins and may point its signature at the other process's data (the test
    ``tests/pipeline/test_numba_cache.py`` forces this interleaving). Upstream: numba issue
    #10128 (open: two processes caching one gufunc leave its kernel and wrapper from different
    compilations, a segfault; numba's developers suggested a file lock) and #4807 (open: cache
    segfaults when generated in parallel). This lock covers one index and its data files, not
    #10128's kernel/wrapper pair (two indexes); the pipeline has no gufuncs.
    ``flock`` is advisory and machine-local: processes on different hosts sharing a cache
    over NFS are not serialised (nor are they by numba). ``IndexDataCacheFile.flush`` (empties
    the index, only on an explicit ``Cache.flush()``) stays unlocked.

    References
    ----------
    .. [1] numba issue #10128, "Race condition in GUFunc caching can lead to segmentation
       faults", https://github.com/numba/numba/issues/10128
    .. [2] numba issue #4807, "Cache causes Segmentation Faults when generated in parallel",
       https://github.com/numba/numba/issues/4807

    Examples
    --------
    >>> from numba.core.caching import IndexDataCacheFile
    >>> install_cache_lock()
    True
    >>> save = IndexDataCacheFile.save
    >>> install_cache_lock() and IndexDataCacheFile.save is save  # installed once
    True
    """
    if fcntl is None:
        return False
    try:
        from numba.core.caching import IndexDataCacheFile
    except ImportError:  # numba reorganised its caching: leave it alone
        return False
    methods = {"save": fcntl.LOCK_EX, "load": fcntl.LOCK_SH}
    # The steps save/load are made of must be there too, or save/load are not what was read.
    if not all(callable(getattr(IndexDataCacheFile, name, None))
               for name in (*methods, "_load_index", "_save_index", "_save_data")):
        return False
    for name, mode in methods.items():
        method = getattr(IndexDataCacheFile, name)
        if not getattr(method, _MARK, False):
            setattr(IndexDataCacheFile, name, _locked(method, mode))
    return True
