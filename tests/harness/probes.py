"""The bad-input probe set: what a new user, a full disk or a supervisor does to every surface of
the harness (`tests.harness.probe_kit` has the `Probe` record, `classify` and the helpers;
`probes_inputs` and `probes_outputs` the probes, `probes_surfaces` those of the later surfaces).

`tests/harness/test_probes_*.py` assert that every probe of this project's areas is clear;
``python -m tests.harness.probe_survey`` counts the classes.
"""
from __future__ import annotations

from tests.harness.probe_kit import (
    CLASSES,
    GATES,
    Probe,
    classify,
    fake_results,
    special_file_probes,
)
from tests.harness.probes_inputs import (
    adc_probes,
    config_probes,
    interference_probes,
    shifter_probes,
    sweep_probes,
)
from tests.harness.probes_outputs import (
    consistency_probes,
    profile_probes,
    scheme_probes,
    signal_probes,
    write_probes,
)

__all__ = ["CLASSES", "GATES", "Probe", "classify", "fake_results", "all_probes", "probes_of"]


def all_probes() -> list[Probe]:
    return (special_file_probes() + sweep_probes() + shifter_probes() + config_probes()
            + adc_probes() + interference_probes() + write_probes()
            + consistency_probes() + scheme_probes() + profile_probes()
            + signal_probes())


def probes_of(surface: str, owner: str = "reliability") -> list[Probe]:
    return [p for p in all_probes() if p.surface == surface and p.owner == owner]
