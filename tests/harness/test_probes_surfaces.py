"""Probe set, third round: damaged results folders (gate, report), what a report must say is
missing, board calibration lines (process), calibrate on bad captures, mmWave Studio setups, a
lab's chip / board / repair-method records and registration calls, full disks under process
and simulate, OpenSCENARIO files, case keys and export (`tests.harness.probes_surfaces`).

Each probe is one bad input; it must get a clear answer: exit 2 with one stderr line (or a
ValueError) naming the file or field, the value and the limit; for a report of incomplete
results, exit 0 and a warning saying what is missing.
"""
from __future__ import annotations

import pytest

from tests.harness.probes import classify
from tests.harness.probes_surfaces import probes_of

SURFACES = ("results", "board_calibration", "calibrate", "studio_setups", "registrations",
            "openscenario")


@pytest.mark.parametrize("probe", [p for s in SURFACES for p in probes_of(s)],
                         ids=lambda p: p.id)
def test_surface_probe_is_clear(probe, tmp_path):
    cls, detail = classify(probe, tmp_path, time_limit_s=120.0)
    assert cls == "clear", detail


# Each draws a whole report (~1 s CPU); the fast sibling asserting the same gaps (one stderr
# warning line and the page text, exit 0) on one report of a copy lacking all of them is
# tests/harness/test_report.py::test_report_says_what_the_results_lack_in_the_page_and_on_stderr.
@pytest.mark.slow
@pytest.mark.parametrize("probe", probes_of("report_gaps"), ids=lambda p: p.id)
def test_report_gap_probe_is_clear(probe, tmp_path):
    cls, detail = classify(probe, tmp_path, time_limit_s=120.0)
    assert cls == "clear", detail


@pytest.mark.parametrize("probe", probes_of("writes"), ids=lambda p: p.id)
def test_full_disk_probe_is_clear(probe, tmp_path):
    cls, detail = classify(probe, tmp_path, time_limit_s=120.0)
    assert cls == "clear", detail


@pytest.mark.slow  # a real pool sweep in a fresh interpreter (~15 s); the forked stand-in
@pytest.mark.parametrize("probe", probes_of("signals"), ids=lambda p: p.id)  # test is fast
def test_hang_up_probe_is_clear(probe, tmp_path):
    cls, detail = classify(probe, tmp_path, time_limit_s=300.0)
    assert cls == "clear", detail
