"""Shared factory fixtures.

Nothing here imports radarsim or numba at module level: the xdist controller process loads
this file too but runs no test, and importing them there (~1 s CPU, pandas and scipy included)
only delayed the start of the workers. The fixtures import radarsim when they are used.
"""
from __future__ import annotations

import os

import numpy as np
import pytest

from core.numba_cache import install_cache_lock
from tests import numba_warm


def _runs_tests(config) -> bool:
    """False in the xdist controller (it hands tests to workers), True in a worker or in a
    run without xdist."""
    return hasattr(config, "workerinput") or not getattr(config.option, "numprocesses", None)


def pytest_configure(config):
    # The xdist workers and the CLI subprocesses of the tests compile kernels beside each
    # other: numba's cache index under its file lock before any kernel compiles (imports
    # numba, so not in the controller).
    if _runs_tests(config):
        install_cache_lock()


@pytest.fixture
def make_config():
    """make_config(mimo="ddma", **overrides) -> RadarConfig based on the R79 preset."""
    import radarsim

    def _make(mimo: str = "ddma", **overrides) -> radarsim.RadarConfig:
        return radarsim.presets.r79(mimo, **overrides)
    return _make


@pytest.fixture
def make_scene():
    """make_scene(targets) -> Scatterers from (range_m, azimuth_deg, elevation_deg,
    radial_velocity_mps, rcs_m2) tuples (velocity purely radial)."""
    import radarsim

    def _make(targets) -> radarsim.Scatterers:
        t = np.atleast_2d(np.asarray(targets, dtype=float))
        if t.size == 0:
            return radarsim.Scatterers.empty()
        return radarsim.Scatterers.from_spherical(*t[:, :5].T, actor_id=np.arange(len(t)))
    return _make


@pytest.fixture
def rng():
    return np.random.default_rng(12345)


@pytest.fixture
def make_x18():
    """make_x18(adc_mode) -> an xWR18xx TDMA profile at 10 Msps, 128 samples, 30 MHz/us (IF
    corner 5.5 MHz real, 11 MHz I/Q), isotropic elements: a second chip family and the
    complex ADC modes next to the R79 preset."""
    import radarsim

    def _make(adc_mode: str = "complex1x") -> radarsim.RadarConfig:
        return radarsim.RadarConfig.from_fields(
            chip="AWR1843", adc_mode=adc_mode, mimo="tdma", n_tx=3, n_chirps=96, n_samples=128,
            adc_rate_sps=10e6, slope_hz_per_s=30e12, ramp_end_time_s=18.81e-6, idle_time_s=5e-6,
            antenna_pattern="isotropic")
    return _make


# Numba kernels compiled once per run, not once per xdist worker (tests/numba_warm.py). Only in
# xdist workers: a run of a few tests compiles only what it meets.
_WARM = numba_warm.Warmup()
_WARM_LATER: list[str] = []
_WARM_TABLE: dict = {}
_WARM_REPORTS: list[dict] = []


def pytest_sessionstart(session):
    worker = os.environ.get("PYTEST_XDIST_WORKER", "")
    if worker.startswith("gw") and os.environ.get(numba_warm.SWITCH, "1") != "0":
        _WARM_TABLE.update(numba_warm.read_signatures())
        # every module no other worker holds now; the held ones after collecting
        _WARM_LATER.extend(numba_warm.warm(numba_warm.claim_order(_WARM_TABLE), _WARM_TABLE,
                                           _WARM, wait=False))


@pytest.hookimpl(hookwrapper=True)
def pytest_runtestloop(session):
    # After collection: the modules no worker has claimed yet (each claims a free one). Only
    # where there are some: warm() imports numba, which the xdist controller does not need.
    if _WARM_LATER:
        numba_warm.warm(_WARM_LATER, _WARM_TABLE, _WARM)
        _WARM_LATER.clear()
    yield


def pytest_sessionfinish(session):
    if _WARM_TABLE and hasattr(session.config, "workeroutput"):
        session.config.workeroutput["numba_warm"] = {
            "worker": os.environ.get("PYTEST_XDIST_WORKER", ""), "compiled": _WARM.compiled,
            "stale": _WARM.stale, "cpu_s": _WARM.cpu_s, "wall_s": _WARM.wall_s,
            "missing": numba_warm.missing(_WARM_TABLE)}


@pytest.hookimpl(optionalhook=True)
def pytest_testnodedown(node, error):
    report = getattr(node, "workeroutput", {}).get("numba_warm")
    if report:
        _WARM_REPORTS.append(report)


def pytest_terminal_summary(terminalreporter):
    for r in sorted(_WARM_REPORTS, key=lambda r: r["worker"]):
        terminalreporter.write_line(
            f"numba warm-up {r['worker']}: {r['compiled']} signatures in {r['wall_s']:.1f} s "
            f"({r['cpu_s']:.1f} s CPU)")
        for line in r["stale"]:
            terminalreporter.write_line(f"  stale (kernel changed?): {line}")
        for line in r["missing"]:
            terminalreporter.write_line(f"  compiled outside the list: {line}")
    if any(r["stale"] or r["missing"] for r in _WARM_REPORTS):
        terminalreporter.write_line("  (after a suite run with TESTS_NUMBA_WARM=0 in a clean "
                                    "checkout, python -m tests.numba_warm rewrites "
                                    "tests/numba_signatures.txt)")
