"""The report's extra sections, in a registry a plugin can add to.

A section is a `ReportSection`: a name, a title and a `render` function of the results
(`ReportInputs`) that returns HTML, or "" when the results hold nothing for it (the shifter
section renders only for a shifter sweep). `harness.report.page.build_report` draws the
headline, the verdicts and the per-case sections, then every registered section in
registration order, then the full summary table.

Examples
--------
>>> from harness.report.sections import REPORT_SECTIONS, ReportSection, register_report_section
>>> list(REPORT_SECTIONS)
['interference', 'shifter', 'mitigation']
>>> def frames_section(inputs):
...     return f"<h2>Frames</h2><p>{inputs.summary['n_frames'].sum()} frames</p>"
>>> sec = ReportSection("frames", "Frames per run", frames_section)
>>> register_report_section(sec) is sec
True
>>> REPORT_SECTIONS.unregister("frames").name
'frames'
"""
from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import pandas as pd

from core.checks import require
from core.errors import BadInput
from core.registry import Registry
from harness.report import interference, mitigation, shifter

__all__ = ["ReportInputs", "ReportSection", "REPORT_SECTIONS", "register_report_section"]


@dataclass(frozen=True, slots=True)
class ReportInputs:
    """What a section may read: the results folder and its tables as the report read them
    (empty frames when a table is missing)."""

    results: Path
    summary: pd.DataFrame
    actors: pd.DataFrame
    detections: pd.DataFrame


@dataclass(frozen=True, slots=True)
class ReportSection:
    """One extra section of the report.

    Parameters
    ----------
    name : str
        Registry key (a Python identifier).
    title : str
        What it shows, for ``radar-harness plugins`` and the README.
    render : callable
        ``render(inputs: ReportInputs) -> str``: the section's HTML, "" to leave it out.
    """

    name: str
    title: str
    render: Callable[[ReportInputs], str]

    def __post_init__(self) -> None:
        require(self, ("name", "title"), "str")
        if not callable(self.render):
            raise BadInput(f"report section {self.name!r}: render={self.render!r} is not "
                           "callable")


#: Report sections by name, drawn in this order.
REPORT_SECTIONS: Registry[ReportSection] = Registry("report section", field="section",
                                                    kind=ReportSection, identifier=True)


def register_report_section(section: ReportSection, *, replace: bool = False) -> ReportSection:
    """Add a section to every report (`REPORT_SECTIONS`); returns it."""
    return REPORT_SECTIONS.register(section, replace=replace)  # the name after the type check


def _interference(inputs: ReportInputs) -> str:
    return interference.html_section(inputs.summary, inputs.actors)


def _shifter(inputs: ReportInputs) -> str:
    return shifter.html_section(inputs.results)


def _mitigation(inputs: ReportInputs) -> str:
    return mitigation.html_section(inputs.results)


register_report_section(ReportSection(
    "interference", "noise-floor rise, INR and Pd versus range of the interference cases",
    _interference))
register_report_section(ReportSection(
    "shifter", "phase-shifter sweep: spurs and ghosts against the shifter error", _shifter))
register_report_section(ReportSection(
    "mitigation", "interference mitigation methods compared", _mitigation))
