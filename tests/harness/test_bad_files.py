"""Bad sweep, case and gate files: exit code 2 and one line naming the file, key and value.

Sweep files were validated only inside each cell (a radar value over a chip limit or
an unknown tracker field failed every cell at run time with exit 1); `base = 5` or a directory
as the sweep file printed a traceback; gates accepted rules that cannot mean anything (min >
max, boolean bounds, a non-numeric metric that then passed with allow_missing).
"""
from __future__ import annotations

import re

import pandas as pd
import pytest

from harness.cli import main
from harness.gates import check as g

HEAD = 'name = "x"\nscenarios = ["head_on_aliasing"]\n'

SWEEP_CASES = {
    "malformed": ("scenarios = [\n", r"malformed TOML"),
    "base_not_table": ('scenarios = ["head_on_aliasing"]\nbase = 5\n',
                       r"base = 5 must be a table"),
    "vary_not_table": ('scenarios = ["head_on_aliasing"]\nvary = [1]\n', r"vary = \[1\] must be"),
    "variants_not_array": (HEAD + "variants = 3\n", r"variants = 3 must be an array"),
    "variant_section_not_table": (HEAD + '[[variants]]\nname = "a"\nradar = 5\n',
                                  r"\[\[variants\]\] 'a': radar = 5 must be a table"),
    "unknown_key": (HEAD + "bogus = 1\n", r"bogus: unknown key"),
    "radar_over_chip_limit": (HEAD + '[vary]\n"radar.adc_rate_sps" = [50e6]\n',
                              r"variant 'adc_rate_sps=50000000\.0': radar\.adc_rate_sps = "
                              r"50000000\.0: adc_rate_sps=5e\+07 exceeds the AWR2944 limit"),
    "radar_string_number": (HEAD + '[vary]\n"radar.tx_power_dbm" = ["abc"]\n',
                            r"radar\.tx_power_dbm = 'abc': tx_power_dbm='abc' must be a number"),
    "radar_absurd_power": (HEAD + '[base.radar]\ntx_power_dbm = 5000.0\n',
                           r"radar\.tx_power_dbm = 5000\.0: tx_power_dbm=5000\.0 is outside"),
    "unknown_radar_field": (HEAD + '[vary]\n"radar.not_a_field" = [1]\n',
                            r"unknown radar field\(s\) \['not_a_field'\]"),
    "unknown_tracker_field": (HEAD + '[vary]\n"tracker.bogus_field" = [1]\n',
                              r"tracker\.bogus_field = 1: .*bogus_field"),
    "bad_tracker_value": (HEAD + '[vary]\n"tracker.motion_model" = ["zz"]\n',
                          r"tracker\.motion_model = 'zz': motion_model='zz' is not one of"),
    "unknown_processing_field": (HEAD + '[vary]\n"processing.bogus" = [1]\n',
                                 r"processing \{'bogus': 1\}: unknown ProcessingConfig"),
    "cfar_wider_than_doppler": (HEAD + '[vary]\n"processing.cfar_window_cells" = [100]\n',
                                r"processing\.cfar_window_cells = 100: cfar window_cells=100 "
                                r".*Doppler axis"),
    "name_escapes_results": ('name = "../../x"\nscenarios = ["head_on_aliasing"]\n',
                             r"name='\.\./\.\./x' must be 1-100 letters"),
    "name_absolute": ('name = "/tmp/abs"\nscenarios = ["head_on_aliasing"]\n',
                      r"name='/tmp/abs' must be"),
    "seed_bool": (HEAD + "seeds = [true]\n", r"seeds=\[True\] must be a non-empty list"),
    "seed_negative": (HEAD + "seeds = [-1]\n", r"seeds=\[-1\]"),
    "duration_1e9": (HEAD + "duration_s = 1e9\n", r"duration_s=1000000000\.0 must be a number "
                                                  r"in \(0, 120\] s"),
    "duration_inf": (HEAD + "duration_s = inf\n", r"duration_s=inf must be"),
    "duration_string": (HEAD + 'duration_s = "long"\n', r"duration_s='long' must be"),
    "frame_stride_zero": (HEAD + "frame_stride = 0\n", r"frame_stride=0 must be an integer"),
    "unknown_scenario": ('scenarios = ["nope"]\n', r"unknown case\(s\) \['nope'\]"),
    "too_many_cells": (HEAD + "seeds = [" + ", ".join(map(str, range(10001))) + "]\n",
                       r"10001 cells .* more than the limit 10000"),
}


@pytest.mark.parametrize("text, match", list(SWEEP_CASES.values()), ids=list(SWEEP_CASES))
def test_bad_sweep_file_exits_2_before_any_worker(tmp_path, capsys, text, match):
    f = tmp_path / "s.toml"
    f.write_text(text)
    assert main(["sweep", str(f), "--out", str(tmp_path / "r"), "--workers", "1"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("radar-harness sweep: error: ")
    assert re.search(match, err[0]), err[0]
    assert not (tmp_path / "r").exists()  # nothing started


@pytest.mark.parametrize("kind", ["directory", "binary", "missing"])
def test_sweep_file_that_is_not_a_toml_file(tmp_path, capsys, kind):
    f = tmp_path / "s.toml"
    if kind == "directory":
        f.mkdir()
    elif kind == "binary":
        f.write_bytes(b"\xff\xfe\x00\x01")
    assert main(["sweep", str(f)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "s.toml" in err[0]


# ------------------------------------------------------------------------------ case files
CASE_CASES = {
    "malformed": ("name = \n", r"malformed TOML"),
    "unknown_key": ('name = "c"\nbogus = 1\n', r"bogus"),
    "wrong_unit": ('name = "c"\nduration_min = 1\n', r"duration_min"),
}


@pytest.mark.parametrize("text, match", list(CASE_CASES.values()), ids=list(CASE_CASES))
def test_bad_case_file_exits_2(tmp_path, capsys, text, match):
    f = tmp_path / "c.toml"
    f.write_text(text)
    assert main(["show", str(f), "--out", str(tmp_path)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and re.search(match, err[0]), err


# ------------------------------------------------------------------------------ gate files
GATE = '[[gate]]\nname = "g"\nmetric = "ghost_rate"\n'
GATE_CASES = {
    "min_above_max": (GATE + "min = 2.0\nmax = 1.0\n", r"gate 'g' has min=2\.0 > max=1\.0"),
    "boolean_bound": (GATE + "max = true\n", r"max: must be a number"),
    "string_bound": (GATE + 'max = "low"\n', r"max: must be a number"),
    "allow_missing_string": (GATE + 'max = 1.0\nallow_missing = "yes"\n',
                             r"allow_missing: must be true or false"),
    "no_bound": (GATE, r"needs min and/or max"),
    "unknown_key": (GATE + "max = 1.0\nbogus = 1\n", r"bogus: unknown key"),
    "bad_aggregate": (GATE + 'max = 1.0\naggregate = "sum"\n', r"aggregate='sum' is not one of"),
    "malformed": ("[[gate]\n", r"malformed TOML"),
    "no_gates": ("", r"no \[\[gate\]\] tables"),
}


@pytest.mark.parametrize("text, match", list(GATE_CASES.values()), ids=list(GATE_CASES))
def test_bad_gate_file_is_bad_input(tmp_path, fake_results, capsys, text, match):
    f = tmp_path / "gates.toml"
    f.write_text(text)
    with pytest.raises(ValueError, match=match):
        g.load_gates(f)
    assert main(["gate", str(fake_results), "--thresholds", str(f), "--markdown",
                 str(tmp_path / "g.md")]) == 2
    assert len(capsys.readouterr().err.strip().splitlines()) == 1


def test_non_numeric_metric_is_bad_input_even_with_allow_missing(tmp_path):
    summary = pd.DataFrame({"scenario": ["a"], "scheme": ["ddma"], "ghost_rate": ["fine"]})
    gate = g.Gate(name="n", metric="ghost_rate", max=1.0, allow_missing=True)
    with pytest.raises(ValueError, match=r"gate 'n': metric 'ghost_rate' is not numeric"):
        g.evaluate_gates(summary, [gate])


def test_gate_on_a_column_that_is_no_metric_is_bad_input():
    with pytest.raises(ValueError, match=r"unknown metric 'note'; known: .*ghost_rate"):
        g.Gate(name="n", metric="note", max=1.0)


def test_gates_directory_is_bad_input(tmp_path, fake_results, capsys):
    assert main(["gate", str(fake_results), "--thresholds", str(tmp_path), "--markdown",
                 str(tmp_path / "g.md")]) == 2
    assert "is a directory" in capsys.readouterr().err


N_KINDS = len(SWEEP_CASES) + 3 + len(CASE_CASES) + len(GATE_CASES) + 2


def test_the_probes_good_baselines_are_accepted(tmp_path):
    """Each probe is a good baseline plus one bad piece: the baselines themselves must pass the
    same validation, or a probe could fail for the baseline's fault, not its own."""
    from harness.sweep.file import load_sweep
    sweep = tmp_path / "sweep.toml"
    sweep.write_text(HEAD)
    spec = load_sweep(sweep)
    assert spec.scenarios == ("head_on_aliasing",)
    gates = tmp_path / "gates.toml"
    gates.write_text(GATE + "max = 1.0\n")
    assert [x.name for x in g.load_gates(gates)] == ["g"]
