"""The catalogue's runs shared by the scenario tests of one test process."""
from __future__ import annotations

import dataclasses

import pytest

from scenarios import run_scenario


@pytest.fixture(scope="session")
def catalogue_run():
    """catalogue_run(name) -> `run_scenario(name, seed=0)` at the case's own duration, run once
    per test process for all its users (the full-duration, round-trip and truth tests each
    ran every case again). Each call returns fresh copies of the truth and ego tables, so a
    user that changed them would not change the others'."""
    runs = {}

    def _run(name: str):
        if name not in runs:
            runs[name] = run_scenario(name, seed=0)
        run = runs[name]
        return dataclasses.replace(run, truth=run.truth.copy(), ego=run.ego.copy())
    return _run
