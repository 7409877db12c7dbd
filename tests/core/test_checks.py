"""The shared field checks and TOML file policy (core.checks): one message shape per rule."""
from __future__ import annotations

import subprocess
import sys
from dataclasses import dataclass

import numpy as np
import pytest

from core.checks import build_from_table, check_keys, one_of, read_toml, require


@dataclass(frozen=True)
class Thing:
    gain_db: float
    n_cells: int = 4
    label: str = "x"
    enabled: bool = True
    limit_m: float | None = None


@pytest.mark.parametrize("value, kwargs, match", [
    (0.0, dict(gt=0), r"v=0.0 must be a finite positive number$"),
    (float("nan"), dict(ge=0), r"v=nan must be finite and >= 0$"),
    (-1.0, dict(ge=0), r"v=-1.0 must be >= 0$"),
    (2.0, dict(ge=0, lt=1), r"v=2.0 must be in \[0, 1\)$"),
    (True, {}, r"v=True must be finite$"),
    ("3", {}, r"v='3' must be finite"),
    (6.0, dict(gt=0, le=5, unit="deg"), r"v=6.0 must be in \(0, 5\] deg"),
    (2.5, dict(kind="integer", ge=1), r"v=2.5 must be an integer >= 1"),
    (0, dict(kind="integer", ge=1, le=4), r"v=0 must be an integer in 1\.\.4$"),
    (1, dict(kind="bool"), r"v=1 must be true or false"),
    (None, dict(gt=0), r"v=None must be a finite positive number"),
    (0, dict(kind="integer", ge=1), r"v=0 must be an integer >= 1$"),
])
def test_require_names_field_value_and_limit(value, kwargs, match):
    holder = type("H", (), {"v": value})()
    kind = kwargs.pop("kind", "number")
    with pytest.raises(ValueError, match=match):
        require(holder, "v", kind, **kwargs)


def test_require_accepts_numpy_scalars_and_optional_none():
    holder = type("H", (), {"a": np.float32(1.5), "b": np.int64(3), "c": None})()
    require(holder, "a", gt=0)
    require(holder, "b", "integer", ge=1)
    require(holder, "c", gt=0, none_ok=True)


def test_one_of_lists_the_known_keys():
    with pytest.raises(ValueError, match=r"cfar mode='median' is not one of \['ca', 'os'\]"):
        one_of("mode", "median", {"os": 1, "ca": 2}, what="cfar ")


@pytest.mark.parametrize("table, match", [
    ({"gain_db": 1.0, "colour": "red"}, r"thing\.colour: unknown key; known: \["),
    ({"gain_dbm": 1.0}, r"thing\.gain_dbm: unknown key"),
    ({"gain_db": 1.0, "limit_km": 2.0}, r"thing\.limit_km: wrong unit; give thing\.limit_m"),
    ({"gain_db": "3 dB"}, r"thing\.gain_db: must be a number in db"),
    ({"gain_db": 1.0, "enabled": "yes"}, r"thing\.enabled: must be true or false"),
    ({"gain_db": 1.0, "label": 3}, r"thing\.label: must be a string"),
    ({"n_cells": 3}, r"thing\.gain_db: required key missing"),
    ([1, 2], r"thing: must be a table"),
])
def test_file_policy_messages(table, match):
    with pytest.raises(ValueError, match=match):
        build_from_table(Thing, table, "thing.")


def test_build_from_table_builds():
    assert build_from_table(Thing, {"gain_db": 2, "limit_m": None}) == Thing(gain_db=2)
    assert check_keys({"a": 1}, {"a", "b"}) == {"a": 1}


def test_read_toml_malformed_names_the_file(tmp_path):
    p = tmp_path / "bad.toml"
    p.write_text("x = = 1")
    with pytest.raises(ValueError, match=r"bad\.toml: malformed TOML"):
        read_toml(p)
    with pytest.raises(FileNotFoundError):
        read_toml(tmp_path / "none.toml")


def test_checks_import_pulls_in_no_highway_env():
    """Every package imports core.checks: it must stay free of the traffic simulator."""
    code = "import sys, core.checks; print('highway_env' in sys.modules)"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True).stdout
    assert out.strip() == "False"
