"""The shipped catalogue: one TOML case file per case in ``scenarios/cases/``.

`SCENARIOS` is the registry users type case names from (``radar-harness run NAME``, sweep
files). A new case is one TOML file in ``scenarios/cases/`` (format: `scenarios.files`); the
catalogue and a user's own case files are read by the same loader.
"""
from __future__ import annotations

from pathlib import Path

from core.registry import Registry

from .catalog import Case
from .files import is_case_path, load_case_directory, load_case_file

__all__ = ["CASES_DIR", "SCENARIOS", "get_case"]

#: Folder of the shipped case files.
CASES_DIR = Path(__file__).with_name("cases")

#: The catalogue, keyed by case name (file-name order).
SCENARIOS: Registry[Case] = Registry("scenario", kind=Case,
                                     missing="unknown scenario {name}; known: {known}")
SCENARIOS.register_all(load_case_directory(CASES_DIR).values())


def get_case(name_or_case) -> Case:
    """The `Case` itself, the catalogue entry of that name, or the case of a file (a path
    ending in .toml or .xosc, or holding a folder: `scenarios.files.load_case_file`).

    Raises
    ------
    ValueError
        Naming the unknown case and the known names.

    Examples
    --------
    >>> from scenarios import get_case
    >>> get_case("r79_motorcycle_rear").name
    'r79_motorcycle_rear'
    >>> get_case("nope")
    Traceback (most recent call last):
    ...
    core.errors.BadInput: unknown scenario 'nope'; known: [...]
    """
    if isinstance(name_or_case, Case):
        return name_or_case
    if isinstance(name_or_case, (str, Path)) and is_case_path(str(name_or_case)):
        return load_case_file(name_or_case)
    return SCENARIOS.lookup(name_or_case)
