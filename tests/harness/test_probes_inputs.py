"""Probe set: Sweep files and keys, shifter command and calibration, chip and board
configs, schemes, scatterers and frames.

Each probe is one bad input (`tests.harness.probes`); it must get a clear answer: exit 2 with
one stderr line (or a ValueError) naming the field or file, the value and the limit, or, for
a gate whose report cannot be written, its verdict as the exit code and a warning.
"""
from __future__ import annotations

import pytest

from tests.harness.probes import classify, probes_of


@pytest.mark.parametrize("probe", probes_of("sweeps"), ids=lambda p: p.name)
def test_sweeps_probe_is_clear(probe, tmp_path):
    cls, detail = classify(probe, tmp_path, time_limit_s=120.0)
    assert cls == "clear", detail


@pytest.mark.parametrize("probe", probes_of("shifter"), ids=lambda p: p.name)
def test_shifter_probe_is_clear(probe, tmp_path):
    cls, detail = classify(probe, tmp_path, time_limit_s=120.0)
    assert cls == "clear", detail


@pytest.mark.parametrize("probe", probes_of("chips_boards"), ids=lambda p: p.name)
def test_chips_boards_probe_is_clear(probe, tmp_path):
    cls, detail = classify(probe, tmp_path, time_limit_s=120.0)
    assert cls == "clear", detail


@pytest.mark.parametrize("probe", probes_of("schemes"), ids=lambda p: p.name)
def test_schemes_probe_is_clear(probe, tmp_path):
    cls, detail = classify(probe, tmp_path, time_limit_s=120.0)
    assert cls == "clear", detail
