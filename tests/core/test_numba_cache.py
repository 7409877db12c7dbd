"""numba's disk-cache race between two processes, forced step by step, and the lock that closes it.

Two subprocesses, A and B, compile two signatures (``float64[::1]``, ``int64[::1]``) of one
throwaway ``njit(cache=True)`` function into an empty ``NUMBA_CACHE_DIR``. Hooks on numba's
``IndexDataCacheFile`` steps (event files passed between the two processes) force the
interleaving numba's unlocked save allows: both load the empty index and pick data file 1, A
saves its index, B saves its index and its data, then A its data. The index then names A's
float64 code for B's int64 signature and A's entry is gone. Each process then calls the other's
signature, which it has not compiled, so its dispatcher loads it from the disk cache as a fresh
process would: with `core.numba_cache.install_cache_lock` both must load and sum right.
Run with the lock disabled (``methods = {}`` in `install_cache_lock`), the locked test fails:
B's float64 signature is missing from the index (B compiles it again).
"""
from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

import core.numba_cache as numba_cache

fcntl = pytest.importorskip("fcntl")  # flock: POSIX only

MODULE = Path(numba_cache.__file__)
KERNEL = '''\
import numba


@numba.njit(cache=True)
def total(x):
    return x[0] + x[1] + x[2]  # no loop: compiles in ~0.2 s
'''
# Role A compiles float64, role B int64. Each step waits for the other's event file; with the
# lock installed B cannot load the index while A holds the lock, so A does not wait for B's
# steps inside save (it could not) and instead sleeps 0.2 s after B arrived at the lock: time
# in which a lock that did not hold would let B load the index A has not saved yet.
WORKER = '''\
import importlib.util, json, os, sys, time
import numpy as np
role, locked, events, moddir, lockmod = sys.argv[1], sys.argv[2] == "1", *sys.argv[3:]
if locked:  # the module alone: importing the pipeline package costs ~2 s per process
    spec = importlib.util.spec_from_file_location("numba_cache", lockmod)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    assert mod.install_cache_lock()
from numba.core.caching import IndexDataCacheFile as C


def signal(name):
    open(os.path.join(events, name), "w").close()


def wait(name):
    deadline = time.monotonic() + 20.0
    while not os.path.exists(os.path.join(events, name)):
        if time.monotonic() > deadline:
            sys.exit(f"{role}: no {name} after 20 s")
        time.sleep(0.002)


save, save_index, save_data = C.save, C._save_index, C._save_data
me, other = role, "B" if role == "A" else "A"


def outer_save(self, key, data):  # both compiled (and looked the cache up) before either saves
    signal(me + "-ready")
    wait(other + "-ready")
    if role == "B":
        wait("A-pre-index")
        signal("B-entered")
    save(self, key, data)


def hooked_index(self, overloads):
    if role == "A":
        signal("A-pre-index")
        wait("B-entered")
        if locked:
            time.sleep(0.2)
        else:
            wait("B-pre-index")
        save_index(self, overloads)
        signal("A-post-index")
    else:
        signal("B-pre-index")
        wait("A-post-index")
        save_index(self, overloads)


def hooked_data(self, name, data):
    if role == "A" and not locked:
        wait("B-post-data")
    save_data(self, name, data)
    signal(me + "-post-data")


C.save, C._save_index, C._save_data = outer_save, hooked_index, hooked_data
sys.path.insert(0, moddir)
import kernel
dtypes = {"A": np.float64, "B": np.int64}
mine = kernel.total(np.arange(1, 4, dtype=dtypes[me]))
C.save, C._save_index, C._save_data = save, save_index, save_data
signal(me + "-done")
wait(other + "-done")
# The other's signature: not compiled here, so looked up in the cache as a fresh process does.
theirs = kernel.total(np.arange(1, 4, dtype=dtypes[other]))
print(json.dumps({"mine": repr(mine), "theirs": repr(theirs),
                  "hits": len(kernel.total.stats.cache_hits),
                  "misses": len(kernel.total.stats.cache_misses)}))
'''
def _race(tmp_path: Path, locked: bool) -> tuple[dict, dict, list[str]]:
    """Run writers A and B through the forced interleaving: their records and the cache's
    data-file names."""
    (tmp_path / "kernel.py").write_text(KERNEL)
    (tmp_path / "worker.py").write_text(WORKER)
    events = tmp_path / "events"
    events.mkdir()
    env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path / "cache")}
    env.pop("NUMBA_DISABLE_JIT", None)
    writers = [subprocess.Popen([sys.executable, str(tmp_path / "worker.py"), role,
                                 "1" if locked else "0", str(events), str(tmp_path),
                                 str(MODULE)], env=env, stdout=subprocess.PIPE,
                                stderr=subprocess.PIPE, text=True)
               for role in ("A", "B")]
    records = []
    try:
        for w in writers:
            out, err = w.communicate(timeout=60)
            assert w.returncode == 0, err
            records.append(json.loads(out))
    finally:  # a writer left waiting for the other's event is not left behind
        for w in writers:
            if w.poll() is None:
                w.kill()
                w.communicate()
    files = sorted(p.name for p in (tmp_path / "cache").rglob("*.nbc"))
    return *records, files


def test_locked_cache_keeps_both_signatures_of_concurrent_writers(tmp_path):
    a, b, files = _race(tmp_path, locked=True)
    assert len(files) == 2  # B saw A's entry and took data file 2
    # Each process loads the other's signature from the cache and gets the right sum.
    assert a == {"mine": "6.0", "theirs": "6", "hits": 1, "misses": 1}
    assert b == {"mine": "6", "theirs": "6.0", "hits": 1, "misses": 1}


@pytest.mark.slow  # the forced race without the lock (fast counterpart: the test above)
def test_unlocked_cache_pairs_a_signature_with_the_other_process_code(tmp_path):
    """The interleaving above does reproduce numba's race: without the lock, B's int64
    signature is indexed to A's float64 code, which reads the int64 bits as float64,
    and A's float64 entry is lost (B compiles it again)."""
    a, b, _ = _race(tmp_path, locked=False)
    assert a["hits"] == 1 and a["theirs"] != "6"
    assert b == {"mine": "6", "theirs": "6.0", "hits": 0, "misses": 2}


def test_install_is_idempotent_and_wraps_save_and_load():
    from numba.core.caching import IndexDataCacheFile
    assert numba_cache.install_cache_lock()
    save = IndexDataCacheFile.save
    assert numba_cache.install_cache_lock()
    assert IndexDataCacheFile.save is save
    assert getattr(IndexDataCacheFile.load, numba_cache._MARK)
    assert not hasattr(save.__wrapped__, numba_cache._MARK)


def test_numba_left_alone_when_its_caching_lacks_a_step(monkeypatch):
    from numba.core import caching

    class Reorganised:  # a numba whose IndexDataCacheFile no longer has _save_index
        def save(self, key, data): ...
        def load(self, key): ...
        def _load_index(self): ...
        def _save_data(self, name, data): ...
    monkeypatch.setattr(caching, "IndexDataCacheFile", Reorganised)
    assert not numba_cache.install_cache_lock()
    assert not hasattr(Reorganised.save, numba_cache._MARK)


def test_unlockable_cache_directory_falls_back_to_numba_behaviour(tmp_path):
    ran = []
    with numba_cache._index_lock(str(tmp_path / "missing-dir" / "f.nbi"), fcntl.LOCK_EX):
        ran.append(True)
    assert ran == [True]


def test_a_stalled_holder_is_passed_by_after_the_wait(tmp_path, monkeypatch):
    """A lock held past `LOCK_WAIT_S` (a stopped process, a hung file system) does not stall
    the step: it runs unlocked, as numba's own does."""
    monkeypatch.setattr(numba_cache, "LOCK_WAIT_S", 0.05)
    index = str(tmp_path / "f.nbi")
    ran = []
    with open(index + ".lock", "a") as holder:  # another open file: flock treats it as another
        fcntl.flock(holder, fcntl.LOCK_EX)     # process's lock
        with open(index + ".lock") as other:
            assert not numba_cache._flock(other, fcntl.LOCK_SH)
        with numba_cache._index_lock(index, fcntl.LOCK_EX):
            ran.append(True)
    assert ran == [True]
    with open(index + ".lock") as f:  # released: taken at once
        assert numba_cache._flock(f, fcntl.LOCK_EX)


def test_a_read_only_lock_file_still_locks(tmp_path, monkeypatch):
    """A lock file this process may not write (another user's) is opened read-only: flock
    needs no write access."""
    import builtins
    path = tmp_path / "f.nbi.lock"
    path.touch()

    def no_write(file, mode="r", *args, **kwargs):
        if mode != "r":
            raise PermissionError(13, "Permission denied", str(file))
        return builtins.open(file, mode, *args, **kwargs)
    monkeypatch.setattr(numba_cache, "open", no_write, raising=False)
    with numba_cache._open_lock_file(str(path)) as f:
        assert f.mode == "r" and numba_cache._flock(f, fcntl.LOCK_EX)
    monkeypatch.setattr(numba_cache, "open", lambda *a, **k: no_write(a[0], "a"),
                        raising=False)
    assert numba_cache._open_lock_file(str(path)) is None


def test_importing_the_packages_patches_nothing():
    """The lock is an explicit call: importing the pipeline (and the harness's CLI, which
    installs it only when a command runs) leaves numba's cache class as numba made it."""
    code = ("import pipeline, harness.cli\n"
            "from numba.core.caching import IndexDataCacheFile as C\n"
            "import core.numba_cache as m\n"
            "print(hasattr(C.save, m._MARK), hasattr(C.load, m._MARK))\n")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True, cwd=MODULE.parents[1]).stdout.split()
    assert out == ["False", "False"]
