"""The Examples sections of the public API run, as scipy's do (doctest).

Every module of `MODULES` has its docstring examples executed here (so ``make test`` and CI run
them), and every entry point of `PUBLIC_API` must carry an ``Examples`` section with at least
one example: a new public function of these comes with one.
"""
from __future__ import annotations

import doctest
import importlib

import pytest

#: Modules whose docstring examples run.
MODULES = (
    "core.registry", "scenarios.registry", "radarsim.frontend", "radarsim.presets",
    "radarsim.mimo", "radarsim.mimo.schemes", "radarsim.chips", "radarsim.boards",
    "radarsim.calibration",
    "pipeline.chain", "pipeline.cfar.modes", "pipeline.mimo.base", "pipeline.tracking.parts",
    "metrics.detection", "radarsim.mimo.fast_slow", "pipeline.mimo.fast_slow",
    "metrics.registry", "metrics.velocity", "metrics.r79", "metrics.interference",
    "pipeline.mimo.echo_law", "pipeline.mimo.ddma_order", "pipeline.mimo.extension",
    "pipeline.cfar.gamma_law", "harness.runtime", "harness.report.sections",
)

#: Public entry points that must show a runnable example: "module:qualified name".
PUBLIC_API = (
    "radarsim.frontend:simulate_frame", "pipeline.chain:process_frame",
    "radarsim.presets:r79", "radarsim.presets:r79_ddma", "radarsim.presets:r79_tdma",
    "radarsim.mimo.schemes:register_scheme", "radarsim.mimo.schemes:scheme_of",
    "radarsim.chips:get_chip", "radarsim.chips:register_chip",
    "radarsim.boards:get_board", "radarsim.boards:register_board",
    "radarsim.calibration:resolve_calibration",
    "radarsim.calibration:shifter_phase_residual_deg",
    "pipeline.mimo.base:register_chain", "pipeline.mimo.base:chain_of",
    "pipeline.cfar:cfar_mode", "scenarios.registry:get_case", "core.registry",
    "metrics.detection:ghost_stats", "metrics.detection:velocity_stats",
    "metrics.r79:critical_distance_m", "metrics.registry:check_criterion",
)

FLAGS = doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE


@pytest.mark.parametrize("name", MODULES)
def test_docstring_examples_run(name):
    module = importlib.import_module(name)
    runner = doctest.DocTestRunner(optionflags=FLAGS)
    tests = doctest.DocTestFinder(exclude_empty=True).find(module, name)
    for test in tests:
        runner.run(test)
    result = runner.summarize(verbose=False)
    assert result.attempted > 0, f"{name} has no docstring example"
    assert result.failed == 0, f"{result.failed} of {result.attempted} examples of {name} failed"


@pytest.mark.parametrize("entry", PUBLIC_API)
def test_public_entry_points_show_an_example(entry):
    mod_name, _, qual = entry.partition(":")
    obj = importlib.import_module(mod_name)
    for part in filter(None, qual.split(".")):
        obj = getattr(obj, part)
    doc = obj.__doc__ or ""
    assert "Examples\n" in doc and ">>> " in doc, f"{entry} has no Examples section"
    assert doctest.DocTestParser().get_examples(doc), f"{entry}: no parsable example"
