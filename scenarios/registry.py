"""The shipped catalogue: one TOML case file per case in ``scenarios/cases/``.

`SCENARIOS` is the registry users type case names from (``radar-harness run NAME``, sweep
files). A new case is one TOML file in ``scenarios/cases/`` (format: `scenarios.files`); the
catalogue and a user's own case files are read by the same loader.
"""
from __future__ import annotations

from pathlib import Path

from .catalog import Case
from .files import load_case_directory

__all__ = ["CASES_DIR", "SCENARIOS", "get_case"]

#: Folder of the shipped case files.
CASES_DIR = Path(__file__).with_name("cases")

#: The catalogue, keyed by case name (file-name order).
SCENARIOS: dict[str, Case] = load_case_directory(CASES_DIR)


def get_case(name_or_case) -> Case:
    """The `Case` itself, or the catalogue entry of that name.

    Raises
    ------
    ValueError
        Naming the unknown case and the known names.
    """
    if isinstance(name_or_case, Case):
        return name_or_case
    if name_or_case not in SCENARIOS:
        raise ValueError(f"unknown scenario {name_or_case!r}; known: {', '.join(SCENARIOS)}")
    return SCENARIOS[name_or_case]
