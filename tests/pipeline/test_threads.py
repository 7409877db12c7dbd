"""Passes split into parts on threads (`pipeline.threads`) give the bits of the whole pass."""
import threading

import numpy as np
import pandas as pd
import pytest

import pipeline
import pipeline.threads as threads
import radarsim
from pipeline.chirp_level.ege import HWA_OUTPUT_SCALE, ege_compress


@pytest.mark.parametrize("n, parts, multiple", [(48, 2, 1), (48, 2, 8), (768, 3, 1), (7, 2, 4),
                                                (3, 2, 4), (1, 2, 1), (0, 2, 1), (10, 1, 1)])
def test_spans_cover_the_axis_in_order_with_boundaries_on_the_multiple(n, parts, multiple):
    s = threads.spans(n, parts, multiple)
    assert len(s) <= max(parts, 1)
    assert [lo for lo, _ in s] == [0] + [hi for _, hi in s[:-1]]
    assert s[-1][1] == n
    assert all(hi > lo for lo, hi in s) or n == 0
    assert all(lo % multiple == 0 for lo, _ in s)


def test_run_parts_returns_in_order_and_uses_another_thread():
    started = threading.Event()

    def helper_part():
        started.set()
        return 1, threading.current_thread().name

    def caller_part():
        assert started.wait(5)  # the helper has taken its part
        return 0, threading.current_thread().name

    names = threads.run_parts([caller_part, helper_part])
    assert [i for i, _ in names] == [0, 1]
    assert names[0][1] == threading.current_thread().name
    assert names[1][1] != names[0][1]


def test_a_part_the_busy_helper_has_not_started_is_run_by_the_caller():
    release = threading.Event()
    blocker = threads._pool().submit(release.wait, 10)  # the helper is busy elsewhere
    try:
        names = threads.run_parts([lambda: threading.current_thread().name,
                                   lambda: threading.current_thread().name])
    finally:
        release.set()
        blocker.result()
    assert names == [threading.current_thread().name] * 2


def test_run_parts_waits_for_a_started_part_before_raising():
    started, done = threading.Event(), threading.Event()

    def slow():
        started.set()
        done.wait(0.2)
        done.set()
        return 1

    def fails():
        assert started.wait(5)
        raise RuntimeError("part failed")

    with pytest.raises(RuntimeError, match="part failed"):
        threads.run_parts([fails, slow])
    assert done.is_set()


def _parts_in_child(_):
    return threads.run_parts([lambda: 1, lambda: 2])


@pytest.mark.skipif(not hasattr(__import__("os"), "fork"), reason="needs fork")
def test_a_forked_worker_runs_parts_after_the_parent_made_its_helper_thread():
    """A sweep's ProcessPoolExecutor forks workers from a process that may have run a chain:
    the child must not wait on the parent's helper thread, which it does not have."""
    import multiprocessing as mp
    threads.run_parts([lambda: 0, lambda: 0])  # the parent's helper thread exists
    with mp.get_context("fork").Pool(1) as pool:
        assert pool.map_async(_parts_in_child, [0]).get(timeout=60) == [[1, 2]]


@pytest.fixture
def one_part(monkeypatch):
    def run(fn):
        monkeypatch.setattr(threads, "N_PARTS", 1)
        try:
            return fn()
        finally:
            monkeypatch.undo()
    return run


@pytest.mark.parametrize("scheme", sorted(radarsim.MIMO_SCHEMES))
def test_every_chain_gives_the_same_cloud_with_one_and_two_parts(scheme, one_part,
                                                                  monkeypatch):
    monkeypatch.setattr(threads, "N_PARTS", 2)  # two parts even on a one-core machine
    cfg = radarsim.presets.r79(scheme)
    g = np.random.default_rng(3)
    k = 40
    sc = radarsim.Scatterers.from_spherical(g.uniform(5, 150, k), g.uniform(-60, 60, k),
                                            g.uniform(-3, 3, k), g.uniform(-30, 30, k),
                                            g.uniform(1, 10, k))
    adc = radarsim.simulate_frame(cfg, sc, np.random.default_rng(4))
    assert threads.n_parts() == 2
    two = pipeline.process_frame(cfg, adc)
    one = one_part(lambda: pipeline.process_frame(cfg, adc))
    assert len(two) > 10
    pd.testing.assert_frame_equal(one, two, check_exact=True)


def test_ege_parts_give_the_same_cube_and_scale_factors(one_part):
    g = np.random.default_rng(5)
    lsb = 1 / HWA_OUTPUT_SCALE  # noise of 8 LSB, one bin in ten 50 dB above it
    rf = ((g.standard_normal((64, 4, 64)) + 1j * g.standard_normal((64, 4, 64))) * 8 * lsb
          * np.where(g.random((64, 1, 64)) < 0.1, 300, 1)).astype(np.complex64)
    a, sa = ege_compress(rf.copy())
    b, sb = one_part(lambda: ege_compress(rf.copy()))
    assert (sa > 0).any()
    assert a.tobytes() == b.tobytes() and sa.tobytes() == sb.tobytes()


def test_inline_splits_nothing_on_its_own_thread_only():
    """`inline` is per thread (a cell's frame threads) and restores what was there before."""
    import threading
    seen = {}
    with threads.inline():
        assert threads.n_parts() == 1 and threads.spans(48) == [(0, 48)]
        with threads.inline():
            assert threads.n_parts() == 1
        assert threads.n_parts() == 1
        other = threading.Thread(target=lambda: seen.setdefault("other", threads.n_parts()))
        other.start()
        other.join()
    assert seen["other"] == threads.N_PARTS
    assert threads.n_parts() == threads.N_PARTS


def test_run_parts_inside_inline_runs_every_call_on_the_calling_thread():
    """A pass split by its caller into more calls than `n_parts` (two independent steps, say)
    still runs on the calling thread inside `inline`: a sweep cell's frame threads keep the
    cores busy and must not queue work on the shared helper thread."""
    import time

    def first():  # long enough for a helper thread to start the others, if it gets them
        time.sleep(0.05)
        return threading.get_ident()
    with threads.inline():
        where = threads.run_parts([first, threading.get_ident, threading.get_ident])
    assert where == [threading.get_ident()] * 3


def test_fft_workers_are_one_inside_inline_and_every_core_outside(monkeypatch):
    """A chain's FFTs use one thread where its passes are not split (`inline`, a sweep cell's
    frame threads): the transform's own threads would only queue for a busy core."""
    monkeypatch.setattr(threads, "N_PARTS", 2)
    assert threads.fft_workers() == -1
    with threads.inline():
        assert threads.fft_workers() == 1
    assert threads.fft_workers() == -1
